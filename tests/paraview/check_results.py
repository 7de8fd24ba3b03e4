# Checks an igacontact output directory with ParaView (pvpython), as a user would open it:
#     pvpython tests/paraview/check_results.py OUTDIR [--max-displacement X] [--max-pressure K=X ...]
# OUTDIR holds result.xdmf (bodies), result_control_nets.xdmf, result_contact.xdmf + result.h5
# (each a temporal collection of spatial collections, see docs/paraview-xdmf-notes.md), result.pvd + result_<step>.vtu (rational Bezier cells,
# io/vtk.hpp) and summary.json.
#
# Each reader runs in a pvpython child process of its own (all its files in that one) (a crashing reader cannot take the
# check down with it, and its stderr is its own): Xdmf3ReaderS, Xdmf3ReaderT and the legacy
# XDMFReader on each of the three .xdmf (result.xdmf must hold bodies only), PVDReader on
# result.pvd. For each:
#   - nothing at all on stderr (ParaView's reader errors and warnings, HDF5 diagnostics);
#   - time steps: the same in every reader, increasing, the last = summary["load_factor"];
#   - at every time step, the arrays and component counts of every block: bodies
#     (displacement 3, stress 6 (9 in the legacy reader, which expands Tensor6; its components are not
#     written again as scalars), von_mises 1; cell data element 1), control nets (control_displacement 3), contact
#     pairs (pressure 1, gap 1, at least one 3-component vector); the Bezier .vtu
#     (RationalWeights 1, displacement 3, stress 6, von_mises 1, HigherOrderDegrees 3);
#   - Warp By Vector (displacement) at the last step runs and keeps every point;
#   - at the last step: the largest |displacement| of the sampled grids equals
#     summary["max_displacement"] (relative --rtol), and the largest contact pressure of
#     contact_<k> equals summary["contact"][k]["max_pressure"]. In the .vtu the displacement
#     array holds Bezier coefficients: the cell corners interpolate (largest at corners <= the
#     summary's value) and the coefficients bound the field (largest >= the summary's value).
#     Command-line values replace the summary's.
# 3-D (a run whose summary lists no result.xdmf): no result.xdmf; the control nets are hexahedra
# (VTK_HEXAHEDRON); result.pvd holds Bezier faces (77) or hexahedra (79) with the 3-D cell arrays
# face, element_ij 3, knot_span 3, parametric_range 6; the summary's largest displacement (at the
# cells' evaluation points) between the cell corners' and the coefficients' largest.
# Exit status 0 when all pass, 1 otherwise (each failure printed).
import argparse
import json
import math
import os
import re
import shutil
import subprocess
import sys

HERE = os.path.abspath(__file__)


