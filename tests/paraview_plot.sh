#!/usr/bin/env bash
# scripts/plot on users' runs (issue 33, items 8 and 11), checked by tests/paraview/check_plot.py:
# the Hertz curve of two cylinders (tests/paraview/two_cylinders.yaml: 1/R = 1/R1 + 1/R2, E*
# from both materials) and the default example's pictures (examples/wheel.yaml: pressure
# smooth against Hertz, axes on the data, viridis, a zoom beside the whole, nothing cut off).
# Usage: paraview_plot.sh EXE SOURCE_DIR. Exits 77 without python3-matplotlib/h5py/yaml/PIL.
set -u
exe="$1"; src="$2"
/usr/bin/python3 -c "import matplotlib, h5py, yaml, PIL" 2> /dev/null || { echo "python3 modules missing: skipped"; exit 77; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
fail=0
"$exe" run "$src/tests/paraview/two_cylinders.yaml" --output "$tmp/cyl" --quiet || { echo "FAIL: two cylinders did not run"; exit 1; }
/usr/bin/python3 "$src/tests/paraview/check_plot.py" hertz "$tmp/cyl" "$src/tests/paraview/two_cylinders.yaml" || fail=1
"$exe" run "$src/examples/wheel.yaml" --output "$tmp/wheel" --quiet || { echo "FAIL: the wheel did not run"; exit 1; }
/usr/bin/python3 "$src/tests/paraview/check_plot.py" default "$tmp/wheel" || fail=1
exit $fail
