#!/usr/bin/env bash
# An example through the command line on 1 and 2 MPI ranks: the same answers, and the physics.
#  - 1 vs 2 ranks: dofs and cuts equal, Newton iterations per step within one; every reaction, contact force and
#    pressure, probe displacement and stress, and the largest displacement agree to 1e-10 of
#    the largest value of that quantity (the direct solver: both runs differ by the round-off
#    of sums taken in another order; 1e-8 where a step took one Newton iteration more, below);
#  - lame (examples/lame_cylinder.yaml): the probes against the closed form (plane strain
#    Lame), displacement to 1e-5 and stress to 1e-2 of the largest (O(h^(p+1)) and O(h^p) at
#    h = 1/16, p >= 2), and the reactions of the two symmetry cuts balance the pressure on
#    the inner quarter circle (p a in x and in y) to 1e-10;
#  - wheel (examples/wheel.yaml): the reactions of each body balance the contact force to
#    1e-8 (the Newton tolerance is 1e-10 of the residual), and the peak pressure and the
#    half-width (the gap's zero crossing at the edge of the active points) agree with Hertz
#    for the computed load within 5 % (as tests/test_contact).
#  - patch3d (examples/contact_patch_3d.yaml): the 3-D contact patch test, exact (below).
#  - sliding3d (examples/sliding_box_3d.yaml): 3-D gross sliding, T = (-mu F_n, 0, 0) exactly.
# Usage: cli_ranks.sh EXE MPIEXEC PROBLEM lame|wheel|patch3d|sliding3d [RUN OPTIONS...]
# (RUN OPTIONS, e.g. --set contact.0.method=mortar_penalty, go to both runs)
# MPI runs take one thread per rank (OMP_NUM_THREADS=1): 2 ranks x 1 thread fill 2 cores; with
# the OpenMP build more threads oversubscribe them and Kokkos warns on stderr.
set -euo pipefail
exe="$1"; mpiexec="$2"; file="$3"; check="$4"; shift 4
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
"$exe" run "$file" --output "$tmp/r1" --quiet "$@"
env OMP_NUM_THREADS=1 "$mpiexec" -n 2 "$exe" run "$file" --output "$tmp/r2" --quiet "$@"
/usr/bin/python3 - "$tmp" "$file" "$check" <<'PY'
import csv, json, math, re, sys
# the contact edge: the gap's zero crossing between the outermost active point and its inactive
# neighbour (the slave points run along the rim towards x = 0)
def edge(d):
    rows = list(csv.DictReader(open(d + "/contact_0.csv")))
    e = float("nan")
    for r0, r1 in zip(rows, rows[1:]):
        if r0["active"] == "0" and r1["active"] != "0":
            g0, g1 = float(r0["gap"]), float(r1["gap"])
            e = abs(float(r0["x"]) + g0 / (g0 - g1) * (float(r1["x"]) - float(r0["x"])))
    return e
tmp, problem, check = sys.argv[1:4]
a, b = (json.load(open(f"{tmp}/r{n}/summary.json")) for n in (1, 2))
assert a["ranks"] == 1 and b["ranks"] == 2, (a["ranks"], b["ranks"])
assert a["converged"] and b["converged"], "not converged"
for k in ("dofs", "cuts"):
    assert a[k] == b[k], (k, a[k], b[k])
# Newton iterations: equal, or one more in a step where the other run's last residual fell
# just below the tolerance (the last linear solve aims at half the Newton tolerance; its
# preconditioner, kept factors of an earlier tangent, follows each run's own decisions to
# refactorise, which count the factors' entries, and those depend on the rank count). The
# answers are then as close as two runs stopped at relative residuals on either side of the
# tolerance 1e-10 can be: 1e-8 of each quantity's largest value (measured: 5e-10 on a 3-D
# stress) instead of the 1e-10 of two runs that took the same steps.
assert len(a["newton_iterations"]) == len(b["newton_iterations"]), ("newton_iterations", a["newton_iterations"], b["newton_iterations"])
for i, j in zip(a["newton_iterations"], b["newton_iterations"]):
    assert abs(i - j) <= 1, ("newton_iterations", a["newton_iterations"], b["newton_iterations"])
