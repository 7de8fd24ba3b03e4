#!/usr/bin/env bash
# compare_lame.sh: igacontact's whole run against deal.II's on the Lame cylinder, to a relative
# L2 displacement error below 5e-11 (issue 34's done-when: igacontact at most half of deal.II).
#
#   igacontact: build/bin/igacontact run examples/lame_cylinder.yaml --quiet --output TMP
#               --set 'bodies.0.refine.degree_elevate=[P-2,P-1]' --set 'bodies.0.refine.subdivide=[NU,NV]'
#               --set output.samples_per_element=1
#               (default p = 4 on [126, 42], 11,960 dofs, the fewest elements of aspect 3 below the
#               bound (error 4e-11); --iga-subdivide 192x64, 26,656 dofs, the filing's;
#               --iga-degree 5 --iga-subdivide 6x22, 594 dofs, the fewest of any aspect at p = 5
#               (4.2e-11); the solver auto picks; its L2 error is computed by the tests
#               AutoByDegree.LameAt..., build/bin/test_solver_choice, which solve the same
#               problems and print it)
#   deal.II:    build-peers/dealii_lame P DOFS|NTxNR (benchmarks/peers/dealii_lame.cpp: FE_Q(P) vector,
#               MappingQ(P) on a polar manifold, UMFPACK, one thread; its JSON line has the error);
#               default P = 4 and 47,000 dofs (47,306: error 4.2e-11, the fewest dofs at P = 4
#               below 5e-11 in steps of a few thousand at NT ~ 2 NR); --dealii-dofs NTxNR names
#               the cells around and through the wall instead (benchmarks/peers/fewest_dealii.py
#               finds the fewest dofs per degree over every aspect)
# Both are whole processes timed from outside by benchmarks/peers/time_pairs.py, in turn (igacontact, deal.II,
# igacontact, ...: --pairs pairs), so the ratio is taken pair by pair on the same machine state.
#
# Usage: benchmarks/peers/compare_lame.sh [--pairs N] [--iga-degree 4|5] [--iga-subdivide NUxNV]
#            [--dealii-degree P] [--dealii-dofs N|NTxNR]
# Needs build/bin/igacontact and build/bin/test_solver_choice (the main build), deal.II 9.4
# (Debian libdeal.ii-dev; builds build-peers/ when dealii_lame is missing).
set -euo pipefail

PAIRS=5
IGA_P=4
IGA_MESH=126x42
DEAL_P=4
DEAL_DOFS=47000
while [ $# -gt 0 ]; do
  case "$1" in
    --pairs) PAIRS=$2; shift 2 ;;
    --iga-degree) IGA_P=$2; shift 2 ;;
    --iga-subdivide) IGA_MESH=$2; shift 2 ;;
    --dealii-degree) DEAL_P=$2; shift 2 ;;
    --dealii-dofs) DEAL_DOFS=$2; shift 2 ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | sed 's/^# \{0,1\}//' | head -n -1; exit 0 ;;
    *) echo "compare_lame.sh: unknown argument $1 (--help)" >&2; exit 2 ;;
  esac
done

ROOT=$(cd "$(dirname "$0")/../.." && pwd)
IGA=$ROOT/build/bin/igacontact
TEST=$ROOT/build/bin/test_solver_choice
for f in "$IGA" "$TEST"; do [ -x "$f" ] || { echo "compare_lame.sh: $f not built" >&2; exit 1; }; done
DEAL=$("$ROOT/benchmarks/peers/build_peers.sh" dealii_lame)
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT

# the errors (each code once, outside the timings)
IGA_LINE=$("$TEST" --gtest_filter='AutoByDegree.LameAt*' | grep "^lame_p${IGA_P}_$IGA_MESH " || true)
[ -n "$IGA_LINE" ] || { echo "compare_lame.sh: no test prints the error of p = $IGA_P on [$IGA_MESH] (p 4: 126x42, 192x64; p 5: 6x22)" >&2; exit 2; }
DEAL_LINE=$("$DEAL" "$DEAL_P" "$DEAL_DOFS")
echo "igacontact: $IGA_LINE"
echo "deal.II:    $DEAL_LINE"
/usr/bin/python3 - "$IGA_LINE" "$DEAL_LINE" <<'PY'
import json, sys
iga = float(sys.argv[1].split("l2_error ")[1].split()[0])
deal = json.loads(sys.argv[2])["l2_error"]
for name, e in (("igacontact", iga), ("deal.II", deal)):
    if not e <= 5e-11:
        sys.exit("%s: relative L2 error %.3g is above 5e-11; choose more dofs" % (name, e))
PY

# the whole processes, in turn: A = igacontact, B = deal.II
"$ROOT/benchmarks/peers/time_pairs.py" --pairs "$PAIRS" \
  "$IGA run $ROOT/examples/lame_cylinder.yaml --quiet --output $TMP/out --set bodies.0.refine.degree_elevate=[$((IGA_P - 2)),$((IGA_P - 1))] --set bodies.0.refine.subdivide=[${IGA_MESH/x/,}] --set output.samples_per_element=1" \
  "$DEAL $DEAL_P $DEAL_DOFS"
