#!/usr/bin/python3
# Writes a small hand-made igacontact output directory that follows the XDMF recipe of
# docs/paraview-xdmf-notes.md (temporal collection of spatial collections; Quadrilateral
# topology with flat {n, c} arrays; Polyvertex with explicit connectivity; geometry and
# topology referenced by the same HDF5 path in every step) plus result.pvd over degree
# (1, 1) Bezier cells and summary.json, for tests/paraview/check_results.py.
#     /usr/bin/python3 tests/paraview/sample_results.py OUTDIR
# result.h5 also holds each node field as NAME_g {n1, n0, c} and NAME_g1 {1, n1, n0, c} (the
# layouts tried for 2DSMesh / 3DSMesh in the notes).
import sys, json, numpy as np, h5py
out = sys.argv[1]
steps = [1/3, 2/3, 1.0]
bodies = {"block": (5, 4), "wheel": (7, 3)}   # n0, n1 samples
ncp = {"block": (4, 3), "wheel": (5, 3)}
npc = 6
h = h5py.File(out + "/result.h5", "w")
def put(name, v, n0, n1):   # v: (n, c) or (n,)
    h[name] = v
    rest = v.shape[1:]
    h[name + "_g"] = v.reshape((n1, n0) + rest)
    h[name + "_g1"] = v.reshape((1, n1, n0) + rest)
maxd, maxp = 0.0, 0.0
for b, (n0, n1) in bodies.items():
    off = 0.0 if b == "block" else 3.0
    X, Y = np.meshgrid(np.linspace(0, 1, n0) + off, np.linspace(0, 1, n1))   # (n1, n0)
    X, Y = X.ravel(), Y.ravel()
    put(f"/bodies/{b}/xyz", np.stack([X, Y, 0 * X], -1), n0, n1)
    put(f"/bodies/{b}/xy", np.stack([X, Y], -1), n0, n1)
    put(f"/bodies/{b}/x", X, n0, n1); put(f"/bodies/{b}/y", Y, n0, n1)
    c0, c1 = ncp[b]
    CX, CY = np.meshgrid(np.linspace(0, 1, c0) + off, np.linspace(-0.2, 0.8, c1))
    CX, CY = CX.ravel(), CY.ravel()
    put(f"/bodies/{b}/control_xyz", np.stack([CX, CY, 0 * CX], -1), c0, c1)
    put(f"/bodies/{b}/element", np.arange((n0 - 1) * (n1 - 1), dtype=np.int32), n0 - 1, n1 - 1)
    for nm, (m0, m1) in (("quads", (n0, n1)), ("control_quads", (c0, c1))):
        h[f"/bodies/{b}/{nm}"] = np.array([[i + j * m0, i + 1 + j * m0, i + 1 + (j + 1) * m0, i + (j + 1) * m0]
                                          for j in range(m1 - 1) for i in range(m0 - 1)], dtype=np.int32)
xs = np.linspace(-0.5, 0.5, npc)
h["/contact/0/conn"] = np.arange(npc, dtype=np.int32)
h["/contact/0/xyz"] = np.stack([xs, 0 * xs, 0 * xs], -1)
for s, lam in enumerate(steps, 1):
    g = f"/step_{s:04d}"
    for b, (n0, n1) in bodies.items():
        X = h[f"/bodies/{b}/xyz"][:, 0]; Y = h[f"/bodies/{b}/xyz"][:, 1]
        u = np.stack([0.01 * lam * Y, -0.02 * lam * X, 0 * X], -1)
        if s == len(steps): maxd = max(maxd, np.hypot(u[:, 0], u[:, 1]).max())
        put(f"{g}/{b}/displacement", u, n0, n1)
        sxx, syy, sxy, szz = lam * X, lam * Y, lam * X * Y, 0.3 * lam * (X + Y)
        put(f"{g}/{b}/stress", np.stack([sxx, syy, szz, sxy, 0 * X, 0 * X], -1), n0, n1)
        put(f"{g}/{b}/von_mises", np.sqrt(0.5 * ((sxx - syy)**2 + (syy - szz)**2 + (szz - sxx)**2) + 3 * sxy**2), n0, n1)
        c0, c1 = ncp[b]
        put(f"{g}/{b}/control_displacement", np.full((c1 * c0, 3), lam) * [0.01, -0.02, 0], c0, c1)
    p = lam * np.maximum(0, 1 - 4 * xs**2)
    if s == len(steps): maxp = p.max()
    h[f"{g}/contact_0/pressure"] = p
    h[f"{g}/contact_0/gap"] = -p / 1e3
    h[f"{g}/contact_0/traction"] = np.stack([0 * p, p, 0 * p], -1)
