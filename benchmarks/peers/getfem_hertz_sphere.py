#!/usr/bin/python3
"""GetFEM 5.4's 3-D contact on the Hertz sphere of examples/hertz_sphere.yaml (issue 36, item 6).

usage: benchmarks/peers/getfem_hertz_sphere.py [--degree 1|2] [--n-a 7] [--growth 1.6] ...

Needs GetFEM's Python interface: the Debian package python3-getfem (GetFEM 5.4.2, with
sequential MUMPS); run it with the system interpreter /usr/bin/python3. Without it the
script says so and exits 77 (skip). Nothing in the build or the test suite uses it.

The problem (the same as igacontact's examples/hertz_sphere.yaml, written by
scripts/hertz_sphere_mesh): quarter model, symmetry planes x = 0 and y = 0, the first
contact point at the origin.
  Ball: radius R = 1, centre (0, 0, R): the lower quarter of the lower hemisphere
    (x >= 0, y >= 0, z <= R); its top plane z = R (the centre plane) moves down by
    delta = 0.0135 (u_z prescribed, u_x and u_y free).
  Block: [0, 1] x [0, 1] x [-1, 0], bottom z = -1 held in z (u_x, u_y free).
  Both: E = 1000, nu = 0.3, small strain (GetFEM's isotropic linearized elasticity brick).
  Symmetry u_x = 0 on x = 0 and u_y = 0 on y = 0 for both bodies.

Meshes (GetFEM's own structured mesh, mapped): hexahedra, geometric transformation
GT_QK(3, k) with k the degree (isoparametric: the Q2 ball's sphere is quadratic).
  Ball: GetFEM's structured mesh of the unit cube (s, t, w) mapped onto the ball octant
    by P -> P |P|_inf / |P|_2 (the faces s = 1, t = 1, w = 1 go onto the sphere), with
    (x, y, z) = R (X_t, X_s, 1 - X_w) (the swap of s and t keeps det J > 0). The contact
    point is the cube corner (0, 0, 1), a regular point of the map (w is the largest
    coordinate around it); its cells there are nearly cubes. Graded as the IGA model is:
    cell size h = a / n_a out to fine x a from the contact point (a = the expected
    contact radius), then x growth per cell: along the sphere's arc (s, t = tan of the
    polar angle on the face w = 1, out to 45 degrees) and the depth below the contact
    point (w = 1 - depth / R; the same w carries the sphere's faces s = 1 and t = 1 from
    45 degrees to the equator).
  Block: a structured mesh of the unit cube mapped to x = L g(s), y = L g(t) and z from -H
    to 0, each graded the same way from the contact point (0, 0, 0) (z towards the top).
Finite elements: FEM_QK(3, k) for the displacements (Q1 or Q2, Lagrange); Gauss
IM_GAUSS_PARALLELEPIPED(3, 2k + 1) (2 or 3 points per direction).
Supports: the normal components held by GetFEM's normal Dirichlet bricks with multipliers
(multiplier of degree k on each face: x = 0 and y = 0 of both bodies, the block's bottom,
the ball's top with u.n = -delta).
Contact (--contact), frictionless, augmented Lagrangian (Alart-Curnier, non-symmetric),
augmentation parameter r (--r, default E / h, as GetFEM's demo_wheel_contact.py takes
1 / (gamma0 h) with gamma0 = 1 / E). Slave: the ball's sphere faces whose mean outward normal
lies within --slave-angle (45 degrees) of -z; master: the block's top (z = 0). The multiplier
(the contact pressure) is a field of degree --mult-degree (default k) on the slave faces (a
filtered fem variable), integrated with the volume's Gauss rule on the slave faces (or a
composite rule, --contact-subdiv S: S x S sub-faces).
  gwfl (default): small sliding in GetFEM's weak form language, as GetFEM's two-body demo
    (interface/tests/python/demo_wheel_contact.py) writes it: the interpolate transformation
    Proj: X -> (X1, X2, 0) (the block's top, reference configuration; the closest point on
    the flat master), gap = (X + u1 - Proj(X) - u2(Proj(X))).e_z, the terms
    lambda (v1 - v2(Proj)).e_z and -(1/r)(lambda + neg_part(lambda + r gap)) mu on the slave:
    lambda <= 0 the normal stress, pressure p = -lambda.
  integral: Model.add_integral_contact_between_nonmatching_meshes_brick (option --option:
    1 Alart-Curnier, 2 symmetric, 3 over-augmented, 4 "new unsymmetric"); the master's fem is
    carried to the slave's integration points by GetFEM's projected_fem. On this problem it
    does not hold the bodies apart: Newton converges (2 iterations) to a state where the ball
    passes into the block beyond r ~ 0.03, the multiplier oscillates in sign and its integral
    is not the support's reaction (n_a = 4: P 0.68 instead of 1.23, the pressure's integral
    11 % above it; p0 +200 to +770 % over the runs; the same with composite integration,
    with r from 1e2 to 1e4, and with a block 1000 times stiffer), while the rigid-obstacle
    brick on the same ball
    (add_integral_contact_with_rigid_obstacle_brick, obstacle z) gives a smooth profile with
    zero gap. In a flat non-matching check (two stacked boxes, 4 x 4 x 4 on 5 x 5 x 5, with
    and without an initial gap) it gives the uniform pressure to -18 % .. +22 % with the
    volume's Gauss rule, +-1.5 % with --contact-subdiv 4. Kept for the record.
  large: the raytracing large-sliding brick (add_integral_large_sliding_contact_brick_raytracing,
    release distance --release, f = 0), vector multiplier (the slave's traction, p = its z
    component up to sign). At n_a = 4 (Q1, r = E / h) it needs 29 Newton iterations with
    line search (gwfl: 5) and 15.5 s (gwfl: 2.1 s) for the same answer (p0 +1.32 %, a (fit)
    +4.8 %; gwfl +1.48 %, +4.6 %).
One load step, GetFEM's Newton (Model.solve, MUMPS) to --max-res.

Outputs, as scripts/hertz_sphere_check measures igacontact's run:
  P  = 4 x |the z reaction of the ball's top| (the integral of its Dirichlet multiplier);
       also 4 x the integral of the contact pressure over the slave faces (should agree)
  p0 = the largest contact pressure (the multiplier's largest nodal value: at the contact
       point), a (edge) = the largest reference radius sqrt(x^2 + y^2) of an active multiplier
       node (gwfl: Alart-Curnier's switch at the node, p - r gap > 0; the bricks: p > 1e-3 p0),
       and the least-squares fit of p^2 = p0^2 (1 - r^2 / a^2) over
       the nodes with r < 0.8 a (iterated from a (edge));
  Hertz at that P: 1/E* = 2 (1 - nu^2) / E, a = (3 P R / (4 E*))^(1/3), p0 = 3 P / (2 pi a^2),
  and the errors in %. Dofs: displacements (both bodies), multipliers (contact, supports) and
  the whole system GetFEM solves; seconds: since the script started (its imports included;
  time the whole process with /usr/bin/time for the interpreter's start-up), the mesh and
  model set-up, the solve, the post-processing. --json prints one JSON line at the end.

The BLAS is held to one thread (OPENBLAS_NUM_THREADS = OMP_NUM_THREADS = 1 unless set), as
the peers of compare_sphere.sh run on one thread.
"""
import time

