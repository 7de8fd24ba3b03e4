#!/usr/bin/env bash
# Runs an example through the command line and checks what it must write.
set -eu
exe="$1"; file="$2"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
"$exe" check "$file" | grep -q "check: OK"
# check runs on one process without MPI or Kokkos; under mpiexec it takes the parallel path,
# and rank 0 alone prints
if command -v mpiexec > /dev/null; then
  n=$(OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpiexec -n 2 --oversubscribe "$exe" check "$file" | grep -c "check: OK")
  [ "$n" = 1 ] || { echo "check on 2 ranks printed 'check: OK' $n times"; exit 1; }
fi
# bad input through check: the same one line, exit 2
printf 'bodies: []\n' > "$tmp/bad.yaml"
set +e; err=$("$exe" check "$tmp/bad.yaml" 2>&1 >/dev/null); rc=$?; set -e
[ "$rc" = 2 ] && [ "$(printf '%s\n' "$err" | wc -l)" = 1 ] || { echo "check of a bad file: exit $rc, '$err'"; exit 1; }
"$exe" "$file" --output "$tmp/out" --quiet
for f in result.h5 result.xdmf summary.json; do test -s "$tmp/out/$f" || { echo "missing $f"; exit 1; }; done
grep -q '"converged": true' "$tmp/out/summary.json"
ls "$tmp/out" | grep -q '\.part$' && { echo "temporary file left behind"; exit 1; }
"$exe" --version | grep -q igacontact
"$exe" --help | grep -q "usage"
echo "example OK"
