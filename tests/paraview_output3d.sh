#!/usr/bin/env bash
# A 3-D output directory (issue 35) through ParaView before a 3-D run exists: test_vtk's
# Output3D.ControlNetAndProbe writes the files of one state of a cylinder shell as ResultWriter
# does (control net HDF5 + result_control_nets.xdmf, result_contact.xdmf, the faces' .vtu and
# result.pvd, summary.json), tests/paraview/check_results.py opens them with every reader (no
# result.xdmf, hexahedral control nets, Bezier faces with the 3-D arrays, the largest
# displacement). Exits 77 (skipped) without pvpython; in CI (CI=true) a missing pvpython fails.
set -eu
test_vtk="$1"; here="$2"
missing() { echo "$1 not found: skipped"; case "${CI:-}" in "" | false | 0) exit 77 ;; *) echo "FAIL: CI=$CI, and CI must have $1"; exit 1 ;; esac; }
command -v pvpython > /dev/null || missing pvpython
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
IGACONTACT_VTU_OUT="$tmp/out" "$test_vtk" --gtest_filter=Output3D.ControlNetAndProbe > "$tmp/gtest.log" 2>&1 || { cat "$tmp/gtest.log"; exit 1; }
pvpython "$here/check_results.py" "$tmp/out"
