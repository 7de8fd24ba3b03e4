#!/usr/bin/python3
# What a reader sees in a picture of scripts/pv-render (python3 + matplotlib + numpy):
#     check_picture.py PNG [--min-colours N] [--max-grey F] [--min-grey F]
# The body region is every pixel that differs from the background (the corner pixel's
# colour) and lies left of the colour bar (the rightmost 12 % of the width). Checks: at least
# N distinct colours there that are not grey (a uniformly grey body has none: its ~150
# distinct colours are greys blended into the background at its edges),
# and the fraction of grey pixels (max - min channel < 12 of 255: no colour map colour of
# Viridis or Cividis is that grey; the background is excluded) at most F (no control net,
# no grey body) or, with --min-grey, at least F (a control net drawn on purpose).
# Prints one line; exit status 0 when the checks pass, 1 otherwise.
import argparse
import sys

import matplotlib.image as mpimg
import numpy as np

ap = argparse.ArgumentParser()
ap.add_argument("png")
ap.add_argument("--min-colours", type=int, default=100)
ap.add_argument("--max-grey", type=float, default=None)
ap.add_argument("--min-grey", type=float, default=None)
a = ap.parse_args()
img = (mpimg.imread(a.png)[..., :3] * 255).round().astype(int)
h, w, _ = img.shape
region = img[:, : int(0.88 * w)]
bg = img[0, 0]
body = region[np.any(np.abs(region - bg) > 6, axis=-1)]
is_grey = body.max(axis=1) - body.min(axis=1) < 12
colours = len({tuple(p) for p in body[~is_grey]})
grey = float(np.mean(is_grey)) if len(body) else 1.0
print("%s: %d body pixels, %d distinct colours besides grey, grey fraction %.4f" % (a.png, len(body), colours, grey))
ok = len(body) > 0.02 * h * w and colours >= a.min_colours
if a.max_grey is not None:
    ok = ok and grey <= a.max_grey
if a.min_grey is not None:
    ok = ok and grey >= a.min_grey
sys.exit(0 if ok else 1)
