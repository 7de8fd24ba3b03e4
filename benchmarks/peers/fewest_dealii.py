#!/usr/bin/python3
"""fewest_dealii.py: deal.II's fewest dofs on the Lame cylinder below a relative L2 error, per
degree, over every aspect of the (theta, r) cell grid (issue 34's comparison: each code at its
best mesh, not one aspect for both).

    benchmarks/peers/fewest_dealii.py [--bound 5e-11] [--degrees 4 5 6 7 8] [--max-cells 40]

For each degree P and each NR (cells through the wall) it finds the fewest NT (cells around)
whose error is below the bound by bisection (the error falls as NT grows at fixed NR, until
NR's own error is reached), and prints the configuration with the fewest dofs per degree
(JSON lines, dealii_lame's own). Each run is build-peers/dealii_lame P NTxNR.
"""
import argparse
import json
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bound", type=float, default=5e-11)
    ap.add_argument("--degrees", type=int, nargs="+", default=[4, 5, 6, 7, 8])
    ap.add_argument("--max-cells", type=int, default=40, help="largest NT and NR tried")
    a = ap.parse_args()
    exe = subprocess.run([os.path.join(ROOT, "benchmarks/peers/build_peers.sh"), "dealii_lame"],
                         check=True, capture_output=True, text=True).stdout.strip()
    cache = {}

    def run(p, nt, nr):
        if (p, nt, nr) not in cache:
            out = subprocess.run([exe, str(p), "%dx%d" % (nt, nr)], check=True, capture_output=True, text=True).stdout
            cache[(p, nt, nr)] = json.loads(out.strip().splitlines()[-1])
        return cache[(p, nt, nr)]

    for p in a.degrees:
        best = None
        for nr in range(1, a.max_cells + 1):
            if best and 2 * (p * nr + 1) * (p + 1) >= best["dofs"]:
                break   # even one cell around has more dofs than the best
            if run(p, a.max_cells, nr)["l2_error"] > a.bound:
                continue   # this NR cannot reach the bound
            lo, hi = 1, a.max_cells   # error(hi) below the bound
            while lo < hi:
                mid = (lo + hi) // 2
                if run(p, mid, nr)["l2_error"] <= a.bound:
                    hi = mid
                else:
                    lo = mid + 1
            r = run(p, lo, nr)
            if best is None or r["dofs"] < best["dofs"]:
                best = r
        print(json.dumps(best) if best else json.dumps({"degree": p, "none_below": a.bound}))
        sys.stdout.flush()


if __name__ == "__main__":
    main()
