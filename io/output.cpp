#include "io/output.hpp"

#include <hdf5.h>
#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_TimeMonitor.hpp>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <initializer_list>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "io/fields.hpp"
#include "io/vtk.hpp"
#include "io/files.hpp"
#include "model/geometry_file.hpp"
#include "kernels/numbering.hpp"

namespace iga {

namespace fs = std::filesystem;

nlohmann::json linear_solver_json(const Problem& P, const DirectSolverStats& ds, long long dofs) {
  const LinearOptions& opt = P.linear;
  nlohmann::json j;
  j["method"] = linear_method_name(opt.method);
  j["chosen_by"] = opt.automatic ? "auto" : "problem file";
  if (opt.automatic) j["auto_direct_max_dofs"] = P.auto_direct_max_dofs();
  if (opt.method == LinearMethod::Direct) {
    j["package"] = "MUMPS";
    // L D L^T where the tangent is symmetric; "LDLT+LU" where some were not (a 2-D mortar
    // pair whose master ends inside a slave element)
    j["factorization"] = ds.lu_factorisations == 0 && opt.symmetric ? "LDLT"
                         : ds.lu_factorisations < ds.factorisations ? "LDLT+LU"
                                                                    : "LU";
    j["ordering"] = ds.ordering;
    j["analyses"] = ds.analyses;
    j["factorizations"] = ds.factorisations;
    j["solves"] = ds.solves;
    j["factor_entries"] = ds.factor_entries;
    j["factor_memory_bytes"] = ds.factor_bytes;
    j["factor_memory_bytes_per_dof"] = dofs > 0 ? ds.factor_bytes / static_cast<double>(dofs) : 0.0;
    // solves condensed onto the contact sides (small strain): the set's size, the solves by
    // the updated Schur complement, the most dofs an update touched, the columns of S^-1 made
    nlohmann::json c;
    c["dofs"] = ds.condensed_size;
    c["solves"] = ds.condensed_solves;
    c["update_rank_max"] = ds.condensed_rank;
    c["inverse_columns"] = ds.condensed_columns;
    c["fell_back"] = ds.condensed_fell_back;
    j["condensed"] = c;
  } else {
    j["preconditioner"] = preconditioner_name(opt.preconditioner);
  }
  j["tolerance"] = opt.tolerance;
  j["forcing"] = eisenstat_walker_forcing(P) ? "eisenstat_walker" : "fixed";
  return j;
}

nlohmann::json reactions_json(const System& sys, const Vector& residual) {
  // per patch block: kCornerSlot side slots (4 used in 2-D, 6 in 3-D) and 4 corners, dim
  // components per place ([Rx, Ry(, Rz)])
  const Problem& P = sys.problem();
  const size_t nb = sys.blocks().size();
  const int dim = sys.dim(), per_block = (kCornerSlot + 4) * dim;
  std::vector<double> local(nb * per_block, 0.0), global(nb * per_block, 0.0);
  auto h = residual.getLocalViewHost(Tpetra::Access::ReadOnly);
  for (const DirichletDof& d : sys.dirichlet()) {
    const LO l = sys.owned_map()->getLocalElement(d.dof);
    local[d.block * per_block + d.side * dim + component_of_dof(d.dof, dim)] += -h(l, 0);
  }
  Teuchos::reduceAll(*sys.comm(), Teuchos::REDUCE_SUM, static_cast<int>(local.size()), local.data(), global.data());
  nlohmann::json j = nlohmann::json::object();
  for (size_t k = 0; k < nb; ++k) {
    const PatchBlock& bd = sys.blocks()[k];
    const Body& body = P.bodies[bd.body];
    nlohmann::json& sides = j[body.name];
    for (int s = 0; s < kCornerSlot + 4; ++s) {
      if (s < kCornerSlot && s >= num_sides(dim)) continue;
      const auto& sc = s < kCornerSlot ? body.sides[bd.patch][s] : body.corners[bd.patch][s - kCornerSlot];
      if (!(sc.fixed[0] || sc.fixed[1] || sc.fixed[2])) continue;
      const std::string name = s < kCornerSlot ? body.side_label(bd.patch, static_cast<Side>(s))
                                               : body.corner_label(bd.patch, static_cast<Corner>(s - kCornerSlot));
      const double* r = &global[k * per_block + s * dim];
      sides[name] = std::vector<double>(r, r + dim);
    }
    if (sides.is_null()) j.erase(body.name);
  }
  // A named boundary of the geometry file whose sides are all held: its total as well, under
  // its name (a control point shared by two sides is counted once: each constrained dof is
  // reported under one side)
  for (size_t b = 0; b < P.bodies.size(); ++b) {
    const Body& body = P.bodies[b];
    if (!j.contains(body.name)) continue;
    nlohmann::json& sides = j[body.name];
    for (const auto& [name, list] : body.named) {
      if (sides.contains(name)) continue;
      std::vector<double> sum(dim, 0.0);
      bool all = !list.empty();
      for (const PatchSide& ps : list) {
        const std::string label = body.side_label(ps.patch, ps.side);
        if (!sides.contains(label)) { all = false; break; }
        for (int c = 0; c < dim; ++c) sum[c] += sides[label][c].get<double>();
      }
      if (all) sides[name] = sum;
    }
  }
  return j;
}

namespace {

std::string dims_str(const std::vector<hsize_t>& d) {
  std::string s;
  for (hsize_t x : d) s += (s.empty() ? "" : " ") + std::to_string(x);
  return s;
}

// An XDMF DataItem naming a dataset of an HDF5 file beside the .xdmf.
enum class Item { Double, Float, Int };
const char* number_type(Item type) {   // the NumberType and Precision attributes' values
  return type == Item::Int ? "Int\" Precision=\"4\"" : type == Item::Float ? "Float\" Precision=\"4\"" : "Float\" Precision=\"8\"";
}
std::string data_item(const std::string& file, const std::string& path, const std::vector<hsize_t>& d,
                      Item type = Item::Double) {
  const char* t = number_type(type);
  return std::string("<DataItem Dimensions=\"") + dims_str(d) + "\" NumberType=\"" + t + " Format=\"HDF\">" + file + ":" +
         path + "</DataItem>";
}

// Parametric sample coordinates: s per element in each direction plus the end.
std::vector<std::pair<double, int>> samples(const std::vector<double>& U, const std::vector<int>& spans, int s) {
  std::vector<std::pair<double, int>> out;
  for (int sp : spans)
    for (int k = 0; k < s; ++k) out.push_back({U[sp] + (U[sp + 1] - U[sp]) * k / s, sp});
  out.push_back({U[spans.back() + 1], spans.back()});
  return out;
}

// Quadrilaterals of an n0 x n1 grid of points (i fastest), counter-clockwise.
std::vector<int> grid_quads(int n0, int n1) {
  std::vector<int> q;
  q.reserve(static_cast<size_t>(n0 - 1) * (n1 - 1) * 4);
  for (int j = 0; j + 1 < n1; ++j)
    for (int i = 0; i + 1 < n0; ++i)
      q.insert(q.end(), {i + j * n0, i + 1 + j * n0, i + 1 + (j + 1) * n0, i + (j + 1) * n0});
  return q;
}

// Hexahedra of an n0 x n1 x n2 grid of points (i fastest): bottom face counter-clockwise,
// then the top (VTK_HEXAHEDRON / XDMF Hexahedron order).
std::vector<int> grid_hexes(int n0, int n1, int n2) {
  std::vector<int> h;
  h.reserve(static_cast<size_t>(n0 - 1) * (n1 - 1) * (n2 - 1) * 8);
  auto at = [&](int i, int j, int k) { return i + n0 * (j + n1 * k); };
  for (int k = 0; k + 1 < n2; ++k)
    for (int j = 0; j + 1 < n1; ++j)
      for (int i = 0; i + 1 < n0; ++i)
        h.insert(h.end(), {at(i, j, k), at(i + 1, j, k), at(i + 1, j + 1, k), at(i, j + 1, k), at(i, j, k + 1),
                           at(i + 1, j, k + 1), at(i + 1, j + 1, k + 1), at(i, j + 1, k + 1)});
  return h;
}

std::string step_name(int step) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "result_%04d", step);
  return buf;
}

