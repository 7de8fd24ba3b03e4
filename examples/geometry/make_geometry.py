#!/usr/bin/python3
"""Writes the example geometry files of this folder, in G+Smo XML and GeoPDEs v2.1 text.

    /usr/bin/python3 examples/geometry/make_geometry.py [output folder]

Exact NURBS: a 90-degree arc of degree 2 has the weights 1, sqrt(2)/2, 1 and its middle
control point where the end tangents meet; a 45-degree arc has cos(22.5 deg) in the middle.
Control points are listed with the first parametric index (xi) running fastest. G+Smo's
<coefs> are Euclidean (the weights sit in the basis); GeoPDEs' coordinate rows are homogeneous
(w x, w y), then a row of weights. Sides: 1 west (xi = 0), 2 east (xi = 1), 3 south (eta = 0),
4 north (eta = 1) in both formats. See docs/geometry-files.md.

  ring4          annulus r 1..2 about (0, 0), four patches from 0, 90, 180, 270 degrees
  wheel4         annulus r 5..10 about (0, 10), patches from 225, 315, 45, 135 degrees:
                 the bottom point (0, 0) is the middle of patch 0
  wheel4_joint   the same wheel with patches from 0, 90, 180, 270 degrees: (0, 0) is the
                 corner where patch 2 ends and patch 3 begins
  plate_with_hole  [0, 4]^2 minus the quarter disc r < 1, two patches split along the diagonal
  punch          half of a flat punch with rounded edges (radius 0.5), one patch: face, top,
                 axis and side named

Each annulus patch: degree [2, 1], xi counter-clockwise along the arc, eta from the inner to
the outer circle (south side inner, north side outer; named boundaries "inner", "outer").
"""
import math
import os
import sys

S = math.sqrt(0.5)  # cos 45 = sin 45 = sqrt(2)/2


def cos_sin(deg):
    """cos and sin of a multiple of 45 degrees, exactly as doubles."""
    k = deg // 45 % 8
    return [(1.0, 0.0), (S, S), (0.0, 1.0), (-S, S), (-1.0, 0.0), (-S, -S), (0.0, -1.0), (S, -S)][k]


class Patch:
    def __init__(self, degree, knots, cp):
        self.degree = degree  # [p_xi, p_eta]
        self.knots = knots    # [U_xi, U_eta]
        self.cp = cp          # [(x, y, w)], xi fastest
        n = [len(knots[d]) - degree[d] - 1 for d in range(2)]
        assert n[0] * n[1] == len(cp)


def quarter_annulus(centre, ri, ro, start):
    """Degree [2, 1]: xi counter-clockwise from angle `start` over 90 degrees, eta ri -> ro."""
    assert start % 45 == 0
    c, s = cos_sin(start)
    cp = []
    for r in (ri, ro):
        cp.append((centre[0] + r * c, centre[1] + r * s, 1.0))
        cp.append((centre[0] + r * (c - s), centre[1] + r * (s + c), S))
        cp.append((centre[0] - r * s, centre[1] + r * c, 1.0))
    return Patch([2, 1], [[0.0, 0.0, 0.0, 1.0, 1.0, 1.0], [0.0, 0.0, 1.0, 1.0]], cp)


def annulus4(centre, ri, ro, starts):
    """Four quarter annuli; patch k's east side meets patch k+1's west side (same direction)."""
    patches = [quarter_annulus(centre, ri, ro, a) for a in starts]
    interfaces = [((k, 2), ((k + 1) % 4, 1), False) for k in range(4)]
    inner = [(k, 3) for k in range(4)]
    outer = [(k, 4) for k in range(4)]
    return patches, interfaces, [("inner", inner), ("outer", outer)]


