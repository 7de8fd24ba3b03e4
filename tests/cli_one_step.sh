#!/usr/bin/env bash
# One load step per stage, as a user writes a first run: examples/ironing.yaml (a neo-Hookean
# slab, a die pressed 1.4 in and slid 4 along it, frictionless) with stages [1, 1] against the
# example's [14, 40]. The one-step stages need many increments: the die's slide in one
# increment gives NaN, and at a quarter of it Newton converged to a folded slab (det F < 0,
# caught only by the check after the step: exit 5); the cuts were counted per load step, so
# a stage of one step ran out of them. Now a converged state with inverted elements is a
# failed increment (cut), and solver.newton.max_cuts counts cuts in a row.
# Frictionless contact of hyperelastic bodies: the end state does not depend on the path, so
# the contact force [Fx, Fy] must agree with the example's to 1e-5 of |F| (both runs stop at a
# relative residual of 1e-8; they agree to 1e-6 in this test's first runs, force x
# included, which is 6 % of |F|).
# Then a 3-D punch with kts_alm at finite strain (below).
# Usage: cli_one_step.sh EXE IRONING_YAML
set -u
exe="$1"; file="$2"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
fail=0
for st in "[1,1]" "[14,40]"; do
  timeout 400 "$exe" run "$file" --output "$tmp/$st" --quiet --set "analysis.stages=$st" 2>"$tmp/err"; rc=$?
  if [ "$rc" != 0 ]; then echo "FAIL stages $st: exit $rc: $(cat "$tmp/err")"; fail=1; fi
done
[ "$fail" = 0 ] || exit 1
python3 - "$tmp/[1,1]/summary.json" "$tmp/[14,40]/summary.json" <<'EOF' || exit 1
import json, math, sys
a, b = (json.load(open(f))["contact"][0] for f in sys.argv[1:3])
fa, fb = a["force"], b["force"]
size = math.hypot(*fb)
err = math.hypot(fa[0] - fb[0], fa[1] - fb[1]) / size
print(f"ironing, stages [1, 1] against [14, 40]: force {fa} against {fb}: |dF| / |F| = {err:.2e}")
if not err <= 1e-5:
    print("FAIL: the one-step run's contact force differs from the example's by more than 1e-5")
    sys.exit(1)
EOF
echo "one load step per stage: ironing converges to the example's end state"

# A punch pressed 0.15 into a neo-Hookean block with kts_alm in 4 load steps: the ALM stall test
# took a window of multiplier updates that started at 0 (no active point yet) for a rate of inf
# and stopped the run at load step 3 ('from 0 to 1.135 times alm_tolerance (inf per update)',
# exit 3). With the punch as soft as the block (E = 100) it converges and the punch's reaction
# balances the contact force. The punch 100x stiffer than the block (the run of that finding)
# locked kts_alm while it kept a penalty per quadrature point besides its multipliers: points
# lifted off under closed weighted gaps, contact area 0.45 of the footprint, the force 6 % above
# mortar_alm's and depending on the penalty (then exit 5, named). kts_alm now has mortar's
# pressure field at the KTS points: the whole footprint in contact, and the converged force the
# same at penalties 1e4 and 1e5 (to what alm_tolerance leaves) and on 2 ranks.
cat > "$tmp/punch.yaml" <<'YAML'
analysis: {type: solid, kinematics: finite, load_steps: 4}
bodies:
  - name: base
    material: {model: neo_hookean, youngs_modulus: 100.0, poisson_ratio: 0.3}
    geometry: {box: {origin: [0, 0, 0], size: [2, 2, 1]}}
    refine: {degree_elevate: 1, subdivide: [12, 12, 3]}
    boundary: {front: {displacement: {x: 0.0, y: 0.0, z: 0.0}}}
  - name: punch
    material: {model: neo_hookean, youngs_modulus: 10000.0, poisson_ratio: 0.3}
    geometry: {box: {origin: [0.5, 0.5, 1.0], size: [1, 1, 0.5]}}
    refine: {degree_elevate: 1, subdivide: [4, 4, 1]}
    boundary: {back: {displacement: {x: 0.0, y: 0.0, z: -0.15}}}
contact:
  - {master: {body: base, side: back}, slave: {body: punch, side: front}, method: kts_alm, penalty: 1.0e4}