# ----------------------------------------------------------------------------------------
# child: one reader, prints one line "RESULT <json>"
def child(kind, path):
    from paraview.simple import PVDReader, WarpByVector, XDMFReader, Xdmf3ReaderS, Xdmf3ReaderT
    from paraview import servermanager as sm
    from vtkmodules.vtkCommonDataModel import vtkCompositeDataSet

    make = {"Xdmf3ReaderS": lambda: Xdmf3ReaderS(FileName=[path]),
            "Xdmf3ReaderT": lambda: Xdmf3ReaderT(FileName=[path]),
            "XDMFReader": lambda: XDMFReader(FileNames=[path]),
            "PVDReader": lambda: PVDReader(FileName=path)}[kind]
    reader = make()
    reader.UpdatePipelineInformation()
    tv = reader.TimestepValues   # a list, or a single float where there is one time step
    times = ([float(t) for t in tv] if hasattr(tv, "__len__") else [float(tv)]) if tv is not None else []

    def leaves(d):
        out = []
        if d is None:
            return out
        if d.IsA("vtkCompositeDataSet"):
            it = d.NewIterator()
            it.InitTraversal()
            while not it.IsDoneWithTraversal():
                md = it.GetCurrentMetaData()
                name = md.Get(vtkCompositeDataSet.NAME()) if md is not None and md.Has(vtkCompositeDataSet.NAME()) else None
                out.append((name, it.GetCurrentDataObject()))
                it.GoToNextItem()
        else:
            out.append((None, d))
        return out

    def arrays(dsa):
        return {dsa.GetArrayName(i): dsa.GetArray(i).GetNumberOfComponents() for i in range(dsa.GetNumberOfArrays())
                if dsa.GetArray(i) is not None}

    def max_norm(a, ids=None):
        m = 0.0
        for i in (range(a.GetNumberOfTuples()) if ids is None else ids):
            t = a.GetTuple(i)
            m = max(m, math.sqrt(sum(v * v for v in t)))
        return m

    steps = []
    for t in times or [None]:
        reader.UpdatePipeline(t) if t is not None else reader.UpdatePipeline()
        blocks = []
        for name, ds in leaves(sm.Fetch(reader)):
            b = {"name": re.sub(r"\[\d+\]$", "", name) if name else None, "raw_name": name,
                 "class": ds.GetClassName(), "points": ds.GetNumberOfPoints(), "cells": ds.GetNumberOfCells(),
                 "point_arrays": arrays(ds.GetPointData()), "cell_arrays": arrays(ds.GetCellData()),
                 "cell_types": sorted({ds.GetCellType(c) for c in range(ds.GetNumberOfCells())})}
            pd = ds.GetPointData()
            if pd.GetArray("displacement") is not None:
                b["max_displacement"] = max_norm(pd.GetArray("displacement"))
                if ds.GetNumberOfCells() and ds.GetCellType(0) in (77, 79):   # Bezier: corners interpolate
                    corners = set()
                    for c in range(ds.GetNumberOfCells()):
                        ids = ds.GetCell(c).GetPointIds()
                        corners.update(ids.GetId(k) for k in range(4 if ds.GetCellType(c) == 77 else 8))
                    b["max_displacement_corners"] = max_norm(pd.GetArray("displacement"), sorted(corners))
            if pd.GetArray("pressure") is not None:
                b["max_pressure"] = max(pd.GetArray("pressure").GetTuple1(i) for i in range(ds.GetNumberOfPoints()))
            blocks.append(b)
        steps.append({"time": t, "blocks": blocks})

    vec = "control_displacement" if path.endswith("_control_nets.xdmf") else "displacement"
    warp = WarpByVector(Input=reader, Vectors=["POINTS", vec], ScaleFactor=1.0)
    warp.UpdatePipeline(times[-1] if times else None)
    warped = sum(ds.GetNumberOfPoints() for _, ds in leaves(sm.Fetch(warp)))
    print("RESULT " + json.dumps({"times": times, "steps": steps, "warped_points": warped}))


