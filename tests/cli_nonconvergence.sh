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

# A body held by contact alone that starts apart from its support (a cap 0.05 above a block,
# pressed by a pressure): the tangent's band of near-contact stiffness moves it by about
# load / (penalty x contact length) per solve, so it never arrives. The line names the body,
# how far apart it still is and what to do, after one cut (smaller increments move it less;
# before, ten cuts and a hint about the penalty alone).
cat > "$tmp/cap_apart.yaml" <<'YAML'
analysis: {type: plane_strain}
bodies:
  - name: base
    material: {youngs_modulus: 500.0, poisson_ratio: 0.25}
    geometry: {rectangle: {origin: [0.0, 0.0], size: [2.0, 0.4]}}
    refine: {degree_elevate: 1, subdivide: [6, 2]}
    boundary: {south: {displacement: {y: 0.0}}, west: {displacement: {x: 0.0}}}
  - name: cap
    material: {youngs_modulus: 500.0, poisson_ratio: 0.25}
    geometry: {rectangle: {origin: [0.0, 0.45], size: [2.0, 0.6]}}
    refine: {degree_elevate: 1, subdivide: [4, 3]}
    boundary: {west: {displacement: {x: 0.0}}, north: {pressure: 5.0}}
contact:
  - {master: {body: cap, side: south}, slave: {body: base, side: north}, method: mortar_penalty, penalty: 1.0e5}
YAML
err=$("$exe" run "$tmp/cap_apart.yaml" --output "$tmp/apart" --quiet 2>&1 >/dev/null); rc=$?
[ "$rc" = 3 ] || { echo "FAIL: cap apart: exit $rc, expected 3"; exit 1; }
echo "$err" | grep -q "stopped after 1 cut(s).*body cap is held by contact alone (contact\[0\]) and touched base nowhere (still 0.0[45][0-9]* apart).*prescribed displacement" \
  || { echo "FAIL: cap apart: message: $err"; exit 1; }
[ "$(printf '%s\n' "$err" | wc -l)" = 1 ] || { echo "FAIL: cap apart: not one line: $err"; exit 1; }
echo "body held by contact alone, apart: $err"