agree = 1e-10
if a["newton_iterations"] != b["newton_iterations"]:
    agree = 1e-8
    print("  Newton iterations per step", a["newton_iterations"], "(1 rank),", b["newton_iterations"], "(2 ranks): answers compared to", agree)
for s in (a, b):
    assert s["linear_solver"]["method"] == "direct", "1e-10 assumes the direct solver: " + s["linear_solver"]["method"]

worst = {}
def same(name, x, y):   # lists of numbers, one quantity: relative to its largest value
    assert len(x) == len(y), (name, x, y)
    scale = max(abs(v) for v in x)
    d = max(abs(u - v) for u, v in zip(x, y))
    assert d <= agree * scale, f"1 vs 2 ranks: {name}: {x} vs {y}"
    worst[name] = d / scale if scale else 0.0

reac = lambda s: [v for body in sorted(s["reactions"]) for side in sorted(s["reactions"][body]) for v in s["reactions"][body][side]]
same("reactions", reac(a), reac(b))
same("max_displacement", [a["max_displacement"]], [b["max_displacement"]])
assert len(a["contact"]) == len(b["contact"])
for k, (ca, cb) in enumerate(zip(a["contact"], b["contact"])):
    if ca["method"].startswith("mortar") and "contact_area" in ca:
        # 3-D mortar: the slots come from an exact clipping, which keeps a corner however small
        # its turn; where a master edge lies along a slave element's edge, round-off of the
        # solution (other sums on 2 ranks) adds or drops such corners and the fans of triangles
        # (and so the number of slots) differ, the segments' union not: the slot count is not
        # compared, the measures and forces are (below, to 1e-10)
        print(f"  contact {k}: active slots {ca['active_points']} (1 rank), {cb['active_points']} (2 ranks)")
    else:
        assert ca["active_points"] == cb["active_points"], (k, ca["active_points"], cb["active_points"])
    for f in ("normal_force", "max_pressure", "contact_area" if "contact_area" in ca else "contact_length"):
        same(f"contact {k} {f}", [ca[f]], [cb[f]])
    same(f"contact {k} force", ca["force"], cb["force"])
    if "tangential_force" in ca and isinstance(ca["tangential_force"], list):   # 3-D friction
        same(f"contact {k} tangential_force", ca["tangential_force"], cb["tangential_force"])
        for f in ("stick_area", "slip_area"):
            assert abs(ca[f] - cb[f]) <= 1e-12, (f, ca[f], cb[f])
assert len(a["probes"]) == len(b["probes"])
for k, (pa, pb) in enumerate(zip(a["probes"], b["probes"])):
    for f in ("displacement", "stress"):
        same(f"probe {k} {f}", pa[f], pb[f])
print("1 vs 2 ranks agree: largest relative difference %.1e (%s)" % max((v, k) for k, v in worst.items()))

text = open(problem).read()
def num(key):   # the first value of `key` in the problem file
    m = re.search(key + r":\s*([-+0-9.eE]+)", text)
    assert m, ("no " + key + " in " + problem)
    return float(m.group(1))

