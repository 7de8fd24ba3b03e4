# The stress of result.pvd (rational Bezier cells) against the sampled stress of result.h5,
# as ParaView shows them (pvpython):
#     pvpython tests/paraview/check_vonmises.py OUTDIR [--tol 0.02]
# The .vtu's point arrays are Bezier coefficients, clamped per cell into the range of the
# cell's samples (io/vtk.hpp), so:
#   - every coefficient of von_mises >= 0 and <= the largest sampled von Mises, and every
#     stress component's coefficients within that component's sampled range (to 1e-12
#     relative): the colour bar's range is the data's, nothing outside it is drawn;
#   - the field ParaView evaluates (Tessellate, chord error 1e-5) reaches the sampled peak of
#     von Mises to --tol (default 2 %): the fit interpolates at every cell corner (sample
#     points) and at the (p+1)^2 fit points; a peak at an interior sample point is met to the
#     degree-p interpolation error, which clamping can only move towards the samples.
# Prints the figures; exit status 0 when all pass.
import argparse
import glob
import os
import sys

import h5py
import numpy as np
from paraview.simple import Tessellate, XMLUnstructuredGridReader
from paraview import servermanager as sm
from vtkmodules.util.numpy_support import vtk_to_numpy

ap = argparse.ArgumentParser()
ap.add_argument("outdir")
ap.add_argument("--tol", type=float, default=0.02)
a = ap.parse_args()
vtu = sorted(glob.glob(os.path.join(a.outdir, "result_*.vtu")))[-1]
with h5py.File(os.path.join(a.outdir, "result.h5"), "r") as f:
    # the sampled stress: one Float32 tensor per point (XX, YY, ZZ, XY, YZ, XZ), von Mises beside it
    st = np.concatenate([f["bodies"][b]["stress"][()] for b in f["bodies"]])
    sampled = {k: st[:, c].astype(float) for k, c in (("sxx", 0), ("syy", 1), ("szz", 2), ("sxy", 3))}
    sampled["von_mises"] = np.concatenate([f["bodies"][b]["von_mises"][()] for b in f["bodies"]]).astype(float)
r = XMLUnstructuredGridReader(FileName=[vtu])
r.UpdatePipeline()
pd = sm.Fetch(r).GetPointData()
coef = {"von_mises": vtk_to_numpy(pd.GetArray("von_mises"))}
st = vtk_to_numpy(pd.GetArray("stress"))
for k, c in (("sxx", 0), ("syy", 1), ("szz", 2), ("sxy", 3)):
    coef[k] = st[:, c]
t = Tessellate(Input=r, ChordError=1e-5, MaximumNumberofSubdivisions=4)
t.UpdatePipeline()
field = vtk_to_numpy(sm.Fetch(t).GetPointData().GetArray("von_mises"))
fails = []
for k in ("sxx", "syy", "szz", "sxy", "von_mises"):
    s, c = sampled[k], coef[k]
    eps = 2.5e-7 * np.abs(s).max()   # both sides are Float32 roundings of the same doubles
    ok = c.min() >= s.min() - eps and c.max() <= s.max() + eps
    print("%-9s sampled [%.6g, %.6g], .vtu coefficients [%.6g, %.6g]%s" % (k, s.min(), s.max(), c.min(), c.max(), "" if ok else "  FAIL"))
    if not ok:
        fails.append(k)
vm = sampled["von_mises"].max()
ratio = field.max() / vm
print("von_mises: .vtu coefficients min %.3g (>= 0), field through Tessellate [%.6g, %.6g] (%d points), peak / sampled peak %.5f (>= %.3f)"
      % (coef["von_mises"].min(), field.min(), field.max(), len(field), ratio, 1 - a.tol))
if coef["von_mises"].min() < 0 or field.min() < 0:
    fails.append("von_mises >= 0")
if not (1 - a.tol <= ratio <= 1 + 1e-6):
    fails.append("peak")
if fails:
    print("FAIL:", ", ".join(fails))
    sys.exit(1)
print("check_vonmises: OK")