h.close()
json.dump({"max_displacement": float(maxd), "contact": [{"max_pressure": float(maxp)}], "load_factor": 1.0},
          open(out + "/summary.json", "w"), indent=1)

# result.pvd + result_<step>.vtu: each sampled quad as a degree (1, 1) Bezier cell (corners =
# samples), ascii, so the .pvd side can be checked against the same summary.
def vtu(path, lam, s):
    hh = h5py.File(out + "/result.h5", "r")
    P, U, C, B = [], [], [], []
    for bi, (b, (n0, n1)) in enumerate(bodies.items()):
        X = hh[f"/bodies/{b}/xyz"][...]; u = hh[f"/step_{s:04d}/{b}/displacement"][...]
        for j in range(n1 - 1):
            for i in range(n0 - 1):
                for (a, c) in ((i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)):
                    P.append(X[a + c * n0]); U.append(u[a + c * n0])
                B.append(bi)
    nc = len(B); npt = len(P)
    f = lambda a: " ".join("%.17g" % v for v in np.ravel(a))
    txt = f'''<?xml version="1.0"?>
<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" header_type="UInt64">
 <UnstructuredGrid>
  <FieldData><DataArray type="Float64" Name="TimeValue" NumberOfTuples="1" format="ascii">{lam!r}</DataArray></FieldData>
  <Piece NumberOfPoints="{npt}" NumberOfCells="{nc}">
   <PointData Vectors="displacement" RationalWeights="RationalWeights">
    <DataArray type="Float64" Name="RationalWeights" format="ascii">{f(np.ones(npt))}</DataArray>
    <DataArray type="Float64" Name="displacement" NumberOfComponents="3" format="ascii">{f(U)}</DataArray>
    <DataArray type="Float64" Name="stress" NumberOfComponents="6" format="ascii">{f(np.zeros(6 * npt))}</DataArray>
    <DataArray type="Float64" Name="von_mises" format="ascii">{f(np.zeros(npt))}</DataArray>
   </PointData>
   <CellData HigherOrderDegrees="HigherOrderDegrees">
    <DataArray type="Int32" Name="HigherOrderDegrees" NumberOfComponents="3" format="ascii">{" ".join("1 1 0" for _ in B)}</DataArray>
    <DataArray type="Int32" Name="body" format="ascii">{" ".join(map(str, B))}</DataArray>
    <DataArray type="Int32" Name="element" format="ascii">{" ".join(map(str, range(nc)))}</DataArray>
   </CellData>
   <Points><DataArray type="Float64" NumberOfComponents="3" format="ascii">{f(P)}</DataArray></Points>
   <Cells>
    <DataArray type="Int64" Name="connectivity" format="ascii">{" ".join(map(str, range(npt)))}</DataArray>
    <DataArray type="Int64" Name="offsets" format="ascii">{" ".join(str(4 * (k + 1)) for k in range(nc))}</DataArray>
    <DataArray type="UInt8" Name="types" format="ascii">{" ".join("77" for _ in B)}</DataArray>
   </Cells>
  </Piece>
 </UnstructuredGrid>
</VTKFile>
'''
    open(path, "w").write(txt)
pvd = ['<?xml version="1.0"?>', '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">', ' <Collection>']
for s, lam in enumerate(steps, 1):
    vtu(out + f"/result_{s:04d}.vtu", lam, s)
    pvd.append(f'  <DataSet timestep="{lam!r}" group="" part="0" file="result_{s:04d}.vtu"/>')
