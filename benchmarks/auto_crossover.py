#!/usr/bin/python3
"""The crossover of solver.linear.method: auto, per degree (issue 34): MUMPS (direct) against
what auto takes above the threshold (CG + BoomerAMG for a linear problem, GMRES + BoomerAMG
with Eisenstat-Walker forcing for contact), on a linear and on a contact family, p = 1..5.

  linear:  examples/lame_cylinder.yaml (Lame's thick cylinder; degree (2, 1) geometry
           elevated to (p, p)) for p >= 2; for p = 1 (a circle needs degree 2) the plate of
           the two-blocks family alone (lower block, south held, north traction)
  contact: examples/two_blocks_scaling.yaml (KTS penalty, 1 load step) with both blocks
           elevated to degree p, the lower block 4n x n elements and the upper n x n

For each degree and size the two solvers run in turn (direct, iterative, direct, ...:
--pairs pairs), so that the machine's drift falls on both alike. Reported per run: dofs,
Newton iterations, the solver's time (stages 4, 4a, 4b, 5), the computing time (every stage
but start-up, reading and output, which do not depend on the solver) and the process' wall
and CPU time; medians over the pairs. The crossover is where the computing time of the two
is equal (log-log interpolation between the bracketing sizes).

usage: benchmarks/auto_crossover.py [--degrees 1 2 3 4 5] [--dofs 1e4 3e4 6e4 1.2e5]
                                    [--families linear contact] [--pairs 1]
                                    [--exe build/bin/igacontact] [--out out/crossover]
Writes OUT/runs.jsonl (one line per run) and prints a Markdown table.
"""
import argparse
import json
import math
import os
import resource
import statistics
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SOLVER = ["4) Preconditioner setup", "4a) Direct: entries and analysis", "4b) Direct: factorisation",
          "5) Linear solve"]
COMPUTE = ["1) Set-up: maps and patches", "2) Assembly: elasticity", "2a) Internal force",
           "2b) Tangent: K + K_c, Dirichlet", "3) Contact: search and assembly", "7) Checks: penetration, inverted elements"] + SOLVER

PLATE = """analysis: {type: plane_strain}
bodies:
  - name: plate
    material: {youngs_modulus: 1000.0, poisson_ratio: 0.3}
    geometry: {rectangle: {origin: [0.0, 0.0], size: [4.0, 1.0]}}
    refine: {subdivide: [8, 2]}
    boundary:
      south: {displacement: {x: 0.0, y: 0.0}}
      north: {traction: [1.0, -2.0]}
output: {samples_per_element: 1}
"""


def sizes_for(family, p, target):
    """--set arguments giving about `target` dofs, and the dofs they give."""
    best = None
    for n in range(2, 2000):
        if family == "contact":
            dofs = 2 * (4 * n + p) * (n + p) + 2 * (n + p) ** 2
            sets = ["bodies.0.refine.degree_elevate=%d" % (p - 1), "bodies.1.refine.degree_elevate=%d" % (p - 1),
                    "bodies.0.refine.subdivide=[%d,%d]" % (4 * n, n), "bodies.1.refine.subdivide=[%d,%d]" % (n, n),
                    "solver.newton.tolerance=1e-10", "solver.linear.tolerance=1e-12"]
        elif p >= 2:   # Lame: NU = 2 NV (the file's aspect)
            dofs = 2 * (2 * n + p) * (n + p)
            sets = ["bodies.0.refine.degree_elevate=[%d,%d]" % (p - 2, p - 1),
                    "bodies.0.refine.subdivide=[%d,%d]" % (2 * n, n), "output.samples_per_element=1"]
        else:          # the plate, degree 1: 4 n x n elements
            dofs = 2 * (4 * n + 1) * (n + 1)
            sets = ["bodies.0.refine.subdivide=[%d,%d]" % (4 * n, n)]
        if best is None or abs(dofs - target) < abs(best[0] - target):
            best = (dofs, sets)
    return best


