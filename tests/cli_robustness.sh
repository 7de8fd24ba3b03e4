#!/usr/bin/env bash
# Robustness with the defaults (issue: robustness): the refinements, degrees and one-step
# loadings of examples/wheel.yaml that used to end in solver failures or internal errors
# (degree 3: block degree_elevate 2, wheel [1, 2]; block subdivide [S, S], wheel [S, S/2]).
# The defaults take the direct solver at these sizes; the gmres cases keep the iterative path
# under the same test. Each must converge and print no internal error, and the answers are
# checked by physics, not against a stored force:
#  - equilibrium: the reactions of each body balance the contact force, to 1e-8 of the normal
#    force (Newton stops at 1e-10 of the residual);
#  - the same discrete problem gives the same answer: gmres against the direct solver, and one
#    load step against two (frictionless contact is path-independent), normal force to 1e-8;
#  - Hertz line contact: the peak pressure within 5 % of Hertz for the computed load (as
#    tests/test_contact; the half-width is not checked here: on these meshes the slave points
#    at the contact edge are too far apart to place it within 5 %);
#  - the same indentation on every mesh and method: normal force within 0.5 % of the S = 8 KTS
#    run (the discretisation difference of the meshes, S = 4 and 8, and of KTS and mortar).
# Usage: cli_robustness.sh EXE WHEEL_YAML
set -u
exe="$1"; wheel="$2"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
fail=0; n=0
p3="--set bodies.0.refine.degree_elevate=2 --set bodies.1.refine.degree_elevate=[1,2]"
case_() {   # name, then --set arguments
  local name="$1"; shift
  n=$((n + 1))
  local out="$tmp/$n"
  timeout 300 "$exe" run "$wheel" --output "$out" --quiet "$@" 2>"$tmp/err"; local rc=$?
  if [ "$rc" != 0 ]; then echo "FAIL $name: exit $rc: $(cat "$tmp/err")"; fail=1; return; fi
  grep -q "internal error" "$tmp/err" && { echo "FAIL $name: internal error"; fail=1; }
  echo "$name" > "$out/name"
}
s8="--set bodies.0.refine.subdivide=[8,8] --set bodies.1.refine.subdivide=[8,4]"
s4="--set bodies.0.refine.subdivide=[4,4] --set bodies.1.refine.subdivide=[4,2]"
case_ "p=3 S=8 kts" $p3 $s8
case_ "p=3 S=8 mortar" $p3 $s8 --set contact.0.method=mortar_penalty
case_ "p=3 S=8 kts gmres" $p3 $s8 --set solver.linear.method=gmres
case_ "p=3 S=8 mortar gmres" $p3 $s8 --set contact.0.method=mortar_penalty --set solver.linear.method=gmres
case_ "p=3 S=4 kts, one load step" $p3 $s4 --set analysis.load_steps=1
case_ "p=3 S=4 mortar, one load step" $p3 $s4 --set analysis.load_steps=1 --set contact.0.method=mortar_penalty
case_ "p=3 S=8 kts, one load step" $p3 $s8 --set analysis.load_steps=1
case_ "p=3 S=8 mortar, one load step" $p3 $s8 --set analysis.load_steps=1 --set contact.0.method=mortar_penalty
/usr/bin/python3 - "$tmp" "$n" "$wheel" <<'PY' || fail=1
import json, math, os, re, sys
tmp, n, wheel = sys.argv[1], int(sys.argv[2]), sys.argv[3]
text = open(wheel).read()
num = lambda key: float(re.search(key + r":\s*([-+0-9.eE]+)", text).group(1))
R, E, nu = num("outer_radius"), num("youngs_modulus"), num("poisson_ratio")
Es = E / (2 * (1 - nu * nu))   # wheel and block of the same material
runs, bad = {}, []
def check(ok, what):
    if not ok:
        bad.append(what); print("FAIL " + what)
for k in range(1, n + 1):
    if not os.path.exists(f"{tmp}/{k}/name"): continue   # failed above
    name = open(f"{tmp}/{k}/name").read().strip()
    s = json.load(open(f"{tmp}/{k}/summary.json"))
    runs[name] = s
    c = s["contact"][0]; P = c["normal_force"]
    check(s["converged"], f"{name}: not converged")
    for body, sign in ((c["slave"]["body"], -1), (c["master"]["body"], 1)):
        for i in range(2):
            tot = sum(v[i] for v in s["reactions"][body].values())
            check(abs(tot - sign * c["force"][i]) <= 1e-8 * P, f"{name}: {body} reactions {tot} vs contact force {c['force'][i]}")
    a = math.sqrt(4 * 2 * P * R / (math.pi * Es)); p0 = 2 * 2 * P / (math.pi * a)   # the whole wheel carries 2 P
    check(abs(c["max_pressure"] - p0) <= 0.05 * p0, f"{name}: peak pressure {c['max_pressure']} vs Hertz {p0}")
    print(f"{name:34s} converged: Newton {sum(s['newton_iterations'])}, cuts {s['cuts']}, linear {s['linear_iterations']}, "
          f"normal force {P:.6f}, peak pressure {c['max_pressure'] / p0 - 1:+.2%} of Hertz")
f = lambda name: runs[name]["contact"][0]["normal_force"] if name in runs else float("nan")
for x, y in (("p=3 S=8 kts gmres", "p=3 S=8 kts"), ("p=3 S=8 mortar gmres", "p=3 S=8 mortar"),
             ("p=3 S=8 kts, one load step", "p=3 S=8 kts"), ("p=3 S=8 mortar, one load step", "p=3 S=8 mortar")):
    check(abs(f(x) - f(y)) <= 1e-8 * f(y), f"{x}: normal force {f(x)} differs from {y}: {f(y)}")
    print(f"{x} against {y}: normal force to {abs(f(x) - f(y)) / f(y):.1e}")
ref = f("p=3 S=8 kts")
for name in runs:
    check(abs(f(name) - ref) <= 0.005 * ref, f"{name}: normal force {f(name)} not within 0.5 % of p=3 S=8 kts {ref}")
sys.exit(1 if bad else 0)
PY
[ $fail = 0 ] && echo "$n robustness cases converged; equilibrium, Hertz and mesh independence hold"
exit $fail