YAML
timeout 300 "$exe" run "$tmp/punch.yaml" --output "$tmp/punch" --quiet --set bodies.1.material.youngs_modulus=100.0 2>"$tmp/err"; rc=$?
[ "$rc" = 0 ] || { echo "FAIL punch kts_alm: exit $rc: $(cat "$tmp/err")"; exit 1; }
python3 - "$tmp/punch/summary.json" <<'EOF' || exit 1
import json, sys
s = json.load(open(sys.argv[1]))
c = s["contact"][0]
r = s["reactions"]["punch"]["back"]
err = max(abs(r[k] + c["force"][k]) for k in range(3)) / abs(c["force"][2])
print(f"punch, kts_alm, finite strain: Newton {s['newton_iterations']}, force {c['force']}, punch reaction {r}: {err:.1e}")
if not (abs(c["force"][2]) > 0 and err <= 1e-6):
    print("FAIL: the punch's reaction does not balance the contact force")
    sys.exit(1)
EOF
echo "kts_alm punch at finite strain converges"
timeout 300 "$exe" run "$tmp/punch.yaml" --output "$tmp/stiff" --quiet 2>"$tmp/err"; rc=$?
[ "$rc" = 0 ] || { echo "FAIL stiff punch kts_alm: exit $rc: $(cat "$tmp/err")"; exit 1; }
timeout 300 "$exe" run "$tmp/punch.yaml" --output "$tmp/stiff5" --quiet --set contact.0.penalty=1e5 2>"$tmp/err"; rc=$?
[ "$rc" = 0 ] || { echo "FAIL stiff punch kts_alm, penalty 1e5: exit $rc: $(cat "$tmp/err")"; exit 1; }
runs=("$tmp/stiff/summary.json" "$tmp/stiff5/summary.json")
if mpiexec=$(command -v mpiexec); then
  timeout 300 "$mpiexec" -n 2 "$exe" run "$tmp/punch.yaml" --output "$tmp/stiff2" --quiet 2>"$tmp/err2" >/dev/null; rc=$?
  [ "$rc" = 0 ] || { echo "FAIL stiff punch kts_alm on 2 ranks: exit $rc: $(cat "$tmp/err2")"; exit 1; }
  runs+=("$tmp/stiff2/summary.json")
fi
python3 - "${runs[@]}" <<'EOF' || exit 1
import json, sys
s = [json.load(open(f))["contact"][0] for f in sys.argv[1:]]
f = [c["force"][2] for c in s]
print(f"stiff punch, kts_alm: normal force {f} (penalty 1e4, 1e5{', 2 ranks' if len(f) > 2 else ''}), "
      f"contact area {[c['contact_area'] for c in s]}")
if not all(c["contact_area"] > 0.99 for c in s):
    sys.exit("FAIL: the punch's footprint (area 1) is not in contact: kts_alm locks")
if not all(abs(x - f[0]) <= 1e-6 * abs(f[0]) for x in f):
    sys.exit("FAIL: the converged force depends on the penalty or the ranks")
EOF
echo "kts_alm on a stiff punch: the whole footprint, the force independent of the penalty and the ranks"

# A wheel pressed 0.004 onto a block on a coarse uniform mesh (32 x 8 wheel elements, 24 x 16
# block) in one step: 3 active KTS points, less than one slave element's 6, and max_pressure 3x Hertz's
# with exit 0 and no word (found by a problem written from the docs). The run converges (the
# forces are right) and says, on stderr and in summary.json, that the zone is not resolved;
# the example's own mesh (wheel.yaml) says nothing.
cat > "$tmp/coarse.yaml" <<'YAML'
analysis: {type: plane_strain}
bodies:
  - name: block
    material: {youngs_modulus: 1000.0, poisson_ratio: 0.3}
    geometry: {rectangle: {origin: [-3.0, -2.0], size: [3.0, 2.0]}}
    refine: {degree_elevate: 1, subdivide: [24, 16]}
    boundary: {south: {displacement: {x: 0.0, y: 0.0}}, east: {displacement: {x: 0.0}}}
  - name: wheel
    material: {youngs_modulus: 1000.0, poisson_ratio: 0.3}
    geometry: {quarter_annulus: {center: [0.0, 1.0], inner_radius: 0.2, outer_radius: 1.0, start_angle: 180}}
    refine: {degree_elevate: [0, 1], subdivide: [32, 8]}
    boundary: {west: {displacement: {y: -0.004}}, east: {displacement: {x: 0.0}}}
contact:
  - {master: {body: block, side: north}, slave: {body: wheel, side: north}, method: kts_penalty, penalty: 1.0e6}
