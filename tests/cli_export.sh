#!/usr/bin/env bash
# igacontact export: the refined geometry in G+Smo XML and GeoPDEs text, read back as the
# geometry of a run, gives the run's answer again (the same spline space and control points);
# the files are the same from 1 and 2 ranks; an unusable output directory is bad input.
#   tests/cli_export.sh <igacontact> <examples dir> <mpiexec>
# MPI runs take one thread per rank (OMP_NUM_THREADS=1): 2 ranks x 1 thread fill 2 cores; with
# the OpenMP build more threads oversubscribe them and Kokkos warns on stderr.
set -eu
exe="$1"; ex="$2"; mpi="$3"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT

"$exe" export "$ex/lame_cylinder.yaml" --output "$tmp/geo" --quiet
for f in cylinder.xml cylinder.txt; do test -s "$tmp/geo/$f" || { echo "missing $f"; exit 1; }; done
ls "$tmp/geo" | grep -q '\.part$' && { echo "temporary file left behind"; exit 1; }
# Nothing but the geometry: no run output.
test ! -e "$tmp/geo/summary.json" || { echo "export wrote a run's summary"; exit 1; }

"$exe" run "$ex/lame_cylinder.yaml" --output "$tmp/a" --quiet
for f in xml txt; do
  "$exe" run "$ex/lame_cylinder.yaml" --output "$tmp/$f" --quiet \
      --set "bodies.0.geometry={file: $tmp/geo/cylinder.$f}" --set 'bodies.0.refine={}'
done
/usr/bin/python3 - "$tmp" <<'PY'
import json, sys
t = sys.argv[1]
s = {k: json.load(open("%s/%s/summary.json" % (t, k))) for k in ("a", "xml", "txt")}
ref = s["a"]["probes"]
for k in ("xml", "txt"):
    for p, q in zip(ref, s[k]["probes"]):
        for f in ("displacement", "stress"):
            scale = max(abs(v) for v in p[f])
            d = max(abs(a - b) for a, b in zip(p[f], q[f]))
            # the same discrete problem: equal to the linear solver's round-off
            assert d <= 1e-10 * scale, (k, f, p[f], q[f])
    assert s[k]["dofs"] == s["a"]["dofs"], (k, s[k]["dofs"])
print("export round trip: probes agree (G+Smo XML and GeoPDEs text)")
PY

# A multi-patch body with named boundaries: same bytes from 1 and 2 ranks.
"$exe" export "$ex/whole_wheel.yaml" --output "$tmp/w1" --quiet
env OMP_NUM_THREADS=1 "$mpi" -n 2 "$exe" export "$ex/whole_wheel.yaml" --output "$tmp/w2" --quiet
for f in wheel.xml wheel.txt block.xml block.txt; do cmp "$tmp/w1/$f" "$tmp/w2/$f"; done
grep -q '<boundary name="inner">' "$tmp/w1/wheel.xml"
grep -qx 'inner' "$tmp/w1/wheel.txt"

# A solid (3-D): the refined trivariate patch exported and read back gives the same probes.
solid="$ex/../tests/paraview/solid_cylinder.yaml"
"$exe" export "$solid" --output "$tmp/s_geo" --quiet
"$exe" run "$solid" --output "$tmp/s_a" --quiet
for f in xml txt; do
  "$exe" run "$solid" --output "$tmp/s_$f" --quiet \
      --set "bodies.0.geometry={file: $tmp/s_geo/cylinder.$f}" --set 'bodies.0.refine={}'
done
/usr/bin/python3 - "$tmp" <<'PY'
import json, sys
t = sys.argv[1]
s = {k: json.load(open("%s/s_%s/summary.json" % (t, k))) for k in ("a", "xml", "txt")}
for k in ("xml", "txt"):
    assert s[k]["dofs"] == s["a"]["dofs"], (k, s[k]["dofs"])
    for p, q in zip(s["a"]["probes"], s[k]["probes"]):
        assert len(p["displacement"]) == 3 and len(p["stress"]) == 6, p
        for f in ("displacement", "stress"):
            scale = max(abs(v) for v in p[f])
            d = max(abs(a - b) for a, b in zip(p[f], q[f]))
            assert d <= 1e-10 * scale, (k, f, p[f], q[f])
print("export round trip in 3-D: probes agree (G+Smo XML and GeoPDEs text)")
PY

# An output path that is a file: one line, exit 2.
touch "$tmp/file"
set +e
msg=$("$exe" export "$ex/lame_cylinder.yaml" --output "$tmp/file" 2>&1 >/dev/null); rc=$?
set -e
[ "$rc" = 2 ] || { echo "export into a file: exit $rc, expected 2"; exit 1; }
[ "$(printf '%s\n' "$msg" | wc -l)" = 1 ] || { echo "not one line: $msg"; exit 1; }
echo "$msg" | grep -q -- "--output" || { echo "message does not name the key: $msg"; exit 1; }
echo "export OK"
