# Checks a rational Bezier .vtu of igacontact (io/vtk.hpp) with ParaView's own reader and
# cell evaluation. Run with pvpython (no display needed):
#     pvpython tests/paraview/check_bezier.py FILE.vtu [--body 0 --center 0 0 --radii 1 2]
# - every cell is VTK_BEZIER_QUADRILATERAL (77); the arrays and their component counts;
#   RationalWeights / HigherOrderDegrees are the attributes VTK's Bezier cells read;
# - the circle test: points of the inner (eta = 0) and outer (eta = 1) sides of the quarter
#   annulus `--body`, evaluated by vtkGenericCell::EvaluateLocation (rational, in VTK's point
#   order), lie on the circles to 1e-12: a wrong point order or ignored weights fails this;
# - Warp By Vector moves every cell by the displacement VTK interpolates in the same cell;
# - Tessellate and Extract Surface (nonlinear subdivision) turn the cells into triangles whose
#   points on body --body stay inside the annulus (to single precision: both filters write
#   float32 points).
# Exit status 0 when all pass, 1 otherwise (each failure printed).
import argparse
import math
import sys

from paraview.simple import (ExtractSurface, Tessellate, WarpByVector, XMLUnstructuredGridReader)
from paraview import servermanager as sm
from vtkmodules.vtkCommonCore import reference
from vtkmodules.vtkCommonDataModel import vtkGenericCell

ap = argparse.ArgumentParser()
ap.add_argument("vtu")
ap.add_argument("--body", type=int, default=0, help="index of the quarter-annulus body")
ap.add_argument("--center", type=float, nargs=2, default=[0.0, 0.0])
ap.add_argument("--radii", type=float, nargs=2, default=[1.0, 2.0], help="inner (eta = 0) and outer (eta = 1)")
ap.add_argument("--tol", type=float, default=1e-12)
args = ap.parse_args()

failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAIL:", what)


reader = XMLUnstructuredGridReader(FileName=[args.vtu])
reader.UpdatePipeline()
grid = sm.Fetch(reader)
nc, npt = grid.GetNumberOfCells(), grid.GetNumberOfPoints()
check(nc > 0 and npt > 0, "cells and points read (%d cells, %d points)" % (nc, npt))
check(all(grid.GetCellType(c) == 77 for c in range(nc)), "all cells VTK_BEZIER_QUADRILATERAL (77)")

pd, cd, fd = grid.GetPointData(), grid.GetCellData(), grid.GetFieldData()
for name, n in [("RationalWeights", 1), ("displacement", 3), ("stress", 6), ("von_mises", 1)]:
    a = pd.GetArray(name)
    check(a is not None and a.GetNumberOfComponents() == n and a.GetNumberOfTuples() == npt,
          "point array %s with %d components" % (name, n))
for name, n in [("HigherOrderDegrees", 3), ("body", 1), ("element", 1), ("element_ij", 2), ("knot_span", 2),
                ("parametric_range", 4)]:
    a = cd.GetArray(name)
    check(a is not None and a.GetNumberOfComponents() == n and a.GetNumberOfTuples() == nc,
          "cell array %s with %d components" % (name, n))
check(pd.GetRationalWeights() is not None, "RationalWeights is the point data's rational-weights attribute")
check(cd.GetHigherOrderDegrees() is not None, "HigherOrderDegrees is the cell data's degrees attribute")
check(pd.GetVectors() is not None and pd.GetVectors().GetName() == "displacement", "displacement is the vectors attribute")
check(pd.GetTensors() is not None and pd.GetTensors().GetName() == "stress", "stress is the tensors attribute")
tv = fd.GetArray("TimeValue")
check(tv is not None and tv.GetNumberOfTuples() == 1, "field data TimeValue")
rid = fd.GetAbstractArray("run_id")
check(rid is not None and rid.GetNumberOfTuples() == 1 and len(rid.GetValue(0)) > 0, "field data run_id (string)")
if failures:
    sys.exit(1)
print("read: %d cells, %d points, TimeValue %g, run_id %r" % (nc, npt, tv.GetValue(0), rid.GetValue(0)))

# circle test through VTK's own evaluation of the Bezier cell
body, rng = cd.GetArray("body"), cd.GetArray("parametric_range")
cx, cy = args.center
cell = vtkGenericCell()
worst, evaluated = 0.0, 0
for c in range(nc):
    if int(body.GetTuple1(c)) != args.body:
        continue
    r = rng.GetTuple4(c)
    grid.GetCell(c, cell)
    w = [0.0] * cell.GetNumberOfPoints()
    for t1, radius in ((0.0, args.radii[0]), (1.0, args.radii[1])):
        if (t1 == 0.0 and r[2] != 0.0) or (t1 == 1.0 and r[3] != 1.0):
            continue
        for q in range(11):
            x = [0.0, 0.0, 0.0]
            cell.EvaluateLocation(reference(0), [q / 10.0, t1, 0.0], x, w)
            worst = max(worst, abs(math.hypot(x[0] - cx, x[1] - cy) - radius))
            evaluated += 1
