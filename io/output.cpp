#include "io/output.hpp"

#include <hdf5.h>
#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_TimeMonitor.hpp>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "io/fields.hpp"
#include "io/files.hpp"

namespace iga {

namespace fs = std::filesystem;

std::vector<std::vector<double>> gather_displacements(const System& sys, const Vector& u) {
  const bool root = sys.comm()->getRank() == 0;
  std::vector<GO> all;
  if (root)
    for (GO g = 0; g < sys.num_dofs(); ++g) all.push_back(g);
  RCP<const Map> m = rcp(new Map(Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid(), all, 0, sys.comm()));
  Vector full(m);
  Import importer(u.getMap(), m);
  full.doImport(u, importer, Tpetra::INSERT);
  std::vector<std::vector<double>> out;
  if (!root) return out;
  auto h = full.getLocalViewHost(Tpetra::Access::ReadOnly);
  for (size_t b = 0; b < sys.bodies().size(); ++b) {
    const size_t n = sys.problem().bodies[b].patch.cp.size();
    std::vector<double> v(2 * n);
    for (size_t k = 0; k < 2 * n; ++k) v[k] = h(2 * sys.bodies()[b].cp_offset + k, 0);
    out.push_back(std::move(v));
  }
  return out;
}

nlohmann::json reactions_json(const System& sys, const Vector& residual) {
  const Problem& P = sys.problem();
  const size_t nb = P.bodies.size();
  std::vector<double> local(nb * 8, 0.0), global(nb * 8, 0.0);
  auto h = residual.getLocalViewHost(Tpetra::Access::ReadOnly);
  for (const DirichletDof& d : sys.dirichlet()) {
    const LO l = sys.owned_map()->getLocalElement(d.dof);
    local[d.body * 8 + d.side * 2 + d.dof % 2] += -h(l, 0);
  }
  Teuchos::reduceAll(*sys.comm(), Teuchos::REDUCE_SUM, static_cast<int>(local.size()), local.data(), global.data());
  nlohmann::json j = nlohmann::json::object();
  for (size_t b = 0; b < nb; ++b) {
    nlohmann::json sides = nlohmann::json::object();
    for (int s = 0; s < 4; ++s) {
      const auto& sc = P.bodies[b].sides[s];
      if (sc.fixed[0] || sc.fixed[1]) sides[side_name(static_cast<Side>(s))] = {global[b * 8 + 2 * s], global[b * 8 + 2 * s + 1]};
    }
    if (!sides.empty()) j[P.bodies[b].name] = sides;
  }
  return j;
}

namespace {

std::string dims_str(const std::vector<hsize_t>& d) {
  std::string s;
  for (hsize_t x : d) s += (s.empty() ? "" : " ") + std::to_string(x);
  return s;
}

std::string data_item(const std::string& path, const std::vector<hsize_t>& d) {
  return "<DataItem Dimensions=\"" + dims_str(d) + "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">result.h5:" +
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

}  // namespace

nlohmann::json write_results(const System& sys, const SolveResult& res, const std::string& dir,
                             const std::string& problem_file, const std::string& run_id) {
  Teuchos::TimeMonitor tm(*Teuchos::TimeMonitor::getNewTimer("6) Output"));
  const Problem& P = sys.problem();
  const auto disp = gather_displacements(sys, *res.u);
  nlohmann::json summary;
  summary["problem"] = problem_file;
  summary["run_id"] = run_id;
  summary["converged"] = res.converged;
  summary["load_factor"] = res.lambda;
  summary["dofs"] = sys.num_dofs();
  summary["ranks"] = sys.comm()->getSize();
  summary["execution_space"] = ExecSpace::name();
  summary["threads_per_rank"] = ExecSpace::concurrency();
  const char* tun = std::getenv("GLIBC_TUNABLES");
  summary["malloc_huge_pages"] = tun != nullptr && std::strstr(tun, "glibc.malloc.hugetlb=1") != nullptr;
  summary["newton_iterations"] = res.newton_iterations;
  summary["linear_iterations"] = res.linear_iterations;
  summary["tangent_pattern_builds"] = res.tangent_rebuilds;
  summary["preconditioner_builds"] = res.preconditioner_builds;
  summary["reactions"] = reactions_json(sys, *res.residual);
  if (!res.converged) summary["message"] = res.message;

  // contact state (replicated on all ranks)
  nlohmann::json contact = nlohmann::json::array();
  std::vector<ContactPointState> cstate;
  for (const auto& c : res.contact) {
    const ContactSummary s = c.summary();
    contact.push_back({{"master", {{"body", P.bodies[c.pair().master.body].name}, {"side", side_name(c.pair().master.side)}}},
                       {"slave", {{"body", P.bodies[c.pair().slave.body].name}, {"side", side_name(c.pair().slave.side)}}},
                       {"method", contact_method_name(c.pair().method)},
                       {"normal_force", s.normal_force},
                       {"force", {s.fx, s.fy}},
                       {"max_pressure", s.max_pressure},
                       {"contact_length", s.contact_length},
                       {"max_penetration", s.max_penetration},
                       {"active_points", s.active_points}});
    cstate.push_back(c.state());
  }
  summary["contact"] = contact;

  nlohmann::json files = nlohmann::json::object();   // name -> {bytes, crc32}, rank 0
  auto write = [&](const std::string& name, const std::string& bytes) {
    write_file_atomic((fs::path(dir) / name).string(), bytes);
    files[name] = {{"bytes", bytes.size()}, {"crc32", crc32_hex(bytes)}};
  };
  on_root(*sys.comm(), [&] {
    // probes
    nlohmann::json probes = nlohmann::json::array();
    std::vector<BodyField> fields;
    for (size_t b = 0; b < P.bodies.size(); ++b) fields.emplace_back(P, static_cast<int>(b), disp[b]);
    for (const Probe& pr : P.output.probes) {
      const Patch& pt = P.bodies[pr.body].patch;
      const double u = pt.knots[0].front() + pr.at[0] * (pt.knots[0].back() - pt.knots[0].front());
      const double v = pt.knots[1].front() + pr.at[1] * (pt.knots[1].back() - pt.knots[1].front());
      const FieldPoint f = fields[pr.body].eval(u, v);
      probes.push_back({{"body", P.bodies[pr.body].name}, {"at", {pr.at[0], pr.at[1]}}, {"x", f.x}, {"y", f.y},
                        {"displacement", {f.ux, f.uy}}, {"stress", {f.sxx, f.syy, f.sxy}}});
    }
    summary["probes"] = probes;

    // result.h5 / result.xdmf
    const std::string h5 = (fs::path(dir) / "result.h5").string();
    std::ostringstream xdmf;
    xdmf << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n <Domain>\n  <Information Name=\"run_id\" Value=\"" << run_id
         << "\"/>\n  <Grid Name=\"igacontact\" GridType=\"Collection\">\n";
    {
      H5Memory f(h5);
      f.attribute("run_id", run_id);
      f.group("/bodies");
      for (size_t b = 0; b < P.bodies.size(); ++b) {
        const Patch& pt = P.bodies[b].patch;
        const auto su = samples(pt.knots[0], pt.element_spans(0), P.output.samples_per_element);
        const auto sv = samples(pt.knots[1], pt.element_spans(1), P.output.samples_per_element);
        const hsize_t n0 = su.size(), n1 = sv.size();
        std::vector<double> x, y, d3, sxx, syy, sxy, szz, vm;
        for (const auto& v : sv)
          for (const auto& u : su) {
            const FieldPoint fp = fields[b].eval(u.first, v.first, u.second, v.second);
            x.push_back(fp.x); y.push_back(fp.y);
            d3.insert(d3.end(), {fp.ux, fp.uy, 0.0});
            sxx.push_back(fp.sxx); syy.push_back(fp.syy); sxy.push_back(fp.sxy); szz.push_back(fp.szz);
            vm.push_back(fp.von_mises());
          }
        const std::string g = "/bodies/" + P.bodies[b].name;
        f.group(g);
        f.write(g + "/x", x, {n1, n0});
        f.write(g + "/y", y, {n1, n0});
        f.write(g + "/displacement", d3, {n1, n0, 3});
        f.write(g + "/sxx", sxx, {n1, n0});
        f.write(g + "/syy", syy, {n1, n0});
        f.write(g + "/sxy", sxy, {n1, n0});
        f.write(g + "/szz", szz, {n1, n0});
        f.write(g + "/von_mises", vm, {n1, n0});
        std::vector<double> cx, cy;
        for (const auto& c : pt.cp) { cx.push_back(c[0]); cy.push_back(c[1]); }
        f.write(g + "/control_x", cx, {(hsize_t)pt.ncp(1), (hsize_t)pt.ncp(0)});
        f.write(g + "/control_y", cy, {(hsize_t)pt.ncp(1), (hsize_t)pt.ncp(0)});
        f.write(g + "/control_displacement", disp[b], {(hsize_t)pt.ncp(1), (hsize_t)pt.ncp(0), 2});
        xdmf << "   <Grid Name=\"" << P.bodies[b].name << "\" GridType=\"Uniform\">\n"
             << "    <Topology TopologyType=\"2DSMesh\" Dimensions=\"" << n1 << " " << n0 << "\"/>\n"
             << "    <Geometry GeometryType=\"X_Y\">\n     " << data_item(g + "/x", {n1, n0}) << "\n     "
             << data_item(g + "/y", {n1, n0}) << "\n    </Geometry>\n"
             << "    <Attribute Name=\"displacement\" AttributeType=\"Vector\" Center=\"Node\">\n     "
             << data_item(g + "/displacement", {n1, n0, 3}) << "\n    </Attribute>\n";
        for (const char* s : {"sxx", "syy", "sxy", "szz", "von_mises"})
          xdmf << "    <Attribute Name=\"" << s << "\" AttributeType=\"Scalar\" Center=\"Node\">\n     "
               << data_item(g + "/" + s, {n1, n0}) << "\n    </Attribute>\n";
        xdmf << "   </Grid>\n";
      }
      if (!cstate.empty()) f.group("/contact");
      for (size_t k = 0; k < cstate.size(); ++k) {
        const auto& s = cstate[k];
        const hsize_t n = s.x.size();
        std::vector<double> xyz, gap(s.gap), pr(s.pressure);
        for (size_t i = 0; i < n; ++i) xyz.insert(xyz.end(), {s.x[i], s.y[i], 0.0});
        for (double& gv : gap)
          if (!std::isfinite(gv)) gv = std::nan("");
        const std::string g = "/contact/pair_" + std::to_string(k);
        f.group(g);
        f.write(g + "/xyz", xyz, {n, 3});
        f.write(g + "/gap", gap, {n});
        f.write(g + "/pressure", pr, {n});
        f.write(g + "/xi", s.xi, {n});
        xdmf << "   <Grid Name=\"contact_" << k << "\" GridType=\"Uniform\">\n"
             << "    <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << n << "\"/>\n"
             << "    <Geometry GeometryType=\"XYZ\">\n     " << data_item(g + "/xyz", {n, 3}) << "\n    </Geometry>\n";
        for (const char* a : {"gap", "pressure"})
          xdmf << "    <Attribute Name=\"" << a << "\" AttributeType=\"Scalar\" Center=\"Node\">\n     "
               << data_item(g + "/" + a, {n}) << "\n    </Attribute>\n";
        xdmf << "   </Grid>\n";
      }
      write("result.h5", f.image());
    }
    xdmf << "  </Grid>\n </Domain>\n</Xdmf>\n";
    write("result.xdmf", xdmf.str());

    for (size_t k = 0; k < cstate.size(); ++k) {
      const auto& s = cstate[k];
      std::ostringstream csv;
      csv.precision(12);
      csv << "x,y,xi,gap,pressure,active\n";
      for (size_t i = 0; i < s.x.size(); ++i)
        csv << s.x[i] << "," << s.y[i] << "," << s.xi[i] << "," << s.gap[i] << "," << s.pressure[i] << ","
            << s.active[i] << "\n";
      write("contact_" + std::to_string(k) + ".csv", csv.str());
    }
  });
  summary["files"] = files;
  return summary;
}

}  // namespace iga