T0 = time.perf_counter()

import argparse  # noqa: E402
import json  # noqa: E402
import math  # noqa: E402
import os  # noqa: E402
import sys  # noqa: E402

for _v in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")

try:
    import numpy as np
    import getfem as gf
except ImportError as e:
    print(f"getfem_hertz_sphere.py: cannot import GetFEM's Python interface ({e}); "
          "install the Debian package python3-getfem (apt-get install python3-getfem) and run "
          "this script with /usr/bin/python3", file=sys.stderr)
    sys.exit(77)


def graded(h, fine, growth, extent):
    """Cell boundaries (distances from the contact point) strictly inside (0, extent):
    size h out to `fine`, then each cell `growth` times the previous one; the last cell
    takes what is left (as scripts/hertz_sphere_mesh grades the IGA knots)."""
    b = []
    s = 0.0
    size = h
    while True:
        if s + 1e-12 >= fine:
            size *= growth
        if s + size * 1.5 >= extent:
            break
        s += size
        b.append(s)
    return b


def interp_nodes(c, nodes):
    """Maps the structured mesh coordinate c in [0, 1] (cell boundaries at i / n) to the
    graded nodes, linearly inside each cell (a Q2 mid-side node goes to the cell's middle)."""
    n = len(nodes) - 1
    i = np.clip(c * n, 0.0, n)
    j = np.minimum(np.floor(i + 1e-9), n - 1).astype(int)
    f = i - j
    nodes = np.asarray(nodes)
    return nodes[j] + f * (nodes[j + 1] - nodes[j])


