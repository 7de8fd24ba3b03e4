#!/usr/bin/env bash
# The XDMF recipe of docs/paraview-xdmf-notes.md in ParaView's three .xdmf readers and the
# .pvd reader: a hand-made output directory (tests/paraview/sample_results.py, Debian's
# python3-h5py) checked by tests/paraview/check_results.py. Exits 77 (skipped) without
# pvpython or h5py.
set -eu
dir="$1"
command -v pvpython > /dev/null || { echo "pvpython not found: skipped"; exit 77; }
/usr/bin/python3 -c "import h5py, numpy" 2> /dev/null || { echo "python3-h5py not found: skipped"; exit 77; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
/usr/bin/python3 "$dir/sample_results.py" "$tmp"
pvpython "$dir/check_results.py" "$tmp"
