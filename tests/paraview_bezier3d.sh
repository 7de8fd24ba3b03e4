#!/usr/bin/env bash
# The 3-D rational Bezier .vtu through ParaView: test_vtk writes a quarter of a thick cylinder
# shell as its boundary faces (VTK_BEZIER_QUADRILATERAL, 77: output.cells: faces) and as its
# elements (VTK_BEZIER_HEXAHEDRON, 79: output.cells: volume), binary and ascii; pvpython checks
# them with ParaView's reader and VTK's own cell evaluation (tests/paraview/check_bezier3d.py).
# Exits 77 (skipped) without pvpython; in CI (CI=true) a missing pvpython fails.
set -eu
test_vtk="$1"; check="$2"
missing() { echo "$1 not found: skipped"; case "${CI:-}" in "" | false | 0) exit 77 ;; *) echo "FAIL: CI=$CI, and CI must have $1"; exit 1 ;; esac; }
command -v pvpython > /dev/null || missing pvpython
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
IGACONTACT_VTU_OUT="$tmp" "$test_vtk" --gtest_filter=VtkBezier3D.WritesShellFiles > "$tmp/gtest.log" 2>&1 || { cat "$tmp/gtest.log"; exit 1; }
for f in shell_faces.vtu:77 shell_faces_ascii.vtu:77 shell_volume.vtu:79 shell_volume_ascii.vtu:79; do
  file=${f%%:*}; type=${f##*:}
  echo "== $file ($(stat -c %s "$tmp/$file") bytes)"
  pvpython "$check" "$tmp/$file" --type "$type"
done