def structured_cube(k, n):
    return gf.Mesh("import", "structured",
                   f'GT="GT_QK(3,{k})";ORG=[0,0,0];SIZES=[1,1,1];NOISED=0;'
                   f"NSUBDIV=[{n[0]},{n[1]},{n[2]}]")


def ball_mesh(args, h, fine):
    R = args.R
    arcs = graded(h, fine, args.growth, R * math.pi / 4)       # arc from the pole on w = 1
    lat = [0.0] + [math.tan(s / R) for s in arcs] + [1.0]
    dep = graded(h, fine, args.growth, R)                       # depth below the contact point
    wn = [0.0] + sorted(1.0 - d / R for d in dep) + [1.0]
    m = structured_cube(args.degree, [len(lat) - 1, len(lat) - 1, len(wn) - 1])
    P = m.pts()
    s = interp_nodes(P[0], lat)
    t = interp_nodes(P[1], lat)
    w = interp_nodes(P[2], wn)
    inf = np.maximum(np.maximum(s, t), w)
    two = np.sqrt(s * s + t * t + w * w)
    scale = np.where(two > 0, inf / np.where(two > 0, two, 1.0), 0.0)
    X = np.vstack([R * t * scale, R * s * scale, R - R * w * scale])
    m.set_pts(X)
    return m, (len(lat) - 1, len(lat) - 1, len(wn) - 1)


def block_mesh(args, h, fine):
    L, H = args.L, args.H
    lat = [0.0] + graded(h, fine, args.growth, L) + [L]
    dep = [0.0] + graded(h, fine, args.growth, H) + [H]
    zn = sorted(-d for d in dep)                                 # -H .. 0
    m = structured_cube(args.degree, [len(lat) - 1, len(lat) - 1, len(zn) - 1])
    P = m.pts()
    X = np.vstack([interp_nodes(P[0], lat), interp_nodes(P[1], lat), interp_nodes(P[2], zn)])
    m.set_pts(X)
    return m, (len(lat) - 1, len(lat) - 1, len(zn) - 1)


def gap_at_nodes(md, mflam, region, dofs):
    """The normal gap (X + u1 - Proj(X) - u2(Proj(X))).e_z at the multiplier's nodes, as the
    weak form has it (--contact gwfl)."""
    g = np.asarray(md.interpolation("(u1 - Interpolate(u2,Proj) + X - Interpolate(X,Proj))(3)",
                                    mflam, region)).ravel()
    return g[dofs]


def basic_values(md, name):
    """A variable's values on the basic dofs of its mesh_fem (a filtered variable or a
    multiplier lives on a reduced mesh_fem: extension matrix x reduced values)."""
    v = md.variable(name)
    mf = md.mesh_fem_of_variable(name)
    if mf.is_reduced():
        return np.asarray(mf.extension_matrix().mult(v)).ravel()
    return np.asarray(v).ravel()


