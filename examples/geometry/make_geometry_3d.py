#!/usr/bin/python3
"""Writes the 3-D example geometry files of this folder, in G+Smo XML and GeoPDEs v2.1 text
(see docs/geometry-files.md).

    /usr/bin/python3 examples/geometry/make_geometry_3d.py [output folder]

  sphere_octant2   the thick sphere octant r 1..2 (x, y, z >= 0) as two trivariate NURBS
                   patches split at 45 degrees about the z axis. Patch 0: xi the revolution
                   about z from 0 to 45 degrees, eta the meridian from the equator (z = 0) to
                   the pole, zeta the radius; patch 1 (45 to 90 degrees) has its directions in
                   another order: xi the radius, eta the revolution, zeta the meridian. Both are
                   right-handed, degree 2 in the angles (exact rational arcs) and 1 in the
                   radius; each has its pole face (patch 0 north, patch 1 back) collapsed onto
                   the z axis. The interface (patch 0 east = patch 1 south) maps patch 0's eta
                   to patch 1's zeta and zeta to xi: G+Smo's "0 2 1 3 1 2 0 0 1 1". Named
                   boundaries: inner, outer, y0 (the plane y = 0), x0, z0; the pole faces are
                   in none.

Exact arcs: an arc of half-angle h has its middle control point at R / cos h (where the end
tangents meet) with weight cos h; the octant is the tensor product of the revolution arc, the
meridian quarter circle and the radius, weights multiplied. Control points: the first
parametric index fastest. G+Smo's <coefs> are Euclidean, the weights in the basis; GeoPDEs'
coordinate rows are homogeneous (w x, w y, w z), then a row of weights. GeoPDEs' interface
line "flag ornt1 ornt2" = "-1 1 1": the two face directions swap (patch 0's eta along patch
1's zeta), both in the same sense.
"""
import math
import os
import sys

S = math.sqrt(0.5)
C = math.cos(math.pi / 8)   # cos 22.5 degrees
RI, RO = 1.0, 2.0


def arc(t0, t1):
    """(cos, sin, weight) of the control points of the unit arc from angle t0 to t1."""
    h, m = 0.5 * (t1 - t0), 0.5 * (t0 + t1)
    c = math.cos(h)
    return [(math.cos(t0), math.sin(t0), 1.0), (math.cos(m) / c, math.sin(m) / c, c), (math.cos(t1), math.sin(t1), 1.0)]


# the meridian quarter circle: (distance from the axis, z, weight)
MER = [(1.0, 0.0, 1.0), (1.0, 1.0, S), (0.0, 1.0, 1.0)]


def point(rev, mer, r):
    x = r * mer[0] * rev[0]
    y = r * mer[0] * rev[1]
    z = r * mer[1]
    return (x, y, z, rev[2] * mer[2])


def patch0():
    rev = arc(0.0, math.pi / 4)
    rev[0] = (1.0, 0.0, 1.0)
    cps = [point(rev[i], MER[j], r) for r in (RI, RO) for j in range(3) for i in range(3)]
    return ([2, 2, 1], cps)


def patch1():
    rev = arc(math.pi / 4, math.pi / 2)
    rev[2] = (0.0, 1.0, 1.0)   # exact
    cps = [point(rev[j], MER[k], r) for k in range(3) for j in range(3) for r in (RI, RO)]
    return ([1, 2, 2], cps)


def num(v):
    return repr(float(v)) if v != int(v) else str(int(v))


def geometry(gid, degree, cps):
    out = [' <Geometry type="TensorNurbs3" id="%d">' % gid, '  <Basis type="TensorNurbsBasis3">', '   <Basis type="TensorBSplineBasis3">']
    for d, p in enumerate(degree):
        knots = " ".join(["0"] * (p + 1) + ["1"] * (p + 1))
        out += ['    <Basis type="BSplineBasis" index="%d">' % d, '     <KnotVector degree="%d">%s</KnotVector>' % (p, knots), "    </Basis>"]
    out += ["   </Basis>", "   <weights>"] + [num(c[3]) for c in cps] + ["</weights>", "  </Basis>", '  <coefs geoDim="3">']
    out += ["%s %s %s" % (num(c[0]), num(c[1]), num(c[2])) for c in cps]
    out += ["</coefs>", " </Geometry>"]
    return out


NAMED = [("inner", [(0, 5), (1, 1)]), ("outer", [(0, 6), (1, 2)]), ("y0", [(0, 1)]), ("x0", [(1, 4)]), ("z0", [(0, 3), (1, 5)])]


def write_geopdes(path):
    out = ["# nurbs mesh v.2.1", "# igacontact example: thick sphere octant r 1..2 in two trivariate patches (make_geometry_3d.py)",
           "3 3 2 1 0"]
    for k, (degree, cps) in enumerate([patch0(), patch1()]):
        out += ["PATCH %d" % (k + 1), " ".join(str(p) for p in degree), " ".join(str(p + 1) for p in degree)]
        out += [" ".join(["0"] * (p + 1) + ["1"] * (p + 1)) for p in degree]
        for c in range(3):
            out.append(" ".join(num(cp[c] * cp[3]) for cp in cps))
        out.append(" ".join(num(cp[3]) for cp in cps))
    out += ["INTERFACE 1", "1 2", "2 3", "-1 1 1"]
    for name, sides in NAMED:
        out += [name, str(len(sides))] + ["%d %d" % (p + 1, s) for p, s in sides]
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def main():
    folder = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
    write_geopdes(os.path.join(folder, "sphere_octant2.txt"))
    out = ['<?xml version="1.0" encoding="UTF-8"?>', "<!--igacontact example: thick sphere octant r 1..2 in two trivariate patches (make_geometry_3d.py)-->", "<xml>"]
    for gid, (degree, cps) in enumerate([patch0(), patch1()]):
        out += geometry(gid, degree, cps)
    out += [' <MultiPatch parDim="3" id="2">', '  <patches type="id_range">0 1</patches>', "  <interfaces>0 2 1 3 1 2 0 0 1 1", "</interfaces>"]
    for name, sides in NAMED:
        rows = ["%d %d" % ps for ps in sides]
        out += ['  <boundary name="%s">%s' % (name, rows[0])] + rows[1:] + ["</boundary>"]
    out += [" </MultiPatch>", "</xml>"]
    with open(os.path.join(folder, "sphere_octant2.xml"), "w") as f:
        f.write("\n".join(out) + "\n")


if __name__ == "__main__":
    main()
