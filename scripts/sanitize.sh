#!/usr/bin/env bash
# The whole test suite under AddressSanitizer + UndefinedBehaviorSanitizer.
# Builds igacontact (not Trilinos) with -fsanitize=address,undefined into build-asan/ and
# runs ctest there; any finding fails the test it occurs in (UBSan does not recover).
# Leak checking is off: Open MPI's start-up allocations (in plugins without symbols, so no
# suppression can name them) are reported as leaks by every test. Memory errors (ASan) and
# undefined behaviour (UBSan) stop the test they occur in; nothing is suppressed.
# Usage: scripts/sanitize.sh [ctest arguments, e.g. -R test_input]
# Takes about 15 minutes on 2 cores (build ~8, tests ~7).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$here"
flags="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
  -DIGACONTACT_BUILD_BENCHMARKS=OFF
cmake --build build-asan -j "$(nproc)"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export ASAN_OPTIONS="detect_leaks=0:strict_string_checks=1:detect_stack_use_after_return=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export IGACONTACT_HUGEPAGES=0   # off by default since 2026-11-27; kept so that a caller's =1 does not re-exec
cd build-asan
# fuzz_problem_loader builds its own ASan binary; the thread tests skip on Serial anyway
ctest --output-on-failure -j 2 --timeout 1500 -E "fuzz_problem_loader" "$@"