def plate_with_hole(R=1.0, L=4.0):
    """Two degree-2 patches; patch 0 between the x axis and the diagonal, patch 1 between the
    diagonal and the y axis. xi runs from the hole outwards, eta counter-clockwise (both
    right-handed). The radial direction is the straight blend of the arc and the square's side
    (a linear blend raised to degree 2: middle row = average, same weights)."""
    w = math.cos(math.pi / 8)   # cos 22.5 deg
    t = math.sqrt(2.0) - 1.0    # tan 22.5 deg
    q = R * S
    arcs = [[(R, 0.0), (R, R * t), (q, q)], [(q, q), (R * t, R), (0.0, R)]]
    sides = [[(L, 0.0), (L, L / 2), (L, L)], [(L, L), (L / 2, L), (0.0, L)]]
    ws = [1.0, w, 1.0]
    patches = []
    for arc, side in zip(arcs, sides):
        cp = []
        for j in range(3):           # eta: angular
            a, b = arc[j], side[j]
            for P in (a, ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2), b):   # xi: radial
                cp.append((P[0], P[1], ws[j]))
        patches.append(Patch([2, 2], [[0.0, 0.0, 0.0, 1.0, 1.0, 1.0]] * 2, cp))
    interfaces = [((0, 4), (1, 3), False)]   # the diagonal, both from the hole outwards
    named = [("hole", [(0, 1), (1, 1)]), ("bottom", [(0, 3)]), ("right", [(0, 2)]),
             ("top", [(1, 2)]), ("left", [(1, 4)])]
    return patches, interfaces, named


def rounded_punch(b=1.5, r=0.5, y0=4.0, h=1.0):
    """Half of a flat punch with rounded edges, one degree [2, 1] patch: the face (south side)
    runs flat from (0, y0) to (b - r, y0) and then round the exact quarter circle of radius r
    up to (b, y0 + r); the top (north side) is the straight line y = y0 + h. xi along the face,
    a double knot where the flat part meets the arc (the face stays tangent-continuous), knot
    placed so that the parameter runs at nearly even speed; eta from the face to the top."""
    a = (b - r) / (b - r + math.pi * r / 2)
    face = [(0.0, y0, 1.0), ((b - r) / 2, y0, 1.0), (b - r, y0, 1.0), (b, y0, S), (b, y0 + r, 1.0)]
    top = [(0.0, y0 + h), ((b - r) / 2, y0 + h), (b - r, y0 + h), (b - r / 2, y0 + h), (b, y0 + h)]
    cp = [f for f in face] + [(t[0], t[1], f[2]) for t, f in zip(top, face)]
    P = Patch([2, 1], [[0.0, 0.0, 0.0, a, a, 1.0, 1.0, 1.0], [0.0, 0.0, 1.0, 1.0]], cp)
    named = [("face", [(0, 3)]), ("top", [(0, 4)]), ("axis", [(0, 1)]), ("side", [(0, 2)])]
    return [P], [], named


def num(v):
    return repr(float(v))


def gismo_interface(a, b, reversed_):
    """G+Smo 2-D interface: patch side patch side, direction map (2), orientation flags (2)."""
    d1, d2 = (a[1] - 1) // 2, (b[1] - 1) // 2
    dmap, orient = [0, 0], [0, 0]
    dmap[d1], dmap[1 - d1] = d2, 1 - d2
    orient[d1] = int((a[1] - 1) % 2 == (b[1] - 1) % 2)
    orient[1 - d1] = int(not reversed_)
    return "%d %d %d %d %d %d %d %d" % (a[0], a[1], b[0], b[1], dmap[0], dmap[1], orient[0], orient[1])


