#!/usr/bin/python3
# What scripts/plot draws, checked from a user's run (issue 33, items 8 and 11):
#     check_plot.py hertz OUTDIR PROBLEM.yaml   two cylinders: the Hertz parameters
#     check_plot.py default OUTDIR              the default example's two pictures
# hertz: `scripts/plot OUTDIR --print-hertz` gives R = 1/(1/R1 + 1/R2) and
#   E* = 1/((1 - nu1^2)/E1 + (1 - nu2^2)/E2) (plane strain) from the problem file's radii and
#   materials, P = twice the half model's contact force, a and p0 by the closed form (all to
#   1e-12); and the computed peak pressure is within 5 % of that p0 (the accuracy the Hertz
#   tests of test_contact ask of the wheel; measured -0.5 % here), while Hertz with the slave
#   radius alone (the old curve) is more than 10 % off (22 % here).
# default: contact_pressure_0.png: the x axis runs from left of the contact edge to the
#   symmetry axis x = 0 and no further (axes on the data); the pressure rises monotonically
#   towards the axis (no dip at the contact edge, as KTS had on this mesh: 4 drops, 7.2 %) and
#   stays within 3 % of p0 of Hertz for |x| < 0.8 a (mortar on this mesh: 2.4 %, the largest
#   near 0.85 a; the edge itself, where Hertz's slope is infinite and the penalty smooths, is
#   left out). deformed_syy.png: the whole view contains every
#   body (nothing cut off), a zoom panel on the contact zone, and >= 95 % of the coloured
#   pixels are viridis colours (within 12/255), a perceptually uniform map.
import csv
import json
import math
import os
import subprocess
import sys

import numpy as np
import yaml
from PIL import Image
from matplotlib import colormaps

HERE = os.path.dirname(os.path.abspath(__file__))
PLOT = os.path.join(HERE, "..", "..", "scripts", "plot")
fails = []


def check(ok, what):
    print(("ok:   " if ok else "FAIL: ") + what)
    if not ok:
        fails.append(what)


def contact_csv(d):
    rows = list(csv.DictReader(open(os.path.join(d, "contact_0.csv"))))
    c = {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}
    keep = np.isfinite(c["gap"])
    return {k: v[keep] for k, v in c.items()}


def hertz(d, problem):
    out = subprocess.run([PLOT, d, "--print-hertz"], capture_output=True, text=True, check=True).stdout
    hz = json.loads(out.splitlines()[0])["hertz"]
    prob = yaml.safe_load(open(problem))
    s = json.load(open(os.path.join(d, "summary.json")))
    b = {x["name"]: x for x in prob["bodies"]}
    pair = s["contact"][0]
    R1 = b[pair["slave"]["body"]]["geometry"]["quarter_annulus"]["outer_radius"]
    R2 = b[pair["master"]["body"]]["geometry"]["quarter_annulus"]["outer_radius"]
    inv = sum((1 - b[n]["material"]["poisson_ratio"] ** 2) / b[n]["material"]["youngs_modulus"]
              for n in (pair["slave"]["body"], pair["master"]["body"]))
    R, Es, P = 1 / (1 / R1 + 1 / R2), 1 / inv, 2 * pair["normal_force"]
    a = math.sqrt(4 * P * R / (math.pi * Es))
    p0 = 2 * P / (math.pi * a)
    for k, want in (("R", R), ("Estar", Es), ("P", P), ("a", a), ("p0", p0)):
        check(abs(hz[k] - want) <= 1e-12 * abs(want), "plot's %s = %.10g, closed form %.10g" % (k, hz[k], want))
    pmax = pair["max_pressure"]
    check(abs(pmax / p0 - 1) < 0.05, "computed peak %.5g within 5 %% of Hertz p0 %.5g (%+.2f %%)" % (pmax, p0, 100 * (pmax / p0 - 1)))
    a1 = math.sqrt(4 * P * R1 / (math.pi * Es))
    p1 = 2 * P / (math.pi * a1)
    check(abs(pmax / p1 - 1) > 0.10, "Hertz with the slave radius alone is off: p0 %.5g (%+.1f %%)" % (p1, 100 * (pmax / p1 - 1)))


