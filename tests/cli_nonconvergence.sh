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

# stops NAME FILE PATTERN [ARGS...]: the run of FILE exits 3 with one line on stderr matching PATTERN
stops() {
  local name="$1" file="$2" pattern="$3"; shift 3
  err=$("$exe" run "$file" --output "$tmp/$name" --quiet "$@" 2>&1 >/dev/null); rc=$?
  [ "$rc" = 3 ] || { echo "FAIL: $name: exit $rc, expected 3: $err"; exit 1; }
  echo "$err" | grep -q "$pattern" || { echo "FAIL: $name: message: $err"; exit 1; }
  [ "$(printf '%s\n' "$err" | wc -l)" = 1 ] || { echo "FAIL: $name: not one line: $err"; exit 1; }
}

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
stops apart "$tmp/cap_apart.yaml" \
  "stopped after 1 cut(s).*body cap is held by contact alone (contact\[0\]) and touched base nowhere (still 0.0[45][0-9]* apart): it started farther from base.*prescribed displacement"
echo "body held by contact alone, apart: $err"

# The same body pulled away by its load (the wheel example's cut under an upward traction):
# no contact can hold it, and the line says so (it said 'it started farther from block than
# its load moves it', found with a hostile input).
stops pulled "$(dirname "$0")/../examples/wheel.yaml" \
  "body wheel is held by contact alone (contact\[0\]) and touched block nowhere (still .* apart): its load pulls it away from block.*reverse the load, or support wheel by a prescribed displacement" \
  --set analysis.load_steps=1 --set "bodies.1.boundary.west={traction: [0.0, 2.0]}"
echo "body held by contact alone, pulled away: $err"

# An augmented Lagrangian given too few multiplier updates (contact.augmentations: 2, a
# penalty of 1 E/h): the gaps are not closed within them at any increment the cuts try, and
# before this the run went on cutting (the press in 256 increments, each a state written; a
# helper's problem wrote 932 MB in 215 cuts). Reaching the limit is a stall: one that a cut
# does not cure ends the run after that cut, and the line says what to raise.
for m in mortar_alm kts_alm; do
  stops "aug_$m" "$(dirname "$0")/../examples/two_blocks_middle.yaml" \
    "stopped after 1 cut(s) of its increment: the augmented Lagrangian reached contact.augmentations = 2.*try more contact.augmentations" \
    --set contact.0.method=$m --set contact.0.augmentations=2 --set contact.0.penalty=1e3
  n=$(ls "$tmp/aug_$m" | grep -c '^result_.*\.vtu$')
  [ "$n" -le 2 ] || { echo "FAIL: aug_$m: $n states written"; exit 1; }
  echo "too few augmentations ($m): $err"
done

# A neo-Hookean block (E = 1) pressed and slid over a base of E = 1e9 at finite strain: Newton
# stalls at relative residual 1e-3 (round-off of the stiff base in the tangent); E = 1e8 or 1e4
# converge in 3 iterations a step. The line names the moduli's ratio and what to give the
# stiff body (it named only load steps, the penalty and max_iterations; found by a problem
# written from the docs)
cat > "$tmp/stiff_base.yaml" <<'YAML'
analysis: {type: plane_strain, kinematics: finite, stages: [5, 10]}
bodies:
  - name: base
    material: {youngs_modulus: 1.0e9, poisson_ratio: 0.3}
    geometry: {rectangle: {origin: [-1.0, -0.5], size: [5.0, 0.5]}}
    refine: {degree_elevate: 1, subdivide: [10, 1]}
    boundary:
      south: {displacement: {x: 0.0, y: 0.0}}
  - name: blk
    material: {model: neo_hookean, youngs_modulus: 1.0, poisson_ratio: 0.3}
    geometry: {rectangle: {origin: [0.0, 0.0], size: [1.0, 1.0]}}
    refine: {degree_elevate: 1, subdivide: [3, 3]}
    boundary:
      north: {displacement: {y: [-0.3, -0.3]}}
      north_west: {displacement: {x: [0.0, 2.0]}}
contact:
  - master: {body: base, side: north}
    slave: {body: blk, side: south}
    method: kts_penalty
    penalty: 1.0e4
YAML
stops stiff_base "$tmp/stiff_base.yaml" "base's Young's modulus is 1e+09 times blk's: give it 1e3-1e4 times"
echo "a base 1e9 times stiffer: $err"