YAML
timeout 300 "$exe" run "$tmp/coarse.yaml" --output "$tmp/coarse" --quiet 2>"$tmp/err"; rc=$?
[ "$rc" = 0 ] || { echo "FAIL coarse wheel: exit $rc: $(cat "$tmp/err")"; exit 1; }
grep -q "^warning: .*contact\[0\] (wheel.north on block.north): the contact zone covers about .* slave element(s).*not resolved" "$tmp/err" ||
  { echo "FAIL coarse wheel: no warning: $(cat "$tmp/err")"; exit 1; }
python3 -c "import json,sys; s=json.load(open(sys.argv[1])); assert any('not resolved' in w for w in s['warnings'])" "$tmp/coarse/summary.json" ||
  { echo "FAIL coarse wheel: summary.json warnings"; exit 1; }
# the same with kts_alm and mortar (mortar counts the slave elements under pressure: one here)
for m in kts_alm mortar_penalty; do
  timeout 300 "$exe" run "$tmp/coarse.yaml" --output "$tmp/coarse_$m" --quiet --set contact.0.method=$m 2>"$tmp/err"; rc=$?
  [ "$rc" = 0 ] || { echo "FAIL coarse wheel $m: exit $rc: $(cat "$tmp/err")"; exit 1; }
  grep -q "^warning: .*contact\[0\] (wheel.north on block.north): the contact zone covers about 1 slave element(s).*not resolved" "$tmp/err" ||
    { echo "FAIL coarse wheel $m: no warning: $(cat "$tmp/err")"; exit 1; }
done
# A zone over three slave elements (the quarter wheel's half of it) but two of the coarser
# master's (a press of 0.016): max_pressure +46 % of Hertz with mortar and no word before the
# master's elements under pressure were counted too (2026-12-05)
timeout 300 "$exe" run "$tmp/coarse.yaml" --output "$tmp/coarse_master" --quiet --set contact.0.method=mortar_penalty \
  --set "bodies.1.boundary.west={displacement: {y: -0.016}}" 2>"$tmp/err"; rc=$?
[ "$rc" = 0 ] || { echo "FAIL coarse master: exit $rc: $(cat "$tmp/err")"; exit 1; }
grep -q "^warning: .*contact\[0\] (wheel.north on block.north): the contact zone covers about 3 slave element(s) (those with pressure) and 2 master element(s).*not resolved" "$tmp/err" ||
  { echo "FAIL coarse master: no warning: $(cat "$tmp/err")"; exit 1; }
# A pair that never touches (the upper block 0.3 above the lower, pressed 0.01): exit 0 with
# every contact quantity 0, and since 2026-12-05 a line saying so (found by a problem written
# from the docs: a mistyped origin gave a converged run and no word)
cat > "$tmp/apart.yaml" <<'YAML'
analysis: {type: plane_strain}
bodies:
  - name: lower
    material: {youngs_modulus: 1000.0, poisson_ratio: 0.3}
    geometry: {rectangle: {origin: [0.0, 0.0], size: [1.0, 0.5]}}
    boundary: {south: {displacement: {x: 0.0, y: 0.0}}}
  - name: upper
    material: {youngs_modulus: 1000.0, poisson_ratio: 0.3}
    geometry: {rectangle: {origin: [0.0, 0.8], size: [1.0, 0.5]}}
    boundary: {north: {displacement: {x: 0.0, y: -0.01}}}
contact:
  - {master: {body: lower, side: north}, slave: {body: upper, side: south}, method: kts_penalty, penalty: 1.0e5}
YAML
timeout 300 "$exe" run "$tmp/apart.yaml" --output "$tmp/apart" --quiet 2>"$tmp/err"; rc=$?
[ "$rc" = 0 ] || { echo "FAIL apart: exit $rc: $(cat "$tmp/err")"; exit 1; }
grep -q "^warning: .*contact\[0\] (upper.south on lower.north) carried no force in any load step (its nearest slave point ended 0.29 from the master)" "$tmp/err" ||
  { echo "FAIL apart: no warning: $(cat "$tmp/err")"; exit 1; }
timeout 300 "$exe" run "$(dirname "$2")/wheel.yaml" --output "$tmp/wheel" --quiet 2>"$tmp/err"; rc=$?
[ "$rc" = 0 ] && [ ! -s "$tmp/err" ] || { echo "FAIL wheel: exit $rc or stderr: $(cat "$tmp/err")"; exit 1; }
echo "a KTS zone narrower than two slave elements: warned; the example: not"