# ----------------------------------------------------------------------------------------
def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("outdir")
    ap.add_argument("--max-displacement", type=float, default=None)
    ap.add_argument("--max-pressure", action="append", default=[], metavar="K=X")
    ap.add_argument("--rtol", type=float, default=1e-9)
    args = ap.parse_args()

    failures = []

    def check(ok, what):
        if not ok:
            failures.append(what)
            print("FAIL:", what)
        return ok

    summary = json.load(open(os.path.join(args.outdir, "summary.json")))
    want_disp = args.max_displacement if args.max_displacement is not None else summary.get("max_displacement")
    want_p = {k: c.get("max_pressure") for k, c in enumerate(summary.get("contact", []))}
    for kv in args.max_pressure:
        k, v = kv.split("=")
        want_p[int(k)] = float(v)
    check(want_disp is not None, "a largest displacement to compare (summary max_displacement or --max-displacement)")
    ncontact = len(want_p)
    friction_fields = any("tangential_force" in c for c in summary.get("contact", []))

    # 3-D (issue 35, docs/paraview.md): no sampled grid (no result.xdmf); the control nets are
    # hexahedra; result.pvd holds Bezier faces (77) or hexahedra (79) with 3-D cell arrays
    three_d = "result.xdmf" not in summary.get("files", {}) and "result.pvd" in summary.get("files", {})
    pvpython = shutil.which("pvpython") or sys.executable
    close = lambda a, b: abs(a - b) <= args.rtol * max(abs(a), abs(b), 1e-300)
    all_times = {}
    xdmfs = ("result.xdmf", "result_control_nets.xdmf", "result_contact.xdmf")
    if three_d:
        xdmfs = xdmfs[1:]
        check(not os.path.exists(os.path.join(args.outdir, "result.xdmf")), "3-D: no result.xdmf (no sampled grid)")
    for kind, fnames in (("Xdmf3ReaderS", xdmfs), ("Xdmf3ReaderT", xdmfs), ("XDMFReader", xdmfs), ("PVDReader", ("result.pvd",))):
        # the files of one reader (one pvpython): their steps merged (the same times in each)
        r, tag = None, "%s(%s)" % (kind, ", ".join(fnames))
        paths = [os.path.join(args.outdir, f) for f in fnames]
        if not all(check(os.path.isfile(p), "%s exists" % p) for p in paths):
            continue
        p = subprocess.run([pvpython, HERE, "--child", kind] + paths, capture_output=True, text=True, timeout=600)
        check(p.returncode == 0, "%s exits 0 (got %d)" % (tag, p.returncode))
        check(p.stderr.strip() == "", "%s writes nothing on stderr; it wrote:\n%s" % (tag, p.stderr.strip()[:3000]))
        lines = [l for l in p.stdout.splitlines() if l.startswith("RESULT ")]
        if not check(len(lines) == len(fnames), "%s reported a result per file" % tag):
            continue
        for fname, line in zip(fnames, lines):
            rf = json.loads(line[7:])
            ftag = "%s(%s)" % (kind, fname)
            if fname == "result.xdmf":
                # only bodies: Xdmf3ReaderS appends the grids of a file into one data set for
                # drawing and keeps only the arrays all of them have (grey bodies otherwise)
                for st in rf["steps"]:
                    odd = [b["raw_name"] for b in st["blocks"] if "stress" not in b["point_arrays"]]
                    check(not odd, "%s t=%r: every grid is a body with stress (not: %s)" % (ftag, st["time"], odd))
            if r is None:
                r = rf
                continue
            check(rf["times"] == r["times"], "%s: the times of result.xdmf %s" % (ftag, r["times"]))
            for a, b in zip(r["steps"], rf["steps"]):
                a["blocks"] += b["blocks"]
            r["warped_points"] += rf["warped_points"]
        if r is None:
            continue
        times = r["times"]
        all_times[kind] = times
        check(len(times) >= 1 and all(a < b for a, b in zip(times, times[1:])), "%s: increasing time steps %s" % (tag, times))
        if "load_factor" in summary and times:
            check(close(times[-1], summary["load_factor"]), "%s: last time %r = load factor %r" % (tag, times[-1], summary["load_factor"]))
        named = kind in ("Xdmf3ReaderT", "XDMFReader")
        for st in r["steps"]:
            t = st["time"]
            bodies = [b for b in st["blocks"] if "stress" in b["point_arrays"]]
            nets = [b for b in st["blocks"] if "control_displacement" in b["point_arrays"]]
            contacts = [b for b in st["blocks"] if "pressure" in b["point_arrays"]]
            check(len(bodies) >= 1 or (three_d and kind != "PVDReader"), "%s t=%r: at least one body" % (tag, t))
            for b in bodies:
                pa, ca = b["point_arrays"], b["cell_arrays"]
                what = "%s t=%r block %s" % (tag, t, b["raw_name"])
                check(b["points"] > 0 and b["cells"] > 0, what + ": points and cells")
                check(pa.get("displacement") == 3, what + ": displacement with 3 components")
                if kind == "PVDReader":
                    for a, n in (("RationalWeights", 1), ("stress", 6), ("von_mises", 1)):
                        check(pa.get(a) == n, what + ": %s with %d components (%s)" % (a, n, pa.get(a)))
                    check(ca.get("HigherOrderDegrees") == 3, what + ": HigherOrderDegrees (3)")
                    if three_d:
                        check(set(b["cell_types"]) <= {77, 79} and b["cell_types"], what + ": 3-D Bezier cells (%s)" % b["cell_types"])
                        for a, n in (("face", 1), ("element_ij", 3), ("knot_span", 3), ("parametric_range", 6)):
                            check(ca.get(a) == n, what + ": 3-D cell array %s with %d components (%s)" % (a, n, ca.get(a)))
                    else:
                        check(b["cell_types"] == [77], what + ": Bezier quadrilaterals (%s)" % b["cell_types"])
                else:
                    check(pa.get("stress") == (9 if kind == "XDMFReader" else 6), what + ": stress tensor (%s)" % pa.get("stress"))
                    check(pa.get("von_mises") == 1, what + ": scalar von_mises")
                    for a in ("sxx", "syy", "sxy", "szz"):   # components of the tensor, not written twice
                        check(a not in pa, what + ": no scalar " + a + " beside the stress tensor")
                    check(ca.get("element") == 1, what + ": cell data element")
                    if named:
                        check(b["name"] is not None, what + ": named")
            if kind != "PVDReader":
                if three_d:
                    check(len(nets) >= 1, "%s t=%r: control nets (%d)" % (tag, t, len(nets)))
                else:
                    check(len(nets) == len(bodies), "%s t=%r: one control net per body (%d, %d)" % (tag, t, len(nets), len(bodies)))
                for b in nets:
                    check(b["points"] > 0 and b["cells"] > 0, "%s t=%r control net %s: points and cells" % (tag, t, b["raw_name"]))
                    check(b["cell_types"] == ([12] if three_d else [9]),
                          "%s t=%r control net %s: %s (%s)" % (tag, t, b["raw_name"], "hexahedra" if three_d else "quadrilaterals", b["cell_types"]))
                check(len(contacts) == ncontact, "%s t=%r: %d contact pairs (found %d)" % (tag, t, ncontact, len(contacts)))
                for b in contacts:
                    what = "%s t=%r block %s" % (tag, t, b["raw_name"])
                    check(b["points"] > 0 and b["cells"] == b["points"], what + ": one vertex cell per point")
                    check(b["point_arrays"].get("gap") == 1, what + ": scalar gap")
                    if friction_fields:   # outputs that carry friction's fields (every run since they came)
                        for a in ("tangential_traction", "slip", "state"):
                            check(b["point_arrays"].get(a) == 1, what + ": scalar " + a)
                    check(3 in b["point_arrays"].values(), what + ": a vector")
                    if named:
                        check(b["name"] is not None and re.fullmatch(r"contact_\d+", b["name"]) is not None, what + ": named contact_<k>")
        check(r["warped_points"] > 0, "%s: Warp By Vector output has points" % tag)

        last = r["steps"][-1]
        bodies = [b for b in last["blocks"] if "max_displacement" in b and "stress" in b["point_arrays"]]
        if want_disp is not None and bodies:
            if kind == "PVDReader":
                corners = max(b["max_displacement_corners"] for b in bodies if "max_displacement_corners" in b)
                coef = max(b["max_displacement"] for b in bodies)
                check(corners <= want_disp * (1 + args.rtol) and coef >= want_disp * (1 - args.rtol),
                      "%s: largest displacement at corners %.10g <= %.10g <= largest coefficient %.10g" % (tag, corners, want_disp, coef))
                print("%s: times %s, largest displacement: corners %.10g, coefficients %.10g (summary %.10g)" % (tag, times, corners, coef, want_disp))
            else:
                got = max(b["max_displacement"] for b in bodies)
                # the sampled grid is Float32: |u| from two rounded components (2 x 2^-24 relative each)
                f32 = max(args.rtol, 2.5e-7)
                check(abs(got - want_disp) <= f32 * max(abs(got), abs(want_disp), 1e-300),
                      "%s: largest displacement %.12g = %.12g (Float32)" % (tag, got, want_disp))
                print("%s: times %s, largest displacement %.12g (summary %.12g)" % (tag, times, got, want_disp))
        if kind != "PVDReader":
            contacts = [b for b in last["blocks"] if "max_pressure" in b]
            if named:
                for k, want in want_p.items():
                    got = [b["max_pressure"] for b in contacts if b["name"] == "contact_%d" % k]
                    check(len(got) == 1 and close(got[0], want), "%s: contact_%d largest pressure %s = %r" % (tag, k, got, want))
            else:   # Xdmf3ReaderS drops the names: compare the sets
                got = sorted(b["max_pressure"] for b in contacts)
                want = sorted(want_p.values())
                check(len(got) == len(want) and all(close(a, b) for a, b in zip(got, want)),
                      "%s: largest contact pressures %s = %s" % (tag, got, want))
    ts = list(all_times.values())
    check(all(len(t) == len(ts[0]) and all(close(a, b) for a, b in zip(t, ts[0])) for t in ts),
          "the same time steps in every reader: %s" % all_times)
    if failures:
        print("%d check(s) failed" % len(failures))
        sys.exit(1)
    print("check_results: OK")


if __name__ == "__main__":
    if len(sys.argv) >= 4 and sys.argv[1] == "--child":
        for path in sys.argv[3:]:
            child(sys.argv[2], path)
    else:
        main()
