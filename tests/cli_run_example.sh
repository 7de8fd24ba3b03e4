#!/usr/bin/env bash
# Runs an example through the command line and checks what it must write. Every command's
# exit code counts: outputs are captured first, then searched (grep -q in a pipe would end
# the producer early, and without pipefail its exit code was lost).
set -euo pipefail
exe="$1"; file="$2"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
out=$("$exe" check "$file")
grep -q "check: OK" <<< "$out" || { echo "check did not print 'check: OK': $out"; exit 1; }
# check runs on one process without MPI or Kokkos; under mpiexec it takes the parallel path,
# and rank 0 alone prints (mpiexec is required, as by the suite's 2-rank tests)
command -v mpiexec > /dev/null || { echo "mpiexec not found"; exit 1; }
out=$(OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpiexec -n 2 --oversubscribe "$exe" check "$file")
n=$(grep -c "check: OK" <<< "$out" || true)   # grep -c exits 1 on a count of 0, checked below
[ "$n" = 1 ] || { echo "check on 2 ranks printed 'check: OK' $n times"; exit 1; }
# bad input through check: the same one line, exit 2
printf 'bodies: []\n' > "$tmp/bad.yaml"
set +e; err=$("$exe" check "$tmp/bad.yaml" 2>&1 >/dev/null); rc=$?; set -e
[ "$rc" = 2 ] && [ "$(printf '%s\n' "$err" | wc -l)" = 1 ] || { echo "check of a bad file: exit $rc, '$err'"; exit 1; }
"$exe" "$file" --output "$tmp/out" --quiet
for f in result.h5 result.xdmf summary.json; do test -s "$tmp/out/$f" || { echo "missing $f"; exit 1; }; done
grep -q '"converged": true' "$tmp/out/summary.json" || { echo "summary: not converged"; exit 1; }
if ls "$tmp/out" | grep '\.part$'; then echo "temporary file left behind"; exit 1; fi
out=$("$exe" --version); grep -q igacontact <<< "$out" || { echo "--version: $out"; exit 1; }
out=$("$exe" --help); grep -q "usage" <<< "$out" || { echo "--help: $out"; exit 1; }
echo "example OK"