def fit(points, a_start, fraction):
    """p^2 = A - B r^2 over (r, p) with r < fraction a, iterated on a (as hertz_sphere_check)."""
    a = a_start
    A = slope = None
    for _ in range(50):
        sel = [(r * r, p * p) for r, p in points if r < fraction * a]
        if len(sel) < 3:
            return None
        x = np.array([q[0] for q in sel])
        y = np.array([q[1] for q in sel])
        slope, A = np.polyfit(x, y, 1)
        if slope >= 0 or A <= 0:
            return None
        a_new = math.sqrt(A / -slope)
        if abs(a_new - a) < 1e-12 * a:
            a = a_new
            break
        a = a_new
    return math.sqrt(A), a, len(sel)


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--degree", type=int, default=1, choices=(1, 2), help="Q1 or Q2")
    ap.add_argument("--R", type=float, default=1.0)
    ap.add_argument("--L", type=float, default=1.0, help="block width")
    ap.add_argument("--H", type=float, default=1.0, help="block depth")
    ap.add_argument("--E", type=float, default=1000.0)
    ap.add_argument("--nu", type=float, default=0.3)
    ap.add_argument("--delta", type=float, default=0.0135, help="the ball top's displacement (down)")
    ap.add_argument("--a", type=float, default=0.12, help="expected contact radius (grading)")
    ap.add_argument("--n-a", type=float, default=7, help="cells across a near the contact point")
    ap.add_argument("--fine", type=float, default=1.3, help="uniform zone, in units of a")
    ap.add_argument("--growth", type=float, default=1.6, help="cell growth factor beyond it")
    ap.add_argument("--mult-degree", type=int, default=None, help="contact multiplier degree (default: --degree)")
    ap.add_argument("--contact", default="gwfl", choices=("gwfl", "integral", "large"),
                    help="gwfl: small sliding in the weak form language; integral: "
                    "add_integral_contact_between_nonmatching_meshes_brick; large: the raytracing "
                    "large-sliding brick")
    ap.add_argument("--release", type=float, default=0.1, help="large sliding: release distance")
    ap.add_argument("--option", type=int, default=1, choices=(1, 2, 3, 4),
                    help="integral contact brick's augmented Lagrangian variant")
    ap.add_argument("--r", type=float, default=None, help="augmentation parameter (default E / h)")
    ap.add_argument("--contact-subdiv", type=int, default=1,
                    help="the contact integral: composite Gauss, S x S sub-faces per slave face")
    ap.add_argument("--slave-angle", type=float, default=45.0, help="degrees from -z")
    ap.add_argument("--max-res", type=float, default=1e-8)
    ap.add_argument("--max-iter", type=int, default=40)
    ap.add_argument("--lsolver", default="mumps")
    ap.add_argument("--fit-fraction", type=float, default=0.8)
    ap.add_argument("--noisy", action="store_true", help="GetFEM's Newton trace")
    ap.add_argument("--json", action="store_true", help="one JSON line at the end")
    ap.add_argument("--vtk", default=None, help="write the contact pressure here (VTK)")
    args = ap.parse_args()
    k = args.degree
    kl = args.mult_degree or k
    E, nu, R = args.E, args.nu, args.R
    h = args.a / args.n_a
    fine = args.fine * args.a
    r_aug = args.r if args.r is not None else E / h
    T_import = time.perf_counter() - T0
    gf.util_trace_level(0)

    # --- meshes and regions
    t = time.perf_counter()
    m1, n1 = ball_mesh(args, h, fine)
    m2, n2 = block_mesh(args, h, fine)
    XM, YM, TOP, CONTACT = 1, 2, 3, 4            # ball
    XB, YB, BOTTOM, MASTER = 11, 12, 13, 14      # block
    tol = 1e-3
    m1.set_region(XM, m1.outer_faces_with_direction([-1.0, 0.0, 0.0], tol))
    m1.set_region(YM, m1.outer_faces_with_direction([0.0, -1.0, 0.0], tol))
    m1.set_region(TOP, m1.outer_faces_with_direction([0.0, 0.0, 1.0], tol))
    m1.set_region(CONTACT, m1.outer_faces_with_direction([0.0, 0.0, -1.0],
                                                          math.radians(args.slave_angle)))
    m2.set_region(XB, m2.outer_faces_with_direction([-1.0, 0.0, 0.0], tol))
    m2.set_region(YB, m2.outer_faces_with_direction([0.0, -1.0, 0.0], tol))
    m2.set_region(BOTTOM, m2.outer_faces_with_direction([0.0, 0.0, -1.0], tol))
    m2.set_region(MASTER, m2.outer_faces_with_direction([0.0, 0.0, 1.0], tol))

    fem = gf.Fem(f"FEM_QK(3,{k})")
    fem_s = fem
    im = gf.Integ(f"IM_GAUSS_PARALLELEPIPED(3,{2 * k + 1})")
    mfu1 = gf.MeshFem(m1, 3)
    mfu1.set_fem(fem)
    mfu2 = gf.MeshFem(m2, 3)
    mfu2.set_fem(fem)
    mflam = gf.MeshFem(m1, 1)
    mflam.set_fem(gf.Fem(f"FEM_QK(3,{kl})"))
    mim1 = gf.MeshIm(m1, im)
    mim2 = gf.MeshIm(m2, im)
    if args.contact_subdiv > 1:      # the contact terms: composite Gauss on the slave faces
        mimc = gf.MeshIm(m1, gf.Integ(f"IM_STRUCTURED_COMPOSITE(IM_GAUSS_PARALLELEPIPED(3,{2 * k + 1}),"
                                      f"{args.contact_subdiv})"))
    else:
        mimc = mim1
    vol1 = gf.asm_generic(mim1, 0, "1", -1)
    vol2 = gf.asm_generic(mim2, 0, "1", -1)

    md = gf.Model("real")
    md.add_fem_variable("u1", mfu1)
    md.add_fem_variable("u2", mfu2)
    lam_l = E * nu / ((1 + nu) * (1 - 2 * nu))
    mu = E / (2 * (1 + nu))
    md.add_initialized_data("lambda_l", [lam_l])
    md.add_initialized_data("mu", [mu])
    md.add_isotropic_linearized_elasticity_brick(mim1, "u1", "lambda_l", "mu")
    md.add_isotropic_linearized_elasticity_brick(mim2, "u2", "lambda_l", "mu")
    md.add_initialized_data("zero", [0.0])
    md.add_initialized_data("top", [-args.delta])
    # the ball's top first: its multiplier is GetFEM's first name for u1, "mult_on_u1"
    for mim, u, reg, data in ((mim1, "u1", TOP, "top"), (mim1, "u1", XM, "zero"),
                              (mim1, "u1", YM, "zero"), (mim2, "u2", XB, "zero"),
                              (mim2, "u2", YB, "zero"), (mim2, "u2", BOTTOM, "zero")):
        md.add_normal_Dirichlet_condition_with_multipliers(mim, u, k, reg, data)
    md.add_initialized_data("r", [r_aug])
    if args.contact == "integral":
        # GetFEM's small-sliding integral brick: the master's fem projected onto the slave's
        # integration points (projected_fem), Alart-Curnier; scalar multiplier
        md.add_filtered_fem_variable("lambda", mflam, CONTACT)
        md.add_integral_contact_between_nonmatching_meshes_brick(
            mimc, "u1", "u2", "lambda", "r", CONTACT, MASTER, args.option)
    elif args.contact == "gwfl":
        # small sliding written in GetFEM's weak form language, as GetFEM's own two-body
        # demo (demo_wheel_contact.py) does: the slave point X goes to the master plane by
        # the transformation X -> (X1, X2, 0) (the block's top, in the reference
        # configuration); gap = (X + u1 - Proj(X) - u2(Proj(X))).e_z; Alart-Curnier:
        # lambda = -(lambda + r gap)_- weakly, lambda <= 0 the normal stress
        md.add_filtered_fem_variable("lambda", mflam, CONTACT)
        md.add_interpolate_transformation_from_expression("Proj", m1, m2, "[X(1);X(2);0]")
        md.add_nonlinear_term(mimc, "lambda*(Test_u1(3)) - lambda*(Interpolate(Test_u2,Proj)(3))",
                              CONTACT)
        md.add_nonlinear_term(mimc, "-(1/r)*(lambda + neg_part(lambda + r*((u1 - Interpolate(u2,Proj)"
                              " + X - Interpolate(X,Proj))(3))))*Test_lambda", CONTACT)
    else:
        # GetFEM's large-sliding brick (raytracing transformation, integral Alart-Curnier,
        # frictionless: f = 0); vector multiplier (the slave's traction)
        mflv = gf.MeshFem(m1, 3)
        mflv.set_fem(gf.Fem(f"FEM_QK(3,{kl})"))
        md.add_filtered_fem_variable("lambda", mflv, CONTACT)
        md.add_initialized_data("f", [0.0])
        md.add_initialized_data("alpha", [1.0])
        ind = md.add_integral_large_sliding_contact_brick_raytracing(
            "r", args.release, "f", "alpha", 0)
        md.add_slave_contact_boundary_to_large_sliding_contact_brick(ind, mimc, CONTACT, "u1", "lambda")
        md.add_master_contact_boundary_to_large_sliding_contact_brick(ind, mim2, MASTER, "u2")
    T_setup = time.perf_counter() - t

    # --- solve
    nb_u = mfu1.nbdof() + mfu2.nbdof()
    nb_lam = len(md.variable("lambda"))
    nb_all = md.nbdof()
    t = time.perf_counter()
    opts = ["max_iter", args.max_iter, "max_res", args.max_res, "lsolver", args.lsolver]
    if args.noisy:
        opts.append("noisy")
    res = md.solve(*opts)
    T_solve = time.perf_counter() - t
    nit = int(res[0]) if res is not None and len(res) else -1
    converged = bool(res[1]) if res is not None and len(res) > 1 else None

    # --- post-processing
    t = time.perf_counter()
    full = basic_values(md, "lambda")             # on the multiplier's basic dofs
    if args.contact == "large":
        full = full[2::3]                         # the traction's z component
    dofs = mflam.basic_dof_on_region(CONTACT)
    nodes = mflam.basic_dof_nodes(dofs)
    radius = np.hypot(nodes[0], nodes[1])
    # the pressure: the multiplier's sign such that the resultant pushes (GetFEM's normal
    # stress is negative in compression)
    sign = -1.0 if np.sum(full) < 0 else 1.0
    p = sign * full[dofs]
    F_contact = sign * gf.asm_generic(mimc, 0, "lam", CONTACT, "lam", 0, mflam, full)
    mf_top = md.mesh_fem_of_variable("mult_on_u1")
    top_full = basic_values(md, "mult_on_u1")
    mf_top_basic = gf.MeshFem(m1, 1)
    mf_top_basic.set_fem(fem_s)
    assert mf_top_basic.nbdof() == len(top_full), (mf_top_basic.nbdof(), len(top_full), mf_top.nbdof())
    F_top = gf.asm_generic(mim1, 0, "m", TOP, "m", 0, mf_top_basic, top_full)
    P = 4 * abs(F_top)
    P_contact = 4 * abs(F_contact)
    Es = 1.0 / (2 * (1 - nu * nu) / E)
    a_h = (3 * P * R / (4 * Es)) ** (1 / 3)
    p0_h = 3 * P / (2 * math.pi * a_h ** 2)
    # active nodes: Alart-Curnier's switch at the multiplier's nodes, p - r gap > 0, the gap
    # (X + u1 - Proj(X) - u2(Proj(X))).e_z interpolated at the node (closed: gap ~ 0, p > 0;
    # open: p ~ 0 and gap > 0 growing as r^2 / 2R)
    if args.contact == "gwfl":
        gap = gap_at_nodes(md, mflam, CONTACT, dofs)
        active = p - r_aug * gap > 0
    else:      # the bricks: no interpolation of the model's own gap; p > 1e-3 p0
        active = p > 1e-3 * p.max()
    act = [(float(rr), float(pp)) for rr, pp, aa in zip(radius, p, active) if aa]
    p0 = float(p.max())
    a_edge = max(rr for rr, _ in act) if act else float("nan")
    f = fit(act, a_edge, args.fit_fraction) if act else None
    # the pressure at the contact point (the node at r = 0)
    p_centre = float(p[np.argmin(radius)])
    if args.vtk:
        sl = gf.Slice(("boundary",), mflam, CONTACT)
        sl.export_to_vtk(args.vtk, mflam, full * sign, "pressure", mfu1, md.variable("u1"), "u")
    T_post = time.perf_counter() - t
    T_total = time.perf_counter() - T0

    err = lambda x, ref: 100.0 * (x - ref) / ref  # noqa: E731
    print(f"GetFEM 5.4 (python3-getfem) Hertz sphere: Q{k} (multiplier Q{kl}), contact {args.contact}"
          f"{' option %d' % args.option if args.contact == 'integral' else ''}, "
          f"r = {r_aug:.4g}, h = a/{args.n_a:g} = {h:.5g}, fine {args.fine:g} a, growth {args.growth:g}, "
          f"delta = {args.delta:g}")
    print(f"  cells: ball {n1[0]} x {n1[1]} x {n1[2]} = {n1[0] * n1[1] * n1[2]}, "
          f"block {n2[0]} x {n2[1]} x {n2[2]} = {n2[0] * n2[1] * n2[2]}; "
          f"volumes {vol1:.6f} (pi/6 = {math.pi / 6:.6f}), {vol2:.6f}")
    print(f"  dofs: displacements {nb_u} (ball {mfu1.nbdof()}, block {mfu2.nbdof()}), "
          f"contact multiplier {nb_lam}, system {nb_all} (the supports' multipliers included)")
    print(f"  Newton: {nit} iterations, converged {converged}")
    print(f"  seconds: import {T_import:.2f}, set-up {T_setup:.2f}, solve {T_solve:.2f}, "
          f"post {T_post:.2f}, total {T_total:.2f} (since the script started)")
    print(f"  P = 4 |Rz(top)| = {P:.6g}; 4 x integral of the contact pressure = {P_contact:.6g} "
          f"({err(P_contact, P):+.3f} %)")
    print(f"  Hertz at this P (E* = {Es:.6g}): a = {a_h:.6g}, p0 = {p0_h:.6g}")
    print(f"  {'':12s} {'computed':>12s} {'Hertz':>12s} {'error':>9s}")
    print(f"  {'p0 (max)':12s} {p0:12.6g} {p0_h:12.6g} {err(p0, p0_h):8.2f}%"
          f"   (at r = 0: {p_centre:.6g})")
    print(f"  {'a (edge)':12s} {a_edge:12.6g} {a_h:12.6g} {err(a_edge, a_h):8.2f}%"
          f"   ({len(act)} of {len(p)} multiplier nodes active)")
    out = dict(degree=k, mult_degree=kl, option=args.option, r=r_aug, n_a=args.n_a,
               growth=args.growth, fine=args.fine, delta=args.delta,
               cells_ball=n1, cells_block=n2, dofs_u=nb_u, dofs_lambda=nb_lam, dofs_system=nb_all,
               newton_iterations=nit, converged=converged,
               seconds=dict(import_=T_import, setup=T_setup, solve=T_solve, post=T_post,
                            total=T_total),
               P=P, P_contact=P_contact, a_hertz=a_h, p0_hertz=p0_h, p0=p0, a_edge=a_edge,
               p0_error_pct=err(p0, p0_h), a_edge_error_pct=err(a_edge, a_h))
    if f:
        p0_f, a_f, nfit = f
        print(f"  {'p0 (fit)':12s} {p0_f:12.6g} {p0_h:12.6g} {err(p0_f, p0_h):8.2f}%")
        print(f"  {'a (fit)':12s} {a_f:12.6g} {a_h:12.6g} {err(a_f, a_h):8.2f}%"
              f"   ({nfit} nodes with r < {args.fit_fraction:g} a)")
        out.update(p0_fit=p0_f, a_fit=a_f, p0_fit_error_pct=err(p0_f, p0_h),
                   a_fit_error_pct=err(a_f, a_h))
    if args.json:
        print(json.dumps(out))
    if converged is False:
        return 3
    return 0


if __name__ == "__main__":
    sys.exit(main())