// 3-D: the control net of a trivariate patch in the state's HDF5 image (control_shape
// {m2, m1, m0}, control_xyz, control_hexes, control_displacement; Float64: the exact data) and
// its grid in result_control_nets.xdmf (Hexahedron topology: Wireframe shows the net).
void write_control_net3(H5Memory& f, const std::string& h5name, const std::string& g, const std::string& bn,
                        const Patch& pt, const std::vector<double>& ucp, std::ostream& nets) {
  const int m0 = pt.ncp(0), m1 = pt.ncp(1), m2 = pt.ncp(2);
  const hsize_t m = static_cast<hsize_t>(m0) * m1 * m2;
  std::vector<double> cxyz, cd3;
  cxyz.reserve(3 * m);
  cd3.reserve(3 * m);
  for (hsize_t a = 0; a < m; ++a) {
    cxyz.insert(cxyz.end(), {pt.cp[a].x[0], pt.cp[a].x[1], pt.cp[a].x[2]});
    cd3.insert(cd3.end(), {ucp[3 * a], ucp[3 * a + 1], ucp[3 * a + 2]});
  }
  const std::vector<int> hexes = grid_hexes(m0, m1, m2);
  const hsize_t mh = hexes.size() / 8;
  f.write_int(g + "/control_shape", {m2, m1, m0}, {3});
  f.write(g + "/control_xyz", cxyz, {m, 3});
  f.write_int(g + "/control_hexes", hexes, {mh, 8});
  f.write(g + "/control_displacement", cd3, {m, 3});
  nets << "   <Grid Name=\"" << bn << "_control_net\" GridType=\"Uniform\">\n"
       << "    <Topology TopologyType=\"Hexahedron\" NumberOfElements=\"" << mh << "\" NodesPerElement=\"8\">"
       << data_item(h5name, g + "/control_hexes", {mh, 8}, Item::Int) << "</Topology>\n"
       << "    <Geometry GeometryType=\"XYZ\">" << data_item(h5name, g + "/control_xyz", {m, 3}) << "</Geometry>\n"
       << "    <Attribute Name=\"control_displacement\" AttributeType=\"Vector\" Center=\"Node\">"
       << data_item(h5name, g + "/control_displacement", {m, 3}) << "</Attribute>\n"
       << "   </Grid>\n";
}


}  // namespace

