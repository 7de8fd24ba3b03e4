#!/usr/bin/env bash
# The XDMF recipe of docs/paraview-xdmf-notes.md in ParaView's three .xdmf readers and the
# .pvd reader: a hand-made output directory (tests/paraview/sample_results.py, Debian's
# python3-h5py) checked by tests/paraview/check_results.py. Exits 77 (skipped) without
# pvpython or h5py; in CI (CI=true) either missing fails.
set -eu
dir="$1"
# a missing optional tool: skipped (77) on a workstation, a failure in CI (CI set, as CI services do)
missing() { echo "$1 not found: skipped"; case "${CI:-}" in "" | false | 0) exit 77 ;; *) echo "FAIL: CI=$CI, and CI must have $1"; exit 1 ;; esac; }
command -v pvpython > /dev/null || missing pvpython
/usr/bin/python3 -c "import h5py, numpy" 2> /dev/null || missing "python3-h5py (or numpy)"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
/usr/bin/python3 "$dir/sample_results.py" "$tmp"
pvpython "$dir/check_results.py" "$tmp"