def write_xml(path, title, patches, interfaces, named):
    out = ['<?xml version="1.0" encoding="UTF-8"?>',
           '<!--%s. Written by examples/geometry/make_geometry.py-->' % title, '<xml>']
    for k, P in enumerate(patches):
        rational = any(c[2] != 1.0 for c in P.cp)
        ind = "   " if rational else "  "
        out.append(' <Geometry type="%s" id="%d">' % ("TensorNurbs2" if rational else "TensorBSpline2", k))
        if rational:
            out.append('  <Basis type="TensorNurbsBasis2">')
        out.append(ind + '<Basis type="TensorBSplineBasis2">')
        for d in range(2):
            out.append(ind + ' <Basis type="BSplineBasis" index="%d">' % d)
            out.append(ind + '  <KnotVector degree="%d">%s</KnotVector>'
                       % (P.degree[d], " ".join(num(u) for u in P.knots[d])))
            out.append(ind + ' </Basis>')
        out.append(ind + '</Basis>')
        if rational:
            out.append('   <weights>' + " ".join(num(c[2]) for c in P.cp) + '</weights>')
            out.append('  </Basis>')
        out.append('  <coefs geoDim="2">')
        out += ["%s %s" % (num(c[0]), num(c[1])) for c in P.cp]
        out.append('</coefs>')
        out.append(' </Geometry>')
    out.append(' <MultiPatch parDim="2" id="%d">' % len(patches))
    out.append('  <patches type="id_range">0 %d</patches>' % (len(patches) - 1))
    if interfaces:
        out.append('  <interfaces>')
        out += [gismo_interface(a, b, r) for a, b, r in interfaces]
        out.append('</interfaces>')
    sides = []
    for _, s in named:
        sides += [x for x in s if x not in sides]
    out.append('  <boundary>')
    out += ["%d %d" % s for s in sides]
    out.append('</boundary>')
    for name, s in named:
        out.append('  <boundary name="%s">' % name)
        out += ["%d %d" % x for x in s]
        out.append('</boundary>')
    out.append(' </MultiPatch>')
    out.append('</xml>')
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def write_geopdes(path, title, patches, interfaces, named):
    out = ["# nurbs mesh v.2.1", "#", "# %s" % title,
           "# Written by examples/geometry/make_geometry.py: coordinates are homogeneous (w x, w y).",
           "#", "2 2 %d %d 0" % (len(patches), len(interfaces))]
    for k, P in enumerate(patches):
        n = [len(P.knots[d]) - P.degree[d] - 1 for d in range(2)]
        out.append("PATCH %d" % (k + 1))
        out.append("%d %d" % tuple(P.degree))
        out.append("%d %d" % tuple(n))
        for d in range(2):
            out.append(" ".join(num(u) for u in P.knots[d]))
        for comp in range(2):
            out.append(" ".join(num(c[comp] * c[2]) for c in P.cp))
        out.append(" ".join(num(c[2]) for c in P.cp))
    for i, (a, b, r) in enumerate(interfaces):
        out += ["INTERFACE %d" % (i + 1), "%d %d" % (a[0] + 1, a[1]), "%d %d" % (b[0] + 1, b[1]),
                "-1" if r else "1"]
    for name, s in named:
        out += [name, "%d" % len(s)] + ["%d %d" % (x[0] + 1, x[1]) for x in s]
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def main():
    folder = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
    cases = {
        "ring4": ("Annulus r 1..2 about (0, 0), four quarter patches from 0, 90, 180, 270 degrees",
                  annulus4((0.0, 0.0), 1.0, 2.0, [0, 90, 180, 270])),
        "wheel4": ("Wheel: annulus r 5..10 about (0, 10), patches from 225, 315, 45, 135 degrees; "
                   "(0, 0) is the middle of patch 0",
                   annulus4((0.0, 10.0), 5.0, 10.0, [225, 315, 45, 135])),
        "wheel4_joint": ("Wheel: annulus r 5..10 about (0, 10), patches from 0, 90, 180, 270 degrees; "
                         "(0, 0) is the joint of patches 2 and 3",
                         annulus4((0.0, 10.0), 5.0, 10.0, [0, 90, 180, 270])),
        "plate_with_hole": ("Plate with a hole: [0, 4]^2 minus the quarter disc r < 1, two patches "
                            "split along the diagonal", plate_with_hole()),
        "punch": ("Half of a flat punch of half width 1.5 with edges rounded to radius 0.5, face on y = 4, "
                  "top on y = 5", rounded_punch()),
    }
    for name, (title, (patches, interfaces, named)) in cases.items():
        write_xml(os.path.join(folder, name + ".xml"), title, patches, interfaces, named)
        write_geopdes(os.path.join(folder, name + ".txt"), title, patches, interfaces, named)


if __name__ == "__main__":
    main()