double write_bodies(H5Memory& f, const std::string& h5name, const Problem& P,
                    const std::vector<std::vector<double>>& disp, std::ostream& grids, std::ostream& nets) {
  double umax = 0;
  const int dim = P.dim();
  for (size_t b = 0; b < P.bodies.size(); ++b)
    for (size_t patch = 0; patch < P.bodies[b].patches.size(); ++patch) {
      const int bi = static_cast<int>(b), k = static_cast<int>(patch);
      const Patch& pt = P.bodies[b].patches[patch];
      // a multi-patch body: one grid per patch, <body>.patch<k>
      const std::string bn = P.bodies[b].name + (P.bodies[b].multipatch() ? ".patch" + std::to_string(k) : std::string());
      const std::string g = "/bodies/" + bn;
      f.group(g);
      if (dim == 3) {
        // 3-D: no sampled grid (docs/paraview.md); the control net as hexahedra
        write_control_net3(f, h5name, g, bn, pt, P.bodies[b].patch_values(k, disp[b]), nets);
        continue;
      }
      const BodyField field(P, bi, disp[b], k);
      const int s = output_samples(P.output, pt);
      const auto su = samples(pt.knots[0], pt.element_spans(0), s);
      const auto sv = samples(pt.knots[1], pt.element_spans(1), s);
      const int n0 = static_cast<int>(su.size()), n1 = static_cast<int>(sv.size());
      const hsize_t n = static_cast<hsize_t>(n0) * n1;
      // the sampled grid is a picture: Float32 (the exact data are the control net's, Float64)
      std::vector<float> xyz, d3, stress, vm;
      xyz.reserve(3 * n); d3.reserve(3 * n); stress.reserve(6 * n); vm.reserve(n);
      for (const auto& v : sv)
        for (const auto& uu : su) {
          const FieldPoint fp = field.eval(uu.first, v.first, uu.second, v.second);
          xyz.insert(xyz.end(), {static_cast<float>(fp.x), static_cast<float>(fp.y), 0.0f});
          d3.insert(d3.end(), {static_cast<float>(fp.ux), static_cast<float>(fp.uy), 0.0f});
          umax = std::max(umax, std::hypot(fp.ux, fp.uy));
          // VTK order XX YY ZZ XY YZ XZ
          stress.insert(stress.end(), {static_cast<float>(fp.sxx), static_cast<float>(fp.syy), static_cast<float>(fp.szz),
                                       static_cast<float>(fp.sxy), 0.0f, 0.0f});
          vm.push_back(static_cast<float>(fp.von_mises()));
        }
      const std::vector<int> quads = grid_quads(n0, n1);
      const hsize_t nq = quads.size() / 4;
      const int ne0 = static_cast<int>(pt.element_spans(0).size());
      std::vector<int> element;
      element.reserve(nq);
      for (int j = 0; j + 1 < n1; ++j)
        for (int i = 0; i + 1 < n0; ++i) element.push_back(i / s + (j / s) * ne0);
      const int m0 = pt.ncp(0), m1 = pt.ncp(1);
      const hsize_t m = static_cast<hsize_t>(m0) * m1;
      std::vector<double> cxyz, cd3;
      const std::vector<double> ucp = P.bodies[b].patch_values(k, disp[b]);
      for (hsize_t a = 0; a < m; ++a) {
        cxyz.insert(cxyz.end(), {pt.cp[a].x[0], pt.cp[a].x[1], 0.0});
        cd3.insert(cd3.end(), {ucp[2 * a], ucp[2 * a + 1], 0.0});
      }
      const std::vector<int> cquads = grid_quads(m0, m1);
      const hsize_t mq = cquads.size() / 4;

      f.write_int(g + "/shape", {n1, n0}, {2});
      f.write_float(g + "/xyz", xyz, {n, 3});
      f.write_int(g + "/quads", quads, {nq, 4});
      f.write_int(g + "/element", element, {nq});
      f.write_float(g + "/displacement", d3, {n, 3});
      f.write_float(g + "/stress", stress, {n, 6});
      f.write_float(g + "/von_mises", vm, {n});
      f.write_int(g + "/control_shape", {m1, m0}, {2});
      f.write(g + "/control_xyz", cxyz, {m, 3});
      f.write_int(g + "/control_quads", cquads, {mq, 4});
      f.write(g + "/control_displacement", cd3, {m, 3});

      grids << "   <Grid Name=\"" << bn << "\" GridType=\"Uniform\">\n"
            << "    <Topology TopologyType=\"Quadrilateral\" NumberOfElements=\"" << nq << "\" NodesPerElement=\"4\">"
            << data_item(h5name, g + "/quads", {nq, 4}, Item::Int) << "</Topology>\n"
            << "    <Geometry GeometryType=\"XYZ\">" << data_item(h5name, g + "/xyz", {n, 3}, Item::Float) << "</Geometry>\n"
            << "    <Attribute Name=\"displacement\" AttributeType=\"Vector\" Center=\"Node\">"
            << data_item(h5name, g + "/displacement", {n, 3}, Item::Float) << "</Attribute>\n"
            << "    <Attribute Name=\"stress\" AttributeType=\"Tensor6\" Center=\"Node\">"
            << data_item(h5name, g + "/stress", {n, 6}, Item::Float) << "</Attribute>\n";
      // the stress once, as a tensor: ParaView colours by its components XX, YY, ZZ, XY (the
      // scalars sxx, syy, sxy, szz written beside it before doubled the file; an XDMF
      // hyperslab view of a column reads in the Xdmf3 readers or in the legacy one, not both)
      grids << "    <Attribute Name=\"von_mises\" AttributeType=\"Scalar\" Center=\"Node\">"
            << data_item(h5name, g + "/von_mises", {n}, Item::Float) << "</Attribute>\n";
      grids << "    <Attribute Name=\"element\" AttributeType=\"Scalar\" Center=\"Cell\">"
            << data_item(h5name, g + "/element", {nq}, Item::Int) << "</Attribute>\n"
            << "   </Grid>\n";
      nets  << "   <Grid Name=\"" << bn << "_control_net\" GridType=\"Uniform\">\n"
            << "    <Topology TopologyType=\"Quadrilateral\" NumberOfElements=\"" << mq << "\" NodesPerElement=\"4\">"
            << data_item(h5name, g + "/control_quads", {mq, 4}, Item::Int) << "</Topology>\n"
            << "    <Geometry GeometryType=\"XYZ\">" << data_item(h5name, g + "/control_xyz", {m, 3}) << "</Geometry>\n"
            << "    <Attribute Name=\"control_displacement\" AttributeType=\"Vector\" Center=\"Node\">"
            << data_item(h5name, g + "/control_displacement", {m, 3}) << "</Attribute>\n"
            << "   </Grid>\n";
    }
  return umax;
}