for s, n in ((a, 1), (b, 2)):
    d = f"{tmp}/r{n}"
    if check == "lame":
        ri, ro, p, E, nu = num("inner_radius"), num("outer_radius"), num("pressure"), num("youngs_modulus"), num("poisson_ratio")
        A, B = p * ri**2 / (ro**2 - ri**2), p * ri**2 * ro**2 / (ro**2 - ri**2)
        assert len(s["probes"]) >= 2, "the Lame example has probes at both radii"
        for q in s["probes"]:
            x, y = q["x"], q["y"]
            r = math.hypot(x, y); c, sn = x / r, y / r
            ur = (1 + nu) / E * ((1 - 2 * nu) * A * r + B / r)
            srr, stt = A - B / r**2, A + B / r**2
            u = (ur * c, ur * sn)
            sig = (srr * c * c + stt * sn * sn, srr * sn * sn + stt * c * c, (srr - stt) * sn * c)
            eu = max(abs(g - e) for g, e in zip(q["displacement"], u)) / abs(ur)
            es = max(abs(g - e) for g, e in zip(q["stress"], sig)) / max(abs(v) for v in sig)
            print(f"  {n} rank(s): probe r = {r:g}: displacement error {eu:.1e}, stress error {es:.1e} (closed form)")
            assert eu <= 1e-5 and es <= 1e-2, ("Lame closed form", q, u, sig)
        R = s["reactions"]["cylinder"]
        fx, fy = sum(v[0] for v in R.values()), sum(v[1] for v in R.values())
        assert abs(fx + p * ri) <= 1e-10 * p * ri and abs(fy + p * ri) <= 1e-10 * p * ri, ("reactions", R, p * ri)
    elif check == "wheel":
        c = s["contact"][0]
        P = c["normal_force"]
        for body, sign in ((c["slave"]["body"], -1), (c["master"]["body"], 1)):
            R = s["reactions"][body]
            for i in range(2):
                tot = sum(v[i] for v in R.values())
                assert abs(tot - sign * c["force"][i]) <= 1e-8 * P, ("equilibrium", body, i, R, c["force"])
        Rw, E, nu = num("outer_radius"), num("youngs_modulus"), num("poisson_ratio")
        Es = E / (2 * (1 - nu * nu))   # two bodies of the same material
        half = math.sqrt(4 * 2 * P * Rw / (math.pi * Es))   # the whole wheel carries 2 P
        p0 = 2 * 2 * P / (math.pi * half)
        e = edge(d)
        print(f"  {n} rank(s): p0 {c['max_pressure']:.5g} (Hertz {p0:.5g}), half-width {e:.5g} (Hertz {half:.5g})")
        assert abs(c["max_pressure"] - p0) <= 0.05 * p0 and abs(e - half) <= 0.05 * half, "Hertz"
    elif check == "patch3d":
        # examples/contact_patch_3d.yaml: the uniform state is exact (sigma_zz = -1), so the
        # contact force is p x area = 4, every pressure 1 and the probe at the top's far corner
        # moves by (nu p / E x 2, the same, -p (1 / E_top + 1 / E_base) - p / eps)
        c = s["contact"][0]
        assert abs(c["normal_force"] - 4) <= 1e-9 and abs(c["force"][2] - 4) <= 1e-9, c
        assert abs(s["reactions"]["base"]["front"][2] - 4) <= 1e-9, s["reactions"]
        rows = list(csv.DictReader(open(d + "/contact_0.csv")))
        assert list(rows[0].keys()) == ["x", "y", "z", "xi", "eta", "gap", "pressure", "active"], rows[0].keys()
        dp = max(abs(float(r["pressure"]) - 1) for r in rows)
        u = s["probes"][0]["displacement"]
        du = max(abs(g - e) for g, e in zip(u, (3e-4, 3e-4, -1.51e-3)))
        print(f"  {n} rank(s): {len(rows)} contact points, max |p - 1| = {dp:.1e}, probe |u - exact| = {du:.1e}")
        assert dp <= 1e-8 and du <= 1e-12, "patch test"
    elif check == "sliding3d":
        # examples/sliding_box_3d.yaml: every point slips along -x with |t| = mu p, so the
        # tangential force is (-mu F_n, 0, 0) and the slip area the whole footprint (1)
        c, mu = s["contact"][0], num("friction")
        T, Fn = c["tangential_force"], c["normal_force"]
        assert abs(T[0] + mu * Fn) <= 1e-9 * Fn and abs(T[1]) <= 1e-9 * Fn and abs(T[2]) <= 1e-9 * Fn, (T, Fn)
        assert abs(c["slip_area"] - 1) <= 1e-12 and c["stick_area"] == 0, c
        rows = list(csv.DictReader(open(d + "/contact_0.csv")))
        assert list(rows[0].keys())[-5:] == ["tx", "ty", "tz", "slip", "state"], rows[0].keys()
        act = [r for r in rows if r["active"] == "1"]
        pmax = max(float(r["pressure"]) for r in act)
        dt = max(abs(float(r["tx"]) + mu * float(r["pressure"])) + abs(float(r["ty"])) for r in act)
        assert all(r["state"] == "2" for r in act) and dt <= 1e-8 * pmax, ("point law", dt)
        print(f"  {n} rank(s): T = {T[0]:.12g} = -mu F_n {-mu * Fn:.12g}; {len(act)} points slip, max |t + mu p e_x| = {dt:.1e}")
    else:
        sys.exit("unknown check " + check)
print(check + ": physics OK on 1 and 2 ranks")
PY
