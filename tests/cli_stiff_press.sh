#!/usr/bin/env bash
# A stiff penalty pressed in one load step with exact linear solves (the direct solver, which
# `auto` takes below a few thousand dofs in 3-D and with friction up to 2e5): the coarse
# Hertz ball of cli_hertz_sphere with KTS at penalty 1e7 (3,942 dofs, `scripts/hertz_sphere_mesh
# --n-a 4 --fine 1.0 --growth 3 --load-steps 1 --method kts_penalty --penalty 1e7`).
# The first Newton iterate puts the ball 0.0135 into the block, where the penalty pressures are
# a thousand times their converged values; there the consistent contact tangent's geometric
# part (-p G: the foot and the normal moving) made it indefinite, Newton's directions were no
# descent directions, and the residual stalled and grew until solver.newton.max_iterations
# (30) cut the step (Newton [12, 8] after the cut, 7 s). Now a step whose direction fails the
# line search is taken again with that part off (eps N N^T alone) until the residual is below
# 1e-3 of the step's first (NewtonCore::newton). Checked:
#  - one load step converges without a cut;
#  - frictionless penalty contact has no path: the normal force equals the 4-step run's to
#    1e-8 (both stop at 1e-10 of the residual; they agree to 1e-10 in this test's first runs).
# Usage: cli_stiff_press.sh EXE SOURCE_DIR
set -u
exe="$1"; src="$2"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
/usr/bin/python3 "$src/scripts/hertz_sphere_mesh" --n-a 4 --fine 1.0 --growth 3 --load-steps 1 \
  --method kts_penalty --penalty 1e7 -o "$tmp/h.yaml" > /dev/null || { echo "FAIL: hertz_sphere_mesh"; exit 1; }
for n in 1 4; do
  timeout 300 "$exe" run "$tmp/h.yaml" --output "$tmp/s$n" --quiet --set solver.linear.method=direct \
    --set analysis.load_steps=$n 2> "$tmp/err"; rc=$?
  [ "$rc" = 0 ] || { echo "FAIL: $n load step(s): exit $rc: $(cat "$tmp/err")"; exit 1; }
done
/usr/bin/python3 - "$tmp/s1/summary.json" "$tmp/s4/summary.json" <<'EOF' || exit 1
import json, sys
one, four = (json.load(open(f)) for f in sys.argv[1:3])
f1, f4 = one["contact"][0]["normal_force"], four["contact"][0]["normal_force"]
err = abs(f1 - f4) / abs(f4)
print(f"one step: Newton {one['newton_iterations']}, cuts {one['cuts']}; four steps: Newton {four['newton_iterations']}")
print(f"normal force {f1!r} against {f4!r}: {err:.1e} relative")
ok = True
if one["cuts"] != 0:
    print("FAIL: the one-step run was cut"); ok = False
if not err <= 1e-8:
    print("FAIL: the one-step run's normal force differs from the 4-step run's by more than 1e-8"); ok = False
sys.exit(0 if ok else 1)
EOF
echo "a stiff penalty pressed in one step: converged without a cut, to the 4-step answer"