nlohmann::json probe_json(const Problem& P, const Probe& pr, const std::vector<double>& body_disp) {
  const Patch& pt = P.bodies[pr.body].patches[pr.patch];
  const BodyField field(P, pr.body, body_disp, pr.patch);
  if (pt.dim() == 3) {
    double t[3];
    for (int d = 0; d < 3; ++d) t[d] = pt.knots[d].front() + pr.at[d] * (pt.knots[d].back() - pt.knots[d].front());
    const FieldPoint fp = field.eval(t);
    return nlohmann::json({{"body", P.bodies[pr.body].name}, {"patch", pr.patch}, {"at", {pr.at[0], pr.at[1], pr.at[2]}},
                      {"x", fp.x}, {"y", fp.y}, {"z", fp.z}, {"displacement", {fp.ux, fp.uy, fp.uz}},
                      {"stress", {fp.sxx, fp.syy, fp.szz, fp.syz, fp.sxz, fp.sxy}}});
  }
  const double u = pt.knots[0].front() + pr.at[0] * (pt.knots[0].back() - pt.knots[0].front());
  const double v = pt.knots[1].front() + pr.at[1] * (pt.knots[1].back() - pt.knots[1].front());
  const FieldPoint fp = field.eval(u, v);
  return nlohmann::json({{"body", P.bodies[pr.body].name}, {"patch", pr.patch}, {"at", {pr.at[0], pr.at[1]}}, {"x", fp.x},
                    {"y", fp.y}, {"displacement", {fp.ux, fp.uy}}, {"stress", {fp.sxx, fp.syy, fp.sxy}}});
}

std::string xdmf_file(const std::string& run_id, const std::vector<std::string>& states) {
  std::ostringstream x;
  x << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n <Domain>\n  <Information Name=\"run_id\" Value=\"" << run_id
    << "\"/>\n  <Grid Name=\"load_steps\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (const auto& s : states) x << s;
  x << "  </Grid>\n </Domain>\n</Xdmf>\n";
  return x.str();
}

// ------------------------------------------------------------------ ResultWriter

ResultWriter::ResultWriter(const System& sys, std::string dir, std::string problem_file, std::string run_id)
    : sys_(sys), dir_(std::move(dir)), problem_file_(std::move(problem_file)), run_id_(std::move(run_id)) {
  history_ = nlohmann::json::array();
  files_ = nlohmann::json::object();
}


