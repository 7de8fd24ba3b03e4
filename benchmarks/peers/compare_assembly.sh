#!/usr/bin/env bash
# compare_assembly.sh: element formation per dof, igacontact against deal.II (issue 18), on
# igacontact's Lame cylinder (examples/lame_cylinder.yaml) at about the same dof count.
#
# For each degree p, N pairs, in the order deal.II, igacontact (spline rule), igacontact
# (spline rule, the element loop: solver.formation=elements), igacontact (Gauss rule), so that
# slow drifts of the machine fall on every code alike (igacontact's tangent is formed row by
# row, solver.formation=sum_factorized, unless the code's name says "elements"):
#   deal.II:    build-peers/dealii_assembly P DOFS --reps R (benchmarks/peers/dealii_assembly.cpp;
#               FE_Q(p) vector, MappingQ(p), QGauss(p + 1), one thread);
#   igacontact: build/bin/igacontact run examples/lame_cylinder.yaml --quiet --output TMP
#               --set 'bodies.0.refine.degree_elevate=[p-2,p-1]' (the geometry is degree (2, 1))
#               --set 'bodies.0.refine.subdivide=[NU,NV]' (NU ~ 2 NV, dofs 2 (NU + p)(NV + p)
#               nearest DOFS, checked against `igacontact check`) --set solver.quadrature=spline|gauss
#               --set solver.linear.method=cg --set output.samples_per_element=1
#               (the last two only shorten the run; they do not touch stage 2), reading
#               summary.json: dofs and timings.
# Columns (medians over the pairs, microseconds per dof):
#   set-up + assembly: deal.II setup_s + assembly_s (distribute_dofs, sparsity pattern,
#     SparseMatrix::reinit; matrix = 0 and the cell loop with the adds);
#     igacontact "2.1) Assembly: graph" + "2.2) Assembly: element loop" (2.2 contains
#     "2.3) Assembly: fillComplete + export" and the allocation of the matrix values).
#   element loop: deal.II assembly_s; igacontact "2.2) Assembly: element loop".
#   igacontact's "2b) Tangent: K + K_c, Dirichlet" (the copy into the tangent and the Dirichlet
#     elimination; deal.II's program has no counterpart) is printed in its own column.
# With --dealii-reps 1 (the default) deal.II assembles once per process, cold, as igacontact
# does; with R > 1 its figures are the in-process medians of R repetitions (warm caches and
# allocator: its set-up falls several times).
#
# Usage: benchmarks/peers/compare_assembly.sh [--dofs N] [--pairs N] [--degrees "2 3 4 5"]
#            [--dealii-reps R] [--dealii-mapping q|cache] [--jsonl FILE]
# Needs build/bin/igacontact (used as built) and deal.II 9.4 (Debian libdeal.ii-dev); builds
# build-peers/ (nice, -j1) when dealii_assembly is missing. Runs one process at a time.
set -euo pipefail

DOFS=1e5
PAIRS=3
DEGREES="2 3 4 5"
REPS=1
MAPPING=q
JSONL=
while [ $# -gt 0 ]; do
  case "$1" in
    --dofs) DOFS=$2; shift 2 ;;
    --pairs) PAIRS=$2; shift 2 ;;
    --degrees) DEGREES=$2; shift 2 ;;
    --dealii-reps) REPS=$2; shift 2 ;;
    --dealii-mapping) MAPPING=$2; shift 2 ;;
    --jsonl) JSONL=$2; shift 2 ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | sed 's/^# \{0,1\}//' | head -n -1; exit 0 ;;
    *) echo "compare_assembly.sh: unknown argument $1 (--help)" >&2; exit 2 ;;
  esac
done

ROOT=$(cd "$(dirname "$0")/../.." && pwd)
PY=/usr/bin/python3
IGA=$ROOT/build/bin/igacontact
YAML=$ROOT/examples/lame_cylinder.yaml
[ -x "$IGA" ] || { echo "compare_assembly.sh: $IGA not built" >&2; exit 1; }
DEAL=$("$ROOT/benchmarks/peers/build_peers.sh" dealii_assembly)

TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
RESULTS=${JSONL:-$TMP/results.jsonl}
: > "$RESULTS"