check(evaluated > 0, "points of body %d on its circular sides evaluated" % args.body)
check(worst <= args.tol, "circle test: largest distance from the circles %.3e <= %.0e" % (worst, args.tol))
print("circle test: %d points, largest |r - R| = %.3e" % (evaluated, worst))

# Warp By Vector: the warped cell at (s, t) = the reference cell + VTK's interpolated displacement
warp = WarpByVector(Input=reader, Vectors=["POINTS", "displacement"], ScaleFactor=1.0)
warp.UpdatePipeline()
wgrid = sm.Fetch(warp)
check(wgrid.GetNumberOfCells() == nc and wgrid.GetCellType(0) == 77, "Warp By Vector keeps the Bezier cells")
disp = pd.GetArray("displacement")
wcell = vtkGenericCell()
umax, werr = 0.0, 0.0
for c in range(0, nc, max(1, nc // 50)):
    grid.GetCell(c, cell)
    wgrid.GetCell(c, wcell)
    w = [0.0] * cell.GetNumberOfPoints()
    for s, t in ((0.3, 0.7), (1.0, 0.0), (0.5, 1.0)):
        x, xw = [0.0] * 3, [0.0] * 3
        cell.EvaluateLocation(reference(0), [s, t, 0.0], x, w)
        u = [sum(w[k] * disp.GetComponent(cell.GetPointId(k), d) for k in range(len(w))) for d in range(3)]
        wcell.EvaluateLocation(reference(0), [s, t, 0.0], xw, w)
        umax = max(umax, math.hypot(u[0], u[1]))
        werr = max(werr, max(abs(xw[d] - x[d] - u[d]) for d in range(3)))
check(werr <= 1e-12 * max(1.0, umax), "warped cells = reference + displacement (%.3e)" % werr)
print("warp: largest displacement sampled %.4e, mismatch %.3e" % (umax, werr))

# Tessellate / Extract Surface with nonlinear subdivision: triangles, inside the annulus
for name, make in (("Tessellate", lambda src: Tessellate(Input=src, ChordError=1e-4, MaximumNumberofSubdivisions=4)),
                   ("ExtractSurface", lambda src: ExtractSurface(Input=src, NonlinearSubdivisionLevel=3))):
    f = make(reader)
    f.UpdatePipeline()
    out = sm.Fetch(f)
    npts = out.GetNumberOfPoints()
    check(out.GetNumberOfCells() > nc and npts > 0, "%s subdivides the cells (%d cells)" % (name, out.GetNumberOfCells()))
    ob = out.GetPointData().GetArray("displacement")
    check(ob is not None and ob.GetNumberOfComponents() == 3, "%s passes the displacement on" % name)
    # points that belong to cells of the annulus body
    bodyc = out.GetCellData().GetArray("body")
    inside = 0.0
    if bodyc is not None:
        ids = set()
        for c in range(out.GetNumberOfCells()):
            if int(bodyc.GetTuple1(c)) == args.body:
                cc = out.GetCell(c)
                ids.update(cc.GetPointId(k) for k in range(cc.GetNumberOfPoints()))
        for i in ids:
            p = out.GetPoint(i)
            r = math.hypot(p[0] - cx, p[1] - cy)
            inside = max(inside, args.radii[0] - r, r - args.radii[1])
        # these filters store their points in single precision: 1e-6 relative
        tol = 1e-6 * args.radii[1] if out.GetPoints().GetDataType() == 10 else 1e-12
        check(inside <= tol, "%s points inside the annulus (%.3e outside, tolerance %.0e)" % (name, inside, tol))
    else:
        check(False, "%s passes the cell array body on" % name)
    # warped input through the same filter
    fw = make(warp)
    fw.UpdatePipeline()
    check(sm.Fetch(fw).GetNumberOfCells() > nc, "%s after Warp By Vector" % name)
    print("%s: %d cells, %d points (%s), largest distance outside the annulus %.2e" % (
        name, out.GetNumberOfCells(), npts, out.GetPoints().GetData().GetDataTypeAsString(), inside))

if failures:
    print("%d check(s) failed" % len(failures))
    sys.exit(1)
print("check_bezier: OK")
