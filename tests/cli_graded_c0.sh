#!/usr/bin/env bash
# A valid mesh must not defeat the default solver (issue 15): a wheel pressed on a block given
# as a degree-1 NURBS with graded knots and `degree_elevate: 1`, so that the degree-2 block is
# only C0 across every knot line (where GMRES + MueLu stagnated). With the defaults (auto: the
# direct solver at this size) it must converge, to the contact force of the same geometry built
# C1 (a degree-2 block with the same knots inserted), within the discretisation difference of
# the two spaces (2 %).
# usage: cli_graded_c0.sh <igacontact> <examples dir>
set -euo pipefail
exe="$1"; examples="$2"
tmp="$(mktemp -d)"; trap 'rm -rf "$tmp"' EXIT

/usr/bin/python3 - "$examples/cattaneo_mindlin.yaml" "$tmp" <<'EOF'
import sys
src, out = sys.argv[1], sys.argv[2]
nx, ny = 40, 20
# knots clustered at the contact point (x centre, y top)
kx = [0.5 + 0.5 * (1 if u >= 0 else -1) * u * u for u in (2.0 * i / nx - 1.0 for i in range(nx + 1))]
ky = [1.0 - (1.0 - j / ny) ** 2 for j in range(ny + 1)]
text = open(src).read()
head, rest = text[:text.index("  - name: block")], text[text.index("  - name: wheel"):]
rest = rest.replace("south: {displacement: {x: [0.0, 0.0015], y: -0.0056}}", "south: {displacement: {x: 0.0, y: -0.0056}}")
rest = rest.replace("    friction: 0.3\n    tangential_penalty: 1.0e5\n", "")
head = head.replace("analysis: {type: plane_strain, stages: [2, 4]}", "analysis: {type: plane_strain, load_steps: 2}")
fmt = lambda v: ", ".join("%.15g" % x for x in v)
mat = "    material: {youngs_modulus: 1000.0, poisson_ratio: 0.3}\n"
bc = "    boundary:\n      south: {displacement: {x: 0.0, y: 0.0}}\n"
# C0: degree 1 with every knot, then elevated (each knot's multiplicity rises with the degree)
c0 = ["  - name: block", mat.rstrip(), "    geometry:", "      nurbs:", "        degree: [1, 1]",
      "        knots: [[0, %s, 1], [0, %s, 1]]" % (fmt(kx), fmt(ky)), "        control_points:"]
c0 += ["          - [%.15g, %.15g, 1]" % (-1.5 + 3.0 * x, -2.0 + 2.0 * y) for y in ky for x in kx]
c0 = "\n".join(c0) + "\n    refine: {degree_elevate: 1}\n" + bc
# C1: the bilinear rectangle elevated first, then the same knots inserted once
c1 = ("  - name: block\n" + mat + "    geometry: {rectangle: {origin: [-1.5, -2.0], size: [3.0, 2.0]}}\n"
      "    refine:\n      degree_elevate: 1\n      insert_knots: [[%s], [%s]]\n" % (fmt(kx[1:-1]), fmt(ky[1:-1])) + bc)
open(out + "/c0.yaml", "w").write(head + c0 + rest)
open(out + "/c1.yaml", "w").write(head + c1 + rest)
EOF

force() { /usr/bin/python3 -c "import json,sys; d=json.load(open(sys.argv[1])); assert d['converged']; print(d['contact'][0]['normal_force'])" "$1"; }
for m in c0 c1; do
  "$exe" run "$tmp/$m.yaml" --output "$tmp/out_$m" --quiet
done
f0=$(force "$tmp/out_c0/summary.json"); f1=$(force "$tmp/out_c1/summary.json")
solver=$(/usr/bin/python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['linear_solver']['method'])" "$tmp/out_c0/summary.json")
echo "graded C0 block: normal force $f0 (linear solver $solver); C1 block: $f1"
/usr/bin/python3 -c "import sys; f0, f1 = float(sys.argv[1]), float(sys.argv[2]); sys.exit(0 if abs(f0 - f1) <= 0.02 * abs(f1) else 1)" "$f0" "$f1"
