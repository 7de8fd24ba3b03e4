#!/usr/bin/env bash
# What a user sees when scripts/pv-render draws an output (issue 33, item 7): the default
# example run, then pictures checked by tests/paraview/check_picture.py:
# - Xdmf3ReaderS (the GUI's default) and Xdmf3ReaderT: the bodies are coloured (>= 100
#   non-grey colours, < 1 % grey pixels: neither grey bodies nor control nets drawn over
#   them), and the colour bar's range = the data range the reader gives = the range of syy
#   written in result.h5 (to 1e-12);
# - the exact geometry (.pvd, von Mises): coloured;
# - --nets --contact: the nets are drawn when asked (grey pixels appear);
# - every pvpython exits 0, also four renders at once (they used to share an xvfb-run
#   display and abort with SIGABRT).
# Usage: paraview_render.sh EXE SOURCE_DIR. Exits 77 (skipped) without pvpython or Xvfb.
set -u
exe="$1"; src="$2"
command -v pvpython > /dev/null || { echo "pvpython not found: skipped"; exit 77; }
command -v Xvfb > /dev/null || { echo "Xvfb not found: skipped"; exit 77; }
unset DISPLAY
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
render="$src/scripts/pv-render"; pic="/usr/bin/python3 $src/tests/paraview/check_picture.py"
fail=0
"$exe" run "$src/examples/wheel.yaml" --output "$tmp/w" --quiet || { echo "FAIL: the wheel did not run"; exit 1; }
h5range=$(/usr/bin/python3 -c "
import h5py, numpy as np, sys
with h5py.File(sys.argv[1]) as f:
    v = np.concatenate([f['bodies'][b]['stress'][()][:, 1] for b in f['bodies']])   # syy: column YY of the tensor
print('%.17g %.17g' % (v.min(), v.max()))" "$tmp/w/result.h5")
echo "result.h5: syy in [$h5range]"
pv() {   # name [args]: render, check the exit status
  local name="$1"; shift
  pvpython "$render" "$tmp/w" --out "$tmp/$name.png" "$@" > "$tmp/$name.log" 2>&1
  local rc=$?
  [ $rc = 0 ] || { echo "FAIL: pv-render $* exited $rc"; tail -5 "$tmp/$name.log"; fail=1; return 1; }
}
for r in S T; do
  pv reader$r --reader $r || continue
  $pic "$tmp/reader$r.png" --max-grey 0.01 || { echo "FAIL: Xdmf3Reader$r: bodies not coloured"; fail=1; }
  /usr/bin/python3 - "$tmp/reader$r.log" $h5range <<'PY' || { echo "FAIL: Xdmf3Reader$r: ranges"; fail=1; }
import sys
f = [l.split() for l in open(sys.argv[1]) if l.startswith("range ")][0]
lo, hi, dlo, dhi = map(float, f[2:6])
want = float(sys.argv[2]), float(sys.argv[3])
close = lambda a, b: abs(a - b) <= 1e-12 * max(abs(b), 1.0)
print("colour bar [%.10g, %.10g], reader's data [%.10g, %.10g], result.h5 [%.10g, %.10g]" % (lo, hi, dlo, dhi, *want))
assert close(lo, want[0]) and close(hi, want[1]) and close(dlo, want[0]) and close(dhi, want[1])
PY
done
pv exact --exact --field von_mises --scale 20 --no-edges && { $pic "$tmp/exact.png" --max-grey 0.01 || { echo "FAIL: .pvd not coloured"; fail=1; }; }
pv nets --nets --contact --scale 20 && { $pic "$tmp/nets.png" --min-grey 0.005 || { echo "FAIL: --nets draws no net"; fail=1; }; }
pids=()
for k in 1 2 3 4; do pvpython "$render" "$tmp/w" --out "$tmp/c$k.png" > "$tmp/c$k.log" 2>&1 & pids+=($!); done
for k in 1 2 3 4; do wait ${pids[$((k-1))]}; rc=$?; [ $rc = 0 ] || { echo "FAIL: concurrent render $k exited $rc"; tail -3 "$tmp/c$k.log"; fail=1; }; done
[ $fail = 0 ] && echo "pv-render pictures passed"
exit $fail
