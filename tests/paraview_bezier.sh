#!/usr/bin/env bash
# The rational Bezier .vtu through ParaView: test_vtk writes a refined quarter annulus (and a
# block) as VTK_BEZIER_QUADRILATERAL cells, pvpython checks it with ParaView's reader and
# VTK's own cell evaluation (tests/paraview/check_bezier.py). Exits 77 (skipped) without pvpython.
set -eu
test_vtk="$1"; check="$2"
command -v pvpython > /dev/null || { echo "pvpython not found: skipped"; exit 77; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
IGACONTACT_VTU_OUT="$tmp" "$test_vtk" --gtest_filter=VtkBezier.WritesQuarterAnnulusFiles > "$tmp/gtest.log" 2>&1 || { cat "$tmp/gtest.log"; exit 1; }
for f in annulus.vtu annulus_ascii.vtu; do
  echo "== $f ($(stat -c %s "$tmp/$f") bytes)"
  pvpython "$check" "$tmp/$f"
done