pvd += [' </Collection>', '</VTKFile>', '']
open(out + "/result.pvd", "w").write("\n".join(pvd))


# result.xdmf (bodies), result_control_nets.xdmf, result_contact.xdmf: the recipe
def item(path, dims, nt="Float", prec=8):
    return ('<DataItem Dimensions="%s" NumberType="%s" Precision="%d" Format="HDF">result.h5:%s</DataItem>'
            % (" ".join(map(str, dims)), nt, prec, path))
def attr(name, typ, path, dims, center="Node", nt="Float", prec=8):
    return '   <Attribute Name="%s" AttributeType="%s" Center="%s">%s</Attribute>' % (name, typ, center, item(path, dims, nt, prec))
def quads(b, path, m0, m1):
    nq = (m0 - 1) * (m1 - 1)
    return ('   <Topology TopologyType="Quadrilateral" NumberOfElements="%d" NodesPerElement="4">%s</Topology>'
            % (nq, item("/bodies/%s/%s" % (b, path), [nq, 4], "Int", 4)))
head = ['<?xml version="1.0" ?>', '<Xdmf Version="3.0">', '<Domain>',
        '<Grid Name="load_steps" GridType="Collection" CollectionType="Temporal">']
files = {"result.xdmf": list(head), "result_control_nets.xdmf": list(head), "result_contact.xdmf": list(head)}
for s, lam in enumerate(steps, 1):
    g = "/step_%04d" % s
    for o in files.values():
        o += [' <Grid Name="step_%04d" GridType="Collection" CollectionType="Spatial">' % s, '  <Time Value="%r"/>' % lam]
    o, on = files["result.xdmf"], files["result_control_nets.xdmf"]
    for b, (n0, n1) in bodies.items():
        n = n0 * n1
        o += ['  <Grid Name="%s" GridType="Uniform">' % b, quads(b, "quads", n0, n1),
              '   <Geometry GeometryType="XYZ">%s</Geometry>' % item("/bodies/%s/xyz" % b, [n, 3]),
              attr("displacement", "Vector", "%s/%s/displacement" % (g, b), [n, 3]),
              attr("stress", "Tensor6", "%s/%s/stress" % (g, b), [n, 6])]
        o += [attr("von_mises", "Scalar", "%s/%s/von_mises" % (g, b), [n])]
        o += [attr("element", "Scalar", "/bodies/%s/element" % b, [(n0 - 1) * (n1 - 1)], "Cell", "Int", 4), '  </Grid>']
        c0, c1 = ncp[b]
        on += ['  <Grid Name="%s_control_net" GridType="Uniform">' % b, quads(b, "control_quads", c0, c1),
               '   <Geometry GeometryType="XYZ">%s</Geometry>' % item("/bodies/%s/control_xyz" % b, [c0 * c1, 3]),
               attr("control_displacement", "Vector", "%s/%s/control_displacement" % (g, b), [c0 * c1, 3]), '  </Grid>']
    files["result_contact.xdmf"] += [
          '  <Grid Name="contact_0" GridType="Uniform">',
          '   <Topology TopologyType="Polyvertex" NumberOfElements="%d" NodesPerElement="1">%s</Topology>' % (npc, item("/contact/0/conn", [npc], "Int", 4)),
          '   <Geometry GeometryType="XYZ">%s</Geometry>' % item("/contact/0/xyz", [npc, 3]),
          attr("pressure", "Scalar", "%s/contact_0/pressure" % g, [npc]), attr("gap", "Scalar", "%s/contact_0/gap" % g, [npc]),
          attr("traction", "Vector", "%s/contact_0/traction" % g, [npc, 3]), '  </Grid>']
    for o in files.values():
        o.append(' </Grid>')
for name, o in files.items():
    o += ['</Grid>', '</Domain>', '</Xdmf>', '']
    open(out + "/" + name, "w").write("\n".join(o))
