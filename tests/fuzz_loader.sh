#!/usr/bin/env bash
# Bounded libFuzzer run (clang, AddressSanitizer) of the problem-file loader, seeded with the
# examples and the bad-input catalogue. Usage: fuzz_loader.sh SOURCE_DIR WORK_DIR [SECONDS]
set -euo pipefail
src="$1"; work="$2"; secs="${3:-30}"
mkdir -p "$work/corpus"
exe="$work/fuzz_problem"
srcs=("$src/tests/fuzz_problem.cpp" "$src/model/problem.cpp" "$src/model/nurbs.cpp" "$src/model/bezier.cpp" "$src/model/geometry_check.cpp" "$src/model/configuration_check.cpp" "$src/model/multipatch.cpp" "$src/model/geometry_file.cpp" "$src/kernels/types.cpp")
stale=0
[ -x "$exe" ] || stale=1
for f in "${srcs[@]}"; do if [ "$f" -nt "$exe" ]; then stale=1; fi; done
if [ "$stale" = 1 ]; then
  clang++ -std=c++17 -O1 -g -fsanitize=fuzzer,address -I"$src" -isystem /usr/include/trilinos \
    -isystem /usr/lib/x86_64-linux-gnu/openmpi/include \
    "${srcs[@]}" \
    -o "$exe" -lyaml-cpp -ltrilinos_muelu -ltrilinos_teuchosparameterlist -ltrilinos_teuchosnumerics -ltrilinos_teuchoscore -ltrilinos_kokkoscore -llapack -lblas
fi
cp "$src"/examples/*.yaml "$src"/tests/bad_inputs/*.yaml "$work/corpus/"
# -rss_limit_mb: refinement of huge fuzzed meshes is refused by allocation, not by a crash
"$exe" "$work/corpus" -max_total_time="$secs" -timeout=20 -rss_limit_mb=2048 -malloc_limit_mb=1024 -max_len=4096 \
  -print_final_stats=1 -artifact_prefix="$work/" 2>&1 | tail -n 12; test "${PIPESTATUS[0]}" = 0