nlohmann::json ResultWriter::contact_json(const std::vector<ContactPairData>& contact) const {
  const Problem& P = sys_.problem();
  nlohmann::json out = nlohmann::json::array();
  for (const auto& c : contact) {
    const ContactSummary s = c.summary();
    if (P.dim() == 3) {   // solids: three force components, the contact area; with friction the
                          // tangential force [Tx, Ty, Tz] and the stick and slip areas
      nlohmann::json j = {{"master", {{"body", P.bodies[c.pair().master.body].name}, {"side", c.pair().master.label}}},
                          {"slave", {{"body", P.bodies[c.pair().slave.body].name}, {"side", c.pair().slave.label}}},
                          {"method", contact_method_name(c.pair().method)},
                          {"penalty", c.pair().penalty},
                          {"normal_force", s.normal_force},
                          {"force", {s.fx, s.fy, s.fz}},
                          {"max_pressure", s.max_pressure},
                          {"contact_area", s.contact_length},
                          {"max_penetration", s.max_penetration},
                          {"active_points", s.active_points},
                          {"friction", c.pair().friction}};
      if (c.friction()) {
        j["tangential_force"] = {s.tangential[0], s.tangential[1], s.tangential[2]};
        j["stick_area"] = s.stick_length;
        j["slip_area"] = s.slip_length;
      }
      out.push_back(j);
      continue;
    }
    out.push_back({{"master", {{"body", P.bodies[c.pair().master.body].name}, {"side", c.pair().master.label}}},
                   {"slave", {{"body", P.bodies[c.pair().slave.body].name}, {"side", c.pair().slave.label}}},
                   {"method", contact_method_name(c.pair().method)},
                   {"penalty", c.pair().penalty},
                   {"normal_force", s.normal_force},
                   {"force", {s.fx, s.fy}},
                   {"max_pressure", s.max_pressure},
                   {"contact_length", s.contact_length},
                   {"max_penetration", s.max_penetration},
                   {"active_points", s.active_points},
                   {"friction", c.pair().friction},
                   {"tangential_force", s.tangential_force},
                   {"stick_length", s.stick_length},
                   {"slip_length", s.slip_length}});
  }
  return out;
}

void ResultWriter::step(const StepState& st) {
  Teuchos::TimeMonitor tm(*Teuchos::TimeMonitor::getNewTimer("6) Output"));
  nlohmann::json h = {{"stage", st.stage}, {"step", st.step}, {"load_factor", st.lambda},
                      {"stage_fraction", st.load_factor}, {"cuts", st.cuts},
                      {"reactions", reactions_json(sys_, *st.residual)}};
  nlohmann::json pairs = nlohmann::json::array();
  for (const auto& c : contact_json(*st.contact))
    if (sys_.dim() == 3) {
      nlohmann::json j = {{"normal_force", c["normal_force"]}, {"force", c["force"]}, {"contact_area", c["contact_area"]},
                          {"max_pressure", c["max_pressure"]}};
      for (const char* key : {"tangential_force", "stick_area", "slip_area"})
        if (c.contains(key)) j[key] = c[key];
      pairs.push_back(j);
    } else
      pairs.push_back({{"normal_force", c["normal_force"]}, {"tangential_force", c["tangential_force"]}, {"force", c["force"]},
                       {"stick_length", c["stick_length"]}, {"slip_length", c["slip_length"]}});
  h["contact"] = pairs;
  history_.push_back(h);
  if (sys_.problem().output.all_steps) write_state(st.step, st.lambda, *st.u, *st.contact);
}

void ResultWriter::root_write(const std::function<void()>& f) {
  on_root(*sys_.comm(), [&] {
    try {
      f();
    } catch (...) {
      batch_.abandon();   // no .part file of a half-written state stays behind
      throw;
    }
  });
}

void ResultWriter::write(const std::string& name, const std::string& bytes) {
  write(name, std::vector<std::string_view>{std::string_view(bytes)});
}

void ResultWriter::write(const std::string& name, const std::vector<std::string_view>& pieces) {
  batch_.add((fs::path(dir_) / name).string(), pieces);
  std::size_t bytes = 0;
  for (const std::string_view& p : pieces) bytes += p.size();
  files_[name] = {{"bytes", bytes}, {"crc32", crc32_hex(pieces)}};
}

