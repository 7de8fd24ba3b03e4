#!/usr/bin/env bash
# The rational Bezier .vtu through ParaView: test_vtk writes a refined quarter annulus (and a
# block) as VTK_BEZIER_QUADRILATERAL cells, pvpython checks it with ParaView's reader and
# VTK's own cell evaluation (tests/paraview/check_bezier.py). Exits 77 (skipped) without pvpython;
# in CI (CI=true) a missing pvpython fails.
set -eu
test_vtk="$1"; check="$2"
# a missing optional tool: skipped (77) on a workstation, a failure in CI (CI set, as CI services do)
missing() { echo "$1 not found: skipped"; case "${CI:-}" in "" | false | 0) exit 77 ;; *) echo "FAIL: CI=$CI, and CI must have $1"; exit 1 ;; esac; }
command -v pvpython > /dev/null || missing pvpython
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
IGACONTACT_VTU_OUT="$tmp" "$test_vtk" --gtest_filter=VtkBezier.WritesQuarterAnnulusFiles > "$tmp/gtest.log" 2>&1 || { cat "$tmp/gtest.log"; exit 1; }
for f in annulus.vtu annulus_ascii.vtu annulus_zlib.vtu; do
  echo "== $f ($(stat -c %s "$tmp/$f") bytes)"
  pvpython "$check" "$tmp/$f"
done
