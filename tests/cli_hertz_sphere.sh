#!/usr/bin/env bash
# The Hertz ball on a block in 3-D as a test (issue 36, item 5; the example
# examples/hertz_sphere.yaml takes 40 s, this coarse mesh of the same problem 2 s):
# `scripts/hertz_sphere_mesh --n-a 4 --fine 1.0 --growth 3 --load-steps 1 --method
# mortar_penalty --penalty 1e5` (quarter model, ball R = 1 on a block, E = 1000, nu = 0.3,
# 3,942 dofs, cells of a / 4 over the contact zone), then scripts/hertz_sphere_check against
# Hertz at the computed load P:
#  - p0 (the largest pressure) and p0 of the least-squares fit of the profile within 2 % of
#    3 P / (2 pi a^2) (the issue's bound);
#  - the fitted contact radius within 5 % of (3 P R / (4 E*))^(1/3): at four cells across a
#    the radius is resolved to a quarter of a cell's width, not to the issue's 3 % (which the
#    example's finer mesh meets: docs/verification.md);
#  - equilibrium: the ball's held top face carries the contact force, z to 1e-8 of it, and
#    the symmetry faces' reactions its x and y (Newton stops at 1e-10 of the residual).
# Usage: cli_hertz_sphere.sh EXE SOURCE_DIR
set -u
exe="$1"; src="$2"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
/usr/bin/python3 "$src/scripts/hertz_sphere_mesh" --n-a 4 --fine 1.0 --growth 3 --load-steps 1 \
  --method mortar_penalty --penalty 1e5 -o "$tmp/h.yaml" > /dev/null || { echo "FAIL: hertz_sphere_mesh"; exit 1; }
timeout 300 "$exe" run "$tmp/h.yaml" --output "$tmp/out" --quiet || { echo "FAIL: the run exited $?"; exit 1; }
/usr/bin/python3 "$src/scripts/hertz_sphere_check" "$tmp/out" > "$tmp/check.txt" || { cat "$tmp/check.txt"; echo "FAIL: hertz_sphere_check"; exit 1; }
sed -n 1,12p "$tmp/check.txt"
/usr/bin/python3 - "$tmp" <<'PY'
import json, re, sys
tmp = sys.argv[1]
err = {}
for line in open(f"{tmp}/check.txt"):
    m = re.match(r"\s*(p0 \(max\)|p0 \(fit\)|a \(fit\))\s+\S+\s+\S+\s+([-+0-9.]+)%", line)
    if m:
        err[m.group(1)] = float(m.group(2))
bounds = {"p0 (max)": 2.0, "p0 (fit)": 2.0, "a (fit)": 5.0}
fail = False
for k, b in bounds.items():
    if k not in err:
        print(f"FAIL: no '{k}' line in the check"); fail = True
    elif abs(err[k]) > b:
        print(f"FAIL: {k} {err[k]:+.2f} % of Hertz, bound {b} %"); fail = True
s = json.load(open(f"{tmp}/out/summary.json"))
F = s["contact"][0]["force"]
R = s["reactions"]["ball"]
Rsum = [sum(r[c] for r in R.values()) for c in range(3)]
for c in range(3):
    if abs(Rsum[c] + F[c]) > 1e-8 * abs(F[2]):
        print(f"FAIL: equilibrium, component {c}: reactions {Rsum[c]:.12g}, contact force {F[c]:.12g}"); fail = True
if fail:
    sys.exit(1)
print(f"Hertz ball: p0 {err['p0 (max)']:+.2f} % (fit {err['p0 (fit)']:+.2f} %), a (fit) {err['a (fit)']:+.2f} %; "
      f"reactions balance the contact force to {max(abs(Rsum[c] + F[c]) for c in range(3)) / abs(F[2]):.1e}")
PY