void ResultWriter::write_state(int step, double lambda, const Vector& u, const std::vector<ContactPairData>& contact) {
  const Problem& P = sys_.problem();
  const auto disp = gather_displacements(sys_, u);   // collective
  std::vector<ContactPointState> cstate;
  for (const auto& c : contact) cstate.push_back(c.state(true));   // the points with a projection
  written_.push_back({step, lambda});   // on every rank: finish() decides collectively from it
  root_write([&] {
    const std::string name = step_name(step), h5name = name + ".h5";
    H5Memory f(h5name);
    f.attribute("run_id", run_id_);
    f.attribute("load_factor", std::to_string(lambda));
    f.group("/bodies");
    // this step's spatial collections: bodies (result.xdmf), control nets
    // (result_control_nets.xdmf), contact points (result_contact.xdmf). Xdmf3ReaderS, the GUI's
    // default, reads a spatial collection as the pieces of ONE data set and ParaView appends
    // them for drawing, keeping only the arrays every piece has: a control net (no stress)
    // beside the bodies left nothing to colour by (grey bodies). So each file holds grids
    // with the same arrays (docs/paraview-xdmf-notes.md).
    std::ostringstream grids, nets, points;
    char tv[64];
    std::snprintf(tv, sizeof tv, "%.17g", lambda);
    for (std::ostringstream* o : {&grids, &nets, &points})
      *o << "  <Grid Name=\"step_" << name.substr(7) << "\" GridType=\"Collection\" CollectionType=\"Spatial\">\n"
         << "   <Time Value=\"" << tv << "\"/>\n";
    const int dim = P.dim();
    double umax = 0;
    {
      Teuchos::TimeMonitor t1(*Teuchos::TimeMonitor::getNewTimer("6.1) Output: sampled grid, control nets"));
      umax = write_bodies(f, h5name, P, disp, grids, nets);
    }
    if (!cstate.empty()) f.group("/contact");
    // a pair's contact points as an XDMF grid: polyvertices at the reference points, the
    // displacement, and the scalar arrays `names` of the HDF5 group g
    auto points_grid = [&](size_t k, const std::string& g, hsize_t n, std::initializer_list<const char*> names) {
      points << "   <Grid Name=\"contact_" << k << "\" GridType=\"Uniform\">\n"
             << "    <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << n << "\" NodesPerElement=\"1\">"
             << data_item(h5name, g + "/conn", {n}, Item::Int) << "</Topology>\n"
             << "    <Geometry GeometryType=\"XYZ\">" << data_item(h5name, g + "/xyz", {n, 3}) << "</Geometry>\n"
             << "    <Attribute Name=\"displacement\" AttributeType=\"Vector\" Center=\"Node\">"
             << data_item(h5name, g + "/displacement", {n, 3}) << "</Attribute>\n";
      for (const char* a : names)
        points << "    <Attribute Name=\"" << a << "\" AttributeType=\"Scalar\" Center=\"Node\">"
               << data_item(h5name, g + "/" + a, {n}) << "</Attribute>\n";
      points << "   </Grid>\n";
    };
    for (size_t k = 0; k < (dim == 3 ? cstate.size() : 0); ++k) {
      // 3-D: the slave points at their reference position with their displacement, their
      // parameters on the slave face, gap, pressure and whether they are active
      const auto& cs = cstate[k];
      const hsize_t n = cs.x.size();
      std::vector<double> d3(3 * n), act(n), xyz_def(3 * n);
      std::vector<int> conn(n);
      for (size_t i = 0; i < n; ++i) {
        const double xc[3] = {cs.x[i], cs.y[i], cs.z[i]};
        for (int c = 0; c < 3; ++c) {
          d3[3 * i + c] = xc[c] - cs.X[3 * i + c];
          xyz_def[3 * i + c] = xc[c];
        }
        act[i] = cs.active[i];
        conn[i] = static_cast<int>(i);
      }
      const std::string g = "/contact/pair_" + std::to_string(k);
      f.group(g);
      f.write_int(g + "/conn", conn, {n});
      f.write(g + "/xyz", cs.X, {n, 3});
      f.write(g + "/displacement", d3, {n, 3});
      f.write(g + "/xyz_deformed", xyz_def, {n, 3});
      f.write(g + "/gap", cs.gap, {n});
      f.write(g + "/pressure", cs.pressure, {n});
      f.write(g + "/xi", cs.xi, {n});
      f.write(g + "/eta", cs.eta, {n});
      f.write(g + "/active", act, {n});
      // friction (zeros when frictionless: every pair's grid has the same arrays): the length
      // of the tangential traction, the accumulated slip, the state (0 open, 1 stick, 2 slip)
      const std::vector<double> fstate(cs.state.begin(), cs.state.end());
      f.write(g + "/tangential_traction", cs.tangential, {n});
      f.write(g + "/slip", cs.slip, {n});
      f.write(g + "/state", fstate, {n});
      points_grid(k, g, n, {"gap", "pressure", "xi", "eta", "active", "tangential_traction", "slip", "state"});
    }
    for (size_t k = 0; k < (dim == 2 ? cstate.size() : 0); ++k) {
      // slave points in the reference configuration with their displacement, so that they
      // move with the bodies under any Warp By Vector scale
      const auto& cs = cstate[k];
      const ContactPair& pair = contact[k].pair();
      const Body& sb = P.bodies[pair.slave.body];
      const SurfaceChain& chain = contact[k].slave_chain();
      std::vector<BodyField> sfields;
      for (size_t q = 0; q < sb.patches.size(); ++q) sfields.emplace_back(P, pair.slave.body, disp[pair.slave.body], static_cast<int>(q));
      const hsize_t n = cs.x.size();
      std::vector<double> xyz, d3, xyz_def, active, state;
      std::vector<int> conn;
      for (size_t i = 0; i < n; ++i) {
        double pu, pv;
        const int q = chain.locate(sb.patches, cs.xi[i], pu, pv);
        const FieldPoint fp = sfields[q].eval(pu, pv);
        xyz.insert(xyz.end(), {fp.x, fp.y, 0.0});
        d3.insert(d3.end(), {fp.ux, fp.uy, 0.0});
        xyz_def.insert(xyz_def.end(), {cs.x[i], cs.y[i], 0.0});
        active.push_back(cs.active[i]);
        state.push_back(cs.state[i]);
        conn.push_back(static_cast<int>(i));
      }
      const std::string g = "/contact/pair_" + std::to_string(k);
      f.group(g);
      f.write_int(g + "/conn", conn, {n});
      f.write(g + "/xyz", xyz, {n, 3});
      f.write(g + "/displacement", d3, {n, 3});
      f.write(g + "/xyz_deformed", xyz_def, {n, 3});
      f.write(g + "/gap", cs.gap, {n});   // projected points only: every gap is defined
      f.write(g + "/pressure", cs.pressure, {n});
      f.write(g + "/xi", cs.xi, {n});
      f.write(g + "/active", active, {n});
      f.write(g + "/tangential_traction", cs.tangential, {n});
      f.write(g + "/slip", cs.slip, {n});
      f.write(g + "/state", state, {n});
      points_grid(k, g, n, {"gap", "pressure", "xi", "active", "tangential_traction", "slip", "state"});
    }
    for (std::ostringstream* o : {&grids, &nets, &points}) *o << "  </Grid>\n";
    write(h5name, f.image());
    // VTK writes string arrays as character codes: the run id also as a readable comment
    auto with_comment = [&](std::string xml) {
      xml.insert(xml.find('\n') + 1, "<!-- igacontact run_id " + run_id_ + " -->\n");
      return xml;
    };
    {
      // the cells' fits and the compression on the cores not taken by other ranks (as MUMPS'
      // threads)
      const int threads = free_cores_per_rank(sys_.comm()->getSize());
      BezierMesh mesh;
      {
        Teuchos::TimeMonitor t2(*Teuchos::TimeMonitor::getNewTimer("6.2) Output: Bezier cells"));
        mesh = bezier_mesh(P, disp, threads);
      }
      // output.compression (auto: zlib where the cells would take more than 400 bytes per dof)
      const bool zlib = P.output.compression == 1 ||
                        (P.output.compression < 0 && static_cast<double>(vtu_raw_bytes(mesh)) >
                                                         OutputOptions::kCompressAboveBytesPerDof * static_cast<double>(sys_.num_dofs()));
      Teuchos::TimeMonitor t3(*Teuchos::TimeMonitor::getNewTimer("6.3) Output: encoding"));
      // written piece by piece (the mesh outlives them)
      write(name + ".vtu", vtu_file(mesh, lambda, run_id_, zlib ? VtkEncoding::AppendedZlib : VtkEncoding::AppendedRaw, threads).parts);
      if (dim == 3) umax = mesh.max_displacement;   // 3-D: at the cells' evaluation points
    }

    // the collections over every state written so far, rewritten whole each time
    xdmf_grids_.push_back({grids.str(), nets.str(), points.str()});
    const char* xdmf_names[3] = {"result.xdmf", "result_control_nets.xdmf", "result_contact.xdmf"};
    for (int fi = dim == 3 ? 1 : 0; fi < 3; ++fi) {   // 3-D: no sampled grid, no result.xdmf
      std::vector<std::string> states;
      for (const auto& gs : xdmf_grids_) states.push_back(gs[fi]);
      write(xdmf_names[fi], xdmf_file(run_id_, states));
    }
    std::vector<std::pair<double, std::string>> vtus;
    for (const auto& w : written_) vtus.push_back({w.lambda, step_name(w.step) + ".vtu"});
    write("result.pvd", with_comment(pvd_collection(vtus)));
    Teuchos::TimeMonitor t4(*Teuchos::TimeMonitor::getNewTimer("6.4) Output: flush"));
    batch_.commit();   // the step's files: one flush, then their names
    max_displacement_ = umax;
  });
}

