#!/usr/bin/python3
"""Times two whole commands in turn (A B A B ...), pair by pair: wall seconds (a monotonic
clock from the start to the reaping) and CPU seconds (user + system of the finished child),
with one warm-up run of each that is not counted; prints each pair and the medians, and the
median of the pair-by-pair ratios A / B (pairing keeps the ratio meaningful when the machine's
speed drifts). A failed run is said and run again (up to 3 times).

usage: benchmarks/peers/time_pairs.py [--pairs 5] [--ok 0 ...] "COMMAND A" "COMMAND B"
(each command is split as a shell splits words; no shell runs it)
"""
import argparse
import resource
import shlex
import statistics
import subprocess
import sys
import time


def run(cmd, ok, tries=3):
    for _ in range(tries):
        r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        t0 = time.monotonic()
        p = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        t = time.monotonic() - t0
        r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        if p.returncode in ok:
            return t, (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
        print("  (exit %d after %.2f s, run again: %s)" % (p.returncode, t, cmd[0]), flush=True)
    sys.exit("%d failures in a row: %s" % (tries, " ".join(cmd)))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--pairs", type=int, default=5)
    ap.add_argument("--ok", type=int, nargs="+", default=[0], help="exit codes counted as success")
    ap.add_argument("a")
    ap.add_argument("b")
    args = ap.parse_args()
    a, b = shlex.split(args.a), shlex.split(args.b)
    run(a, args.ok)
    run(b, args.ok)   # warm-up (page cache, libraries), not counted
    wa, wb, ca, cb = [], [], [], []
    for i in range(args.pairs):
        t, c = run(a, args.ok)
        wa.append(t); ca.append(c)
        t, c = run(b, args.ok)
        wb.append(t); cb.append(c)
        print("  pair %d: A %.2f s (cpu %.2f), B %.2f s (cpu %.2f), ratio %.3f" % (i + 1, wa[-1], ca[-1], wb[-1], cb[-1], wa[-1] / wb[-1]),
              flush=True)
    med = statistics.median
    r = [x / y for x, y in zip(wa, wb)]
    print("  median wall: A %.2f s, B %.2f s; median ratio A/B (pair by pair) wall %.3f (pairs %.3f-%.3f), cpu %.3f" %
          (med(wa), med(wb), med(r), min(r), max(r), med([x / y for x, y in zip(ca, cb)])))


if __name__ == "__main__":
    main()
