#!/usr/bin/env bash
# Bounded libFuzzer run (clang, AddressSanitizer) of the problem-file loader, seeded with the
# examples and the bad-input catalogue. The fuzzer WORK_DIR/fuzz_problem is built by the build
# (target fuzz_problem, tests/CMakeLists.txt: rebuilt when a source or a header it includes
# changes). Without clang++ it skips (77); in CI (CI set) that fails.
# Usage: fuzz_loader.sh SOURCE_DIR WORK_DIR [SECONDS]
set -euo pipefail
src="$1"; work="$2"; secs="${3:-30}"
exe="$work/fuzz_problem"
if [ ! -x "$exe" ]; then
  if command -v clang++ > /dev/null || command -v clang++-14 > /dev/null; then
    echo "FAIL: $exe not built (cmake --build <build> --target fuzz_problem)"; exit 1
  fi
  echo "clang++ not found: skipped"
  case "${CI:-}" in "" | false | 0) exit 77 ;; *) echo "FAIL: CI=$CI, and CI must have clang++"; exit 1 ;; esac
fi
mkdir -p "$work/corpus"
# a memory budget of 100 MB: a fuzzed "subdivide: [100, 100000]" (2e7 dofs, valid on this
# machine) is refused by the size check instead of refined for longer than -timeout under ASan
export IGACONTACT_MEMORY_LIMIT=1e8
cp "$src"/examples/*.yaml "$src"/tests/bad_inputs/*.yaml "$work/corpus/"
# -rss_limit_mb: refinement of huge fuzzed meshes is refused by allocation, not by a crash
"$exe" "$work/corpus" -max_total_time="$secs" -timeout=20 -rss_limit_mb=2048 -malloc_limit_mb=1024 -max_len=4096 \
  -print_final_stats=1 -artifact_prefix="$work/" > "$work/fuzz.log" 2>&1 || { tail -n 40 "$work/fuzz.log"; exit 1; }
tail -n 12 "$work/fuzz.log"