# A body held by contact alone whose slave side lies nowhere in front of its master (two half
# cylinders set on opposite sides of the symmetry line, touching at one point, the upper one
# pressed by a traction): the first tangent is singular, though MUMPS finds no exact null
# pivot (the solution's true residual is 2.8 of the load). It was cut 10 times (the same
# matrix each time, exit 3 after ten lines); now the first failure ends it, and the line names
# the body and the pair that holds nothing (found by a problem written from the docs).
cat > "$tmp/nowhere.yaml" <<'YAML'
analysis: {type: plane_strain, load_steps: 2}
bodies:
  - name: lower
    material: {youngs_modulus: 1000.0, poisson_ratio: 0.3}
    geometry: {quarter_annulus: {center: [0.0, -2.0], inner_radius: 0.2, outer_radius: 2.0, start_angle: 0}}
    refine: {degree_elevate: [0, 1], subdivide: [6, 3]}
    boundary: {west: {displacement: {x: 0.0, y: 0.0}}, east: {displacement: {x: 0.0}}}
  - name: upper
    material: {youngs_modulus: 1000.0, poisson_ratio: 0.3}
    geometry: {quarter_annulus: {center: [0.0, 1.0], inner_radius: 0.1, outer_radius: 1.0, start_angle: 180}}
    refine: {degree_elevate: [0, 1], subdivide: [6, 3]}
    boundary: {west: {traction: [0.0, -0.6]}, east: {displacement: {x: 0.0}}}
contact:
  - {master: {body: lower, side: north}, slave: {body: upper, side: north}, method: mortar_penalty, penalty: 1.0e6}
YAML
stops nowhere "$tmp/nowhere.yaml" \
  "failed at its first iteration, which no smaller increment changes.*singular.*body upper is held by contact alone (contact\[0\]) and touched lower nowhere (no slave point of contact\[0\] lies in front of its master" \
  --set solver.linear.method=direct
echo "body held by contact alone, facing nothing: $err"

# A ball touching a block at one point, pressed by a traction in one load step (force control)
# on a coarse mesh (8 x 8 x 4 elements each): kts_penalty converges (its point at the pole
# touches), but mortar's gap of the pole's control point is the mean over its support, 8e-4,
# which the band of near-contact stiffness cannot close (found by a problem written from the
# docs; the line said only 'start the bodies touching', which they do). The line now says why
# with mortar and what to do.
cat > "$tmp/ball.yaml" <<'YAML'
analysis:
  type: solid
bodies:
  - name: block
    material: {youngs_modulus: 1000.0, poisson_ratio: 0.3}
    geometry: {box: {origin: [0.0, 0.0, -1.0], size: [1.0, 1.0, 1.0]}}
    refine:
      degree_elevate: 1
      subdivide: [8, 8, 4]
    boundary:
      west:  {displacement: {x: 0.0}}
      south: {displacement: {y: 0.0}}
      front: {displacement: {z: 0.0}}
  - name: ball
    material: {youngs_modulus: 1000.0, poisson_ratio: 0.3}
    geometry:
      nurbs:
        degree: [2, 2, 1]
        knots: [[0, 0, 0, 1, 1, 1], [0, 0, 0, 1, 1, 1], [0, 0, 1, 1]]
        control_points: [
          [0.0, 0.0, 1.0, 1.0], [0.0, 0.0, 1.0, 0.7071067811865476], [0.0, 0.0, 1.0, 1.0],
          [0.0, 0.0, 1.0, 0.7071067811865476], [0.0, 0.0, 1.0, 0.5], [0.0, 0.0, 1.0, 0.7071067811865476],
          [0.0, 0.0, 1.0, 1.0], [0.0, 0.0, 1.0, 0.7071067811865476], [0.0, 0.0, 1.0, 1.0],
          [0.0, 0.0, 0.0, 1.0], [0.0, 1.0, 0.0, 0.7071067811865476], [0.0, 1.0, 1.0, 1.0],
          [1.0, 0.0, 0.0, 0.7071067811865476], [1.0, 1.0, 0.0, 0.5], [1.0, 1.0, 1.0, 0.7071067811865476],
          [1.0, 0.0, 1.0, 1.0], [1.0, 0.0, 1.0, 0.7071067811865476], [1.0, 0.0, 1.0, 1.0]]
    refine:
      degree_elevate: [0, 0, 1]
      subdivide: [8, 8, 4]
    boundary:
      west:  {displacement: {y: 0.0}}
      south: {displacement: {x: 0.0}}
      east:  {traction: [0.0, 0.0, -0.382]}
contact:
  - master: {body: block, side: back}
    slave:  {body: ball, side: back}
    method: mortar_penalty
    penalty: 1e6
output:
  steps: last
YAML
stops ball "$tmp/ball.yaml" \
  "body ball is held by contact alone.*with mortar_penalty the gap of a slave control point is the mean over its support.*refine the slave where they touch, or take kts_penalty"
"$exe" run "$tmp/ball.yaml" --output "$tmp/ball_kts" --quiet --set contact.0.method=kts_penalty 2>/dev/null \
  || { echo "FAIL: ball with kts_penalty: exit $?"; exit 1; }
echo "ball under force control: mortar's line says why: $err"