for p in $DEGREES; do
  # igacontact: subdivide [NU, NV], NU in 2 NV + {-1, 0, 1}, dofs 2 (NU + p)(NV + p) nearest DOFS
  read -r NU NV < <("$PY" -c "
p, t = $p, float('$DOFS')
best = min(((abs(2 * (nu + p) * (nv + p) - t), nu, nv) for nv in range(1, 2000)
            for nu in (2 * nv - 1, 2 * nv, 2 * nv + 1) if nu >= 1), key=lambda x: x[0])
print(best[1], best[2])")
  SETS=(--set "bodies.0.refine.degree_elevate=[$((p - 2)),$((p - 1))]" --set "bodies.0.refine.subdivide=[$NU,$NV]"
        --set solver.linear.method=cg --set output.samples_per_element=1)
  CHECK=$(nice "$IGA" check "$YAML" "${SETS[@]}")
  IGA_DOFS=$(sed -n 's/.*total \([0-9]*\) dofs.*/\1/p' <<<"$CHECK")
  echo "p = $p: igacontact ${NU} x ${NV} elements, $IGA_DOFS dofs (igacontact check)" >&2
  for ((k = 1; k <= PAIRS; k++)); do
    # A: deal.II
    nice "$DEAL" "$p" "$DOFS" --reps "$REPS" --mapping "$MAPPING" > "$TMP/dealii.json"
    "$PY" - "$TMP/dealii.json" "$p" "$k" >> "$RESULTS" <<'EOF'
import json, sys
d = json.loads(open(sys.argv[1]).read())
if d["check"] != "pass":
    sys.exit("deal.II rigid-motion check failed: %s" % d)
print(json.dumps({"p": int(sys.argv[2]), "pair": int(sys.argv[3]), "code": "deal.II", "dofs": d["dofs"],
                  "elements": d["cells"], "points": d["quadrature_points"],
                  "setup_assembly_s": d["setup_s"] + d["assembly_s"], "element_loop_s": d["assembly_s"],
                  "tangent_s": None}))
EOF
    # B: igacontact, spline rule (rows, then elements), then Gauss (rows)
    for variant in "spline sum_factorized" "spline elements" "gauss sum_factorized"; do
      read -r rule formation <<< "$variant"
      name=$rule
      [ "$formation" = elements ] && name="$rule elements"
      rm -rf "$TMP/out"
      nice "$IGA" run "$YAML" --quiet --output "$TMP/out" "${SETS[@]}" --set "solver.quadrature=$rule" \
        --set "solver.formation=$formation"
      "$PY" - "$TMP/out/summary.json" "$p" "$k" "$name" "$NU" "$NV" "$IGA_DOFS" >> "$RESULTS" <<'EOF'
import json, sys
d = json.load(open(sys.argv[1]))
if d["dofs"] != int(sys.argv[7]):
    sys.exit("igacontact run has %s dofs, check said %s" % (d["dofs"], sys.argv[7]))
t = d["timings"]
need = ["2.1) Assembly: graph", "2.2) Assembly: element loop", "2b) Tangent: K + K_c, Dirichlet"]
missing = [k for k in need if k not in t]
if missing:
    sys.exit("summary.json timings lack %s (keys: %s)" % (missing, sorted(t)))
print(json.dumps({"p": int(sys.argv[2]), "pair": int(sys.argv[3]), "code": "igacontact " + sys.argv[4],
                  "dofs": d["dofs"], "elements": int(sys.argv[5]) * int(sys.argv[6]),
                  "points": d["quadrature"]["points"],
                  "setup_assembly_s": t["2.1) Assembly: graph"] + t["2.2) Assembly: element loop"],
                  "element_loop_s": t["2.2) Assembly: element loop"],
                  "tangent_s": t["2b) Tangent: K + K_c, Dirichlet"]}))
EOF
    done
  done
done

"$PY" - "$RESULTS" "$PAIRS" "$REPS" "$MAPPING" <<'EOF'
import json, statistics, sys
rows = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
pairs, reps, mapping = sys.argv[2], int(sys.argv[3]), sys.argv[4]
med = statistics.median
print("Medians over %s pair(s); us per dof; deal.II: MappingQ%s, %s." % (
    pairs, "Cache" if mapping == "cache" else "",
    "one cold assembly per process" if reps == 1 else "in-process median of %d repetitions" % reps))
print()
print("| p | code | dofs | elements | quadrature points | set-up + assembly (us/dof) | element loop (us/dof) "
      "| element loop / deal.II's | 2b tangent + Dirichlet (us/dof) |")
print("|---|---|---|---|---|---|---|---|---|")
order = ["deal.II", "igacontact spline", "igacontact spline elements", "igacontact gauss"]
for p in sorted({r["p"] for r in rows}):
    ref = None
    for code in order:
        rs = [r for r in rows if r["p"] == p and r["code"] == code]
        if not rs:
            continue
        n = rs[0]["dofs"]
        sa = med([1e6 * r["setup_assembly_s"] / r["dofs"] for r in rs])
        el = med([1e6 * r["element_loop_s"] / r["dofs"] for r in rs])
        if code == "deal.II":
            ref = el
        tg = "" if rs[0]["tangent_s"] is None else "%.3f" % med([1e6 * r["tangent_s"] / r["dofs"] for r in rs])
        print("| %d | %s | %s | %s | %s | %.3f | %.3f | %s | %s |" % (
            p, code, format(n, ","), format(rs[0]["elements"], ","), format(rs[0]["points"], ","), sa, el,
            "%.2f" % (el / ref) if ref else "", tg))
EOF
