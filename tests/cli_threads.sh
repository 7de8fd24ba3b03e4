#!/usr/bin/env bash
# The same answers on 1 and 2 threads (Kokkos OpenMP build): runs a problem with
# OMP_NUM_THREADS=1 and 2 and compares reactions, contact forces and the contact pressure at
# every slave point. Threaded assembly sums element contributions atomically in another order,
# so the answers agree to the Newton and Krylov tolerances, not bit for bit: relative 1e-7 of
# the largest value of each quantity. Skipped (exit 77) on a Serial-only Kokkos.
set -eu
exe="$1"; file="$2"; shift 2   # further arguments go to "run" (e.g. --set ...)
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
for t in 1 2; do
  OMP_NUM_THREADS=$t OMP_PROC_BIND=spread OMP_PLACES=cores "$exe" run "$file" --output "$tmp/t$t" --quiet "$@"
  if grep -q '"execution_space": "Serial"' "$tmp/t$t/summary.json"; then
    echo "Kokkos has the Serial backend only: nothing to compare"; exit 77
  fi
done
/usr/bin/python3 - "$tmp/t1" "$tmp/t2" <<'EOF'
import csv, json, sys
a, b = (json.load(open(d + "/summary.json")) for d in sys.argv[1:3])
print(f"{a['execution_space']}: {a['threads_per_rank']} vs {b['threads_per_rank']} threads")
if b["threads_per_rank"] < 2:
    sys.exit("the second run did not get 2 threads")

def close(name, x, y, scale):
    err = abs(x - y) / max(scale, 1e-300)
    print(f"{name}: {x:.12g} vs {y:.12g} (rel. {err:.1e})")
    if err > 1e-7:
        sys.exit(f"{name} differs between 1 and 2 threads")

for body, sides in a["reactions"].items():
    for side, r in sides.items():
        scale = max(abs(v) for v in r)
        for k in range(2):
            close(f"reaction {body}.{side}[{k}]", r[k], b["reactions"][body][side][k], scale)
for k, (ca, cb) in enumerate(zip(a["contact"], b["contact"])):
    close(f"contact {k} normal force", ca["normal_force"], cb["normal_force"], abs(ca["normal_force"]))
    pa = [float(r["pressure"]) for r in csv.DictReader(open(f"{sys.argv[1]}/contact_{k}.csv"))]
    pb = [float(r["pressure"]) for r in csv.DictReader(open(f"{sys.argv[2]}/contact_{k}.csv"))]
    scale = max(abs(p) for p in pa)
    worst = max(abs(x - y) for x, y in zip(pa, pb)) / scale
    print(f"contact {k} pressure at {len(pa)} points: max difference {worst:.1e} of the peak")
    if len(pa) != len(pb) or worst > 1e-7:
        sys.exit(f"contact {k} pressure differs between 1 and 2 threads")
print("threads OK")
EOF