nlohmann::json ResultWriter::finish(const SolveResult& res) {
  Teuchos::TimeMonitor tm(*Teuchos::TimeMonitor::getNewTimer("6) Output"));
  const Problem& P = sys_.problem();
  // the kept state: written already when it is the last converged step
  const int kept = res.steps_converged;
  if (written_.empty() || written_.back().step != kept) write_state(kept, res.lambda, *res.u, res.contact);
  const auto disp = gather_displacements(sys_, *res.u);
  nlohmann::json summary;
  summary["problem"] = problem_file_;
  summary["run_id"] = run_id_;
  summary["converged"] = res.converged;
  summary["load_factor"] = res.lambda;
  summary["dofs"] = sys_.num_dofs();
  summary["ranks"] = sys_.comm()->getSize();
  summary["execution_space"] = ExecSpace::name();
  summary["threads_per_rank"] = ExecSpace::concurrency();
  const char* tun = std::getenv("GLIBC_TUNABLES");
  summary["malloc_huge_pages"] = tun != nullptr && std::strstr(tun, "glibc.malloc.hugetlb=1") != nullptr;
  summary["newton_iterations"] = res.newton_iterations;
  summary["cuts"] = res.cuts;
  summary["stages"] = P.stages;
  summary["linear_iterations"] = res.linear_iterations;
  summary["tangent_pattern_builds"] = res.tangent_rebuilds;
  summary["preconditioner_builds"] = res.preconditioner_builds;
  summary["linear_solver"] = linear_solver_json(P, res.direct, sys_.num_dofs());
  summary["reactions"] = reactions_json(sys_, *res.residual);
  if (!res.converged) summary["message"] = res.message;
  summary["contact"] = contact_json(res.contact);
  summary["history"] = history_;
  summary["output_steps"] = P.output.all_steps ? "all" : "last";
  std::vector<ContactPointState> cstate;
  for (const auto& c : res.contact) cstate.push_back(c.state(true));   // the points with a projection

  root_write([&] {
    // result.h5: the kept state, the same file as its result_<n>.h5 (a hard link; a copy
    // where the file system has none)
    const std::string last = step_name(kept) + ".h5";
    const fs::path from = fs::path(dir_) / last, to = fs::path(dir_) / "result.h5";
    std::error_code ec;
    fs::remove(to, ec);
    fs::create_hard_link(from, to, ec);
    if (ec) {
      std::ifstream in(from, std::ios::binary);
      std::stringstream ss;
      ss << in.rdbuf();
      if (!in) throw OutputError("cannot read back " + from.string());
      write("result.h5", ss.str());
    } else {
      files_["result.h5"] = files_[last];
    }

    nlohmann::json probes = nlohmann::json::array();
    for (const Probe& pr : P.output.probes) {
      probes.push_back(probe_json(P, pr, disp[pr.body]));
    }
    summary["probes"] = probes;

    // the refined geometry and the deformed control nets, for G+Smo and the tools that read
    // its XML: per body, the reference multipatch first (what a reader takes), then the
    // deformed one
    Teuchos::TimeMonitor t5(*Teuchos::TimeMonitor::getNewTimer("6.5) Output: geometry, csv, summary"));
    for (size_t b = 0; b < P.bodies.size(); ++b) {
      const MultiPatch ref = body_geometry(P.bodies[b]), def = body_geometry(P.bodies[b], &disp[b]);
      write("geometry_" + P.bodies[b].name + ".xml", gismo_xml_text({&ref, &def}));
    }
    summary["max_displacement"] = max_displacement_;

    for (size_t k = 0; k < cstate.size(); ++k) {
      const auto& s = cstate[k];
      std::ostringstream csv;
      csv.precision(12);
      auto num = [&](double v) -> std::ostream& {
        if (std::isfinite(v)) csv << v;
        return csv;
      };
      if (P.dim() == 3) {   // solids: ../docs/problem-file.md, "Outputs"
        const bool fric = res.contact[k].friction();
        csv << "x,y,z,xi,eta,gap,pressure,active" << (fric ? ",tx,ty,tz,slip,state" : "") << "\n";
        for (size_t i = 0; i < s.x.size(); ++i) {
          for (double v : {s.x[i], s.y[i], s.z[i], s.xi[i], s.eta[i], s.gap[i], s.pressure[i]}) num(v) << ",";
          csv << s.active[i];
          if (fric) {
            for (double v : {s.tx[i], s.ty[i], s.tz[i], s.slip[i]}) {
              csv << ",";
              num(v);
            }
            csv << "," << s.state[i];
          }
          csv << "\n";
        }
        write("contact_" + std::to_string(k) + ".csv", csv.str());
        continue;
      }
      csv << "x,y,xi,gap,pressure,active,tangential_traction,slip,state\n";
      // the slave points with a projection on the master (state(true)): every value is
      // defined; a value that is not finite all the same is left empty, never written as nan
      for (size_t i = 0; i < s.x.size(); ++i) {
        num(s.x[i]) << ",";
        num(s.y[i]) << ",";
        num(s.xi[i]) << ",";
        num(s.gap[i]) << ",";
        num(s.pressure[i]) << "," << s.active[i] << ",";
        num(s.tangential[i]) << ",";
        num(s.slip[i]) << "," << s.state[i] << "\n";
      }
      write("contact_" + std::to_string(k) + ".csv", csv.str());
    }
    batch_.commit();
    summary["files"] = files_;
  });
  return summary;
}

}  // namespace iga