def run(exe, problem, sets, method, out):
    args = [exe, "run", problem, "--quiet", "--output", out] + sum((["--set", s] for s in sets), [])
    if method == "direct":
        args += ["--set", "solver.linear.method=direct"]
    # the iterative side: what auto takes above its threshold (it is the loader's default then)
    else:
        args += ["--set", "solver.linear.method=" + method, "--set", "solver.linear.preconditioner=boomeramg"]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.monotonic()
    p = subprocess.run(args, capture_output=True, text=True)
    wall = time.monotonic() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode != 0:
        sys.exit("failed (%d): %s\n%s" % (p.returncode, " ".join(args), p.stderr))
    s = json.load(open(os.path.join(out, "summary.json")))
    t = s["timings"]
    return {"dofs": s["dofs"], "newton": sum(s["newton_iterations"]), "linear_its": s["linear_iterations"],
            "solver_s": sum(t.get(k, 0.0) for k in SOLVER), "compute_s": sum(t.get(k, 0.0) for k in COMPUTE),
            "wall_s": wall, "cpu_s": (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime),
            "factor_entries": s["linear_solver"].get("factor_entries")}


def crossover(points):
    """points: [(dofs, direct_s, iterative_s)] by dofs; the dofs where the two are equal."""
    for (n0, d0, i0), (n1, d1, i1) in zip(points, points[1:]):
        r0, r1 = math.log(d0 / i0), math.log(d1 / i1)
        if r0 <= 0 < r1:
            return math.exp(math.log(n0) + (math.log(n1) - math.log(n0)) * (-r0) / (r1 - r0))
    if all(d > i for _, d, i in points):
        return "< %d" % points[0][0]
    if all(d <= i for _, d, i in points):
        return "> %d" % points[-1][0]
    return "?"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--degrees", type=int, nargs="+", default=[1, 2, 3, 4, 5])
    ap.add_argument("--dofs", type=float, nargs="+", default=[1e4, 3e4, 6e4, 1.2e5])
    ap.add_argument("--families", nargs="+", default=["linear", "contact"])
    ap.add_argument("--pairs", type=int, default=1)
    ap.add_argument("--exe", default=os.path.join(ROOT, "build", "bin", "igacontact"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "crossover"))
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    plate = os.path.join(a.out, "plate.yaml")
    with open(plate, "w") as f:
        f.write(PLATE)
    log = open(os.path.join(a.out, "runs.jsonl"), "a")
    rows = []
    for family in a.families:
        for p in a.degrees:
            problem = (os.path.join(ROOT, "examples", "two_blocks_scaling.yaml") if family == "contact"
                       else os.path.join(ROOT, "examples", "lame_cylinder.yaml") if p >= 2 else plate)
            iterative = "gmres" if family == "contact" else "cg"
            points = []
            for target in a.dofs:
                dofs, sets = sizes_for(family, p, target)
                res = {"direct": [], iterative: []}
                for k in range(a.pairs):
                    for m in ("direct", iterative):
                        r = run(a.exe, problem, sets, m, os.path.join(a.out, "run"))
                        r.update({"family": family, "p": p, "method": m, "pair": k})
                        log.write(json.dumps(r) + "\n")
                        log.flush()
                        res[m].append(r)
                med = {m: {q: statistics.median(x[q] for x in rs) for q in ("compute_s", "solver_s", "wall_s", "cpu_s")}
                       for m, rs in res.items()}
                d, i = med["direct"], med[iterative]
                rows.append("| %s | %d | %s | %d / %d | %.2f / %.2f | %.2f / %.2f | %.2f / %.2f | %.2f |" % (
                    family, p, format(dofs, ","), res["direct"][0]["newton"], res[iterative][0]["newton"],
                    d["solver_s"], i["solver_s"], d["compute_s"], i["compute_s"], d["cpu_s"], i["cpu_s"],
                    d["compute_s"] / i["compute_s"]))
                print(rows[-1], flush=True)
                points.append((dofs, d["compute_s"], i["compute_s"]))
            c = crossover(points)
            rows.append("| %s | %d | crossover (computing time equal): %s | | | | | |" % (
                family, p, format(round(c), ",") if isinstance(c, float) else c))
            print(rows[-1], flush=True)
    print("\n| family | p | dofs | Newton its direct / iterative | solver s direct / iterative "
          "| computing s direct / iterative | process CPU s direct / iterative | direct / iterative |")
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(r)


if __name__ == "__main__":
    main()
