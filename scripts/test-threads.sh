#!/usr/bin/env bash
# The threads check (issue 38), apart from CI's Serial suite because its Trilinos takes an hour
# to build once per machine (scripts/build-trilinos-openmp.sh). With that install at PREFIX
# (default /opt/trilinos-openmp) it
#  1. builds igacontact against it into build-omp/ (and the Serial build/ if missing);
#  2. runs the whole ctest suite there with OMP_NUM_THREADS=2 (the thread tests compare 1 and
#     2 threads; MPI tests take 1 thread per rank);
#  3. runs the wheel (KTS and mortar), the sliding block (friction) and the whole wheel
#     (four patches, friction) on the Serial build and on 2 threads, and compares their
#     summary.json (contact forces, reactions, probes, largest displacement) to 1e-10.
# Without the install it says how to make one and exits 77 (skipped).
# Usage: scripts/test-threads.sh [PREFIX]
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$here"
prefix="${1:-/opt/trilinos-openmp}"
if [ ! -f "$prefix/lib/cmake/Trilinos/TrilinosConfig.cmake" ]; then
  echo "test-threads: no OpenMP Trilinos at $prefix: run scripts/build-trilinos-openmp.sh once (about an hour); skipped"
  exit 77
fi
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 HWLOC_COMPONENTS=-gl OMP_PROC_BIND=false
[ -x build/bin/igacontact ] || { cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release && cmake --build build -j "$(nproc)"; }
cmake -S . -B build-omp -G Ninja -DCMAKE_BUILD_TYPE=Release -DIGACONTACT_TRILINOS_PREFIX="$prefix" > /dev/null
cmake --build build-omp -j "$(nproc)"
grep -q "^#define KOKKOS_ENABLE_OPENMP" "$prefix"/include/KokkosCore_config.h || { echo "FAIL: $prefix has no Kokkos OpenMP"; exit 1; }
(cd build-omp && OMP_NUM_THREADS=2 ctest --output-on-failure -j 2 --timeout 900)

tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
fail=0
compare() {   # name, problem, --set ...
  local name="$1" file="$2"; shift 2
  build/bin/igacontact run "$file" --output "$tmp/$name.serial" --quiet "$@"
  OMP_NUM_THREADS=2 build-omp/bin/igacontact run "$file" --output "$tmp/$name.omp" --quiet "$@"
  /usr/bin/python3 - "$tmp/$name.serial/summary.json" "$tmp/$name.omp/summary.json" "$name" <<'PY' || fail=1
import json, sys
a, b = (json.load(open(f)) for f in sys.argv[1:3])
assert b["threads_per_rank"] == 2 and b["execution_space"] == "OpenMP", (b["execution_space"], b["threads_per_rank"])
def numbers(x, path=""):
    if isinstance(x, dict):
        for k, v in x.items(): yield from numbers(v, path + "." + k)
    elif isinstance(x, list):
        for i, v in enumerate(x): yield from numbers(v, path + "[%d]" % i)
    elif isinstance(x, (int, float)) and not isinstance(x, bool):
        yield path, float(x)
worst = 0.0
for key in ("contact", "reactions", "probes", "max_displacement"):
    na, nb = dict(numbers(a.get(key))), dict(numbers(b.get(key)))
    assert na.keys() == nb.keys(), key
    scale = max([abs(v) for v in na.values()] + [1e-300])
    for p in na:
        worst = max(worst, abs(na[p] - nb[p]) / scale)
ok = worst <= 1e-10 and a["newton_iterations"] == b["newton_iterations"]
print("%s: Serial against 2 threads, largest difference %.2e of each quantity's scale; Newton %s / %s: %s"
      % (sys.argv[3], worst, a["newton_iterations"], b["newton_iterations"], "ok" if ok else "FAIL"))
sys.exit(0 if ok else 1)
PY
}
compare wheel_kts examples/wheel.yaml --set contact.0.method=kts_penalty
compare wheel_mortar examples/wheel.yaml
compare sliding_block examples/sliding_block.yaml
compare whole_wheel examples/whole_wheel.yaml
[ "$fail" = 0 ] && echo "test-threads: all passed"
exit $fail
