#!/usr/bin/env bash
# The stress of result.pvd stays within the sampled range (issue 33, item 7): the default
# example (examples/wheel.yaml) and a squeezed ring (tests/paraview/squeezed_ring.yaml), each
# checked by tests/paraview/check_vonmises.py (von Mises >= 0, every coefficient within the
# sampled range, the peak within 2 % of the sampled one). Exits 77 without pvpython or h5py.
set -u
exe="$1"; src="$2"
command -v pvpython > /dev/null || { echo "pvpython not found: skipped"; exit 77; }
pvpython -c "import h5py" 2> /dev/null || { echo "h5py not importable in pvpython: skipped"; exit 77; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
fail=0
for f in "$src/examples/wheel.yaml" "$src/tests/paraview/squeezed_ring.yaml"; do
  n=$(basename "$f" .yaml)
  "$exe" run "$f" --output "$tmp/$n" --quiet || { echo "FAIL: $n did not run"; fail=1; continue; }
  echo "== $n"
  pvpython "$src/tests/paraview/check_vonmises.py" "$tmp/$n" || fail=1
done
exit $fail
