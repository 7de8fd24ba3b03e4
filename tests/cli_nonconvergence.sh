#!/usr/bin/env bash
# A run that cannot converge: exit 3, one line saying what to try, and the output of the last
# converged load step with converged = false.
set -u
exe="$1"; file="$2"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
err=$("$exe" run "$file" --output "$tmp/out" --quiet --set solver.newton.max_iterations=1 --set analysis.load_steps=2 2>&1 >/dev/null); rc=$?
[ "$rc" = 3 ] || { echo "FAIL: exit $rc, expected 3"; exit 1; }
echo "$err" | grep -q "did not converge.*try" || { echo "FAIL: message: $err"; exit 1; }
[ "$(printf '%s\n' "$err" | wc -l)" = 1 ] || { echo "FAIL: not one line: $err"; exit 1; }
grep -q '"converged": false' "$tmp/out/summary.json" || { echo "FAIL: summary"; exit 1; }
test -s "$tmp/out/result.h5" || { echo "FAIL: no result.h5"; exit 1; }
echo "non-convergence reported: $err"