def default(d):
    subprocess.run([PLOT, d], capture_output=True, text=True, check=True)
    im = Image.open(os.path.join(d, "contact_pressure_0.png"))
    meta = json.loads(im.text["igacontact"])
    lo, hi = meta["xlim"]
    a, p0, xc = meta["hertz"]["a"], meta["hertz"]["p0"], meta["hertz"]["xc"]
    c = contact_csv(d)
    act = c["active"] > 0
    check(hi <= c["x"].max() + 1e-12 and hi >= c["x"].max() - 0.05 * a,
          "pressure picture: x axis ends at the data's end (the symmetry axis) %.4g (data to %.4g)" % (hi, c["x"].max()))
    edge = c["x"][act].min()
    check(edge - 0.6 * a <= lo < edge, "pressure picture: x axis starts just left of the contact edge (%.4g, edge %.4g, a %.4g)" % (lo, edge, a))
    o = np.argsort(c["x"])
    x, p = c["x"][o], c["pressure"][o]
    pa = p[p > 0]
    # no dip: near the axis Hertz's pressure is flat (zero slope) and the mortar pressure
    # interpolated at the segment points varies there by ~1e-5 p0 (the points on the axis
    # itself, 4e-6 p0 below the largest): a drop counts above 1e-4 p0, far below the dip of
    # the issue (several % at the contact edge)
    drops = np.diff(pa) < -1e-4 * p0
    check(not drops.any(), "pressure rises monotonically to the axis (%d drops)" % drops.sum())
    inner = np.abs(x - xc) < 0.8 * a
    dev = np.abs(p - p0 * np.sqrt(np.maximum(0, 1 - (x - xc) ** 2 / a ** 2)))[inner].max() / p0
    check(dev <= 0.03, "pressure within 3 %% of Hertz p0 for |x| < 0.8 a: %.2f %%" % (100 * dev))

    im = Image.open(os.path.join(d, "deformed_syy.png"))
    meta = json.loads(im.text["igacontact"])
    import h5py
    with h5py.File(os.path.join(d, "result.h5"), "r") as f:
        xy = np.concatenate([f["bodies"][b]["xyz"][()][:, :2] + f["bodies"][b]["displacement"][()][:, :2] for b in f["bodies"]])
    whole = meta["panels"][0]
    check(meta["panels"][0]["scale"] == 1.0, "whole view at true displacements (magnified, bodies in contact would overlap)")
    inside = (whole["xlim"][0] < xy[:, 0].min() and xy[:, 0].max() < whole["xlim"][1]
              and whole["ylim"][0] < xy[:, 1].min() and xy[:, 1].max() < whole["ylim"][1])
    check(inside, "whole view contains every body: x %s, y %s" % (whole["xlim"], whole["ylim"]))
    check(len(meta["panels"]) == 2 and meta["zoom"] is not None, "a zoom on the contact zone beside the whole")
    if meta["zoom"]:
        (zx0, zx1), (zy0, zy1) = meta["zoom"]
        check(zx0 < edge and zx1 >= xc - 1e-12 and zx1 - zx0 < 10 * a,
              "zoom [%.3g, %.3g] holds the contact zone [%.3g, %.3g] and is < 10 a wide" % (zx0, zx1, edge, xc))
    rgb = np.asarray(im.convert("RGB")).reshape(-1, 3).astype(float)
    coloured = rgb[(rgb.max(axis=1) - rgb.min(axis=1)) > 30]   # not white, black, grey
    vir = colormaps["viridis"](np.linspace(0, 1, 256))[:, :3] * 255
    sub = coloured[:: max(1, len(coloured) // 20000)]
    dist = np.sqrt(((sub[:, None, :] - vir[None, :, :]) ** 2).sum(-1)).min(axis=1)
    frac = float(np.mean(dist <= 12))
    # the red zoom frame is the only other colour drawn
    check(frac >= 0.95, "deformed picture: %.1f %% of the coloured pixels are viridis colours" % (100 * frac))


if sys.argv[1] == "hertz":
    hertz(sys.argv[2], sys.argv[3])
else:
    default(sys.argv[2])
print("check_plot: %s" % ("OK" if not fails else "%d failed" % len(fails)))
sys.exit(1 if fails else 0)
