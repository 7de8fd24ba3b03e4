// Problem file: checks of the whole problem: rigid-body freedom, floating-point scales, and
// whether it fits the machine.
#include "model/yaml_reader.hpp"
#include "kernels/numbering.hpp"
#include "model/rigid_modes.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <cmath>
#include <filesystem>
#include <functional>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>

namespace iga {

namespace detail {

// Rank of the rigid-body modes (model/rigid_modes.hpp) restricted to the constrained dofs of a
// body: num_rigid_modes(dim) means no rigid motion is left free.
int rigid_rank(const Body& b) {
  const int dim = b.patches.front().dim(), nm = num_rigid_modes(dim);
  double G[kMaxRigidModes][kMaxRigidModes] = {};
  auto add = [&](const ControlPoint& cp, int c) {
    double row[kMaxRigidModes];
    for (int m = 0; m < nm; ++m) row[m] = rigid_mode(m, c, cp.x.data(), dim);
    for (int i = 0; i < nm; ++i)
      for (int j = 0; j < nm; ++j) G[i][j] += row[i] * row[j];
  };
  for (size_t k = 0; k < b.patches.size(); ++k) {
    for (int s = 0; s < num_sides(dim); ++s)
      for (int c = 0; c < dim; ++c)
        if (b.sides[k][s].fixed[c])
          for (int a : b.patches[k].side_indices(static_cast<Side>(s))) add(b.patches[k].cp[a], c);
    if (dim == 2)
      for (int s = 0; s < 4; ++s)
        for (int c = 0; c < dim; ++c)
          if (b.corners[k][s].fixed[c]) add(b.patches[k].cp[corner_index(b.patches[k], static_cast<Corner>(s))], c);
  }
  // rank by Gaussian elimination with full pivoting on the nm x nm Gram matrix
  double scale = 0;
  for (int i = 0; i < nm; ++i) scale = std::max(scale, G[i][i]);
  if (scale == 0) return 0;
  int rank = 0;
  bool used_r[kMaxRigidModes] = {}, used_c[kMaxRigidModes] = {};
  for (int k = 0; k < nm; ++k) {
    int pr = -1, pc = -1;
    double best = 0;
    for (int i = 0; i < nm; ++i)
      for (int j = 0; j < nm; ++j)
        if (!used_r[i] && !used_c[j] && std::abs(G[i][j]) > best) { best = std::abs(G[i][j]); pr = i; pc = j; }
    if (pr < 0 || best < 1e-10 * scale) break;
    used_r[pr] = used_c[pc] = true;
    ++rank;
    for (int i = 0; i < nm; ++i)
      if (!used_r[i]) {
        const double f = G[i][pc] / G[pr][pc];
        for (int j = 0; j < nm; ++j) G[i][j] -= f * G[pr][j];
      }
  }
  return rank;
}

void check_problem(const Reader& R, const YAML::Node& root, Problem& P) {
  const YAML::Node bodies = root["bodies"];
  // Scales: stiffness and penalty times thickness must stay normal floating-point numbers
  // (a thickness of 1e-320 made every stiffness vanish and "converged" at zero displacement).
  for (size_t b = 0; b < P.bodies.size(); ++b) {
    const double et = P.bodies[b].E * P.thickness;
    if (!(std::isfinite(et) && et >= std::numeric_limits<double>::min()))
      R.fail(root["analysis"] && root["analysis"]["thickness"] ? "analysis.thickness" : "bodies[" + std::to_string(b) + "].material.youngs_modulus",
             root["analysis"] && root["analysis"]["thickness"] ? root["analysis"]["thickness"] : bodies[b]["material"]["youngs_modulus"],
             "youngs_modulus x thickness of body '" + P.bodies[b].name + "' is not a normal floating-point number; rescale the units");
  }
  for (size_t k = 0; k < P.contact.size(); ++k) {
    const double pt = P.contact[k].penalty * P.thickness;
    if (!(std::isfinite(pt) && pt >= std::numeric_limits<double>::min()))
      R.fail("contact[" + std::to_string(k) + "].penalty", root["contact"][k]["penalty"],
             "penalty x thickness is not a normal floating-point number; rescale the units");
  }

  // The whole problem, output samples included, must fit the machine.
  {
    double dofs = 0, out_bytes = 0;
    int degree = 1;
    for (const auto& b : P.bodies) {
      dofs += static_cast<double>(P.dim()) * b.num_cps;
      for (const Patch& q : b.patches) {
        for (int d = 0; d < q.dim(); ++d) degree = std::max(degree, q.degree[d]);
        if (q.dim() == 2) {
          out_bytes += R.sample_bytes(static_cast<double>(q.element_spans(0).size()), static_cast<double>(q.element_spans(1).size()));
          continue;
        }
        // 3-D: the Bezier points of the .vtu on rank 0, about 112 bytes each (io/vtk): the
        // boundary faces, or every element's hexahedron with output.cells: volume
        double pts[3];
        for (int d = 0; d < 3; ++d) pts[d] = q.degree[d] * static_cast<double>(q.num_elements(d)) + 1;
        out_bytes += 112.0 * (P.output.volume_cells ? pts[0] * pts[1] * pts[2]
                                                    : 2 * (pts[0] * pts[1] + pts[1] * pts[2] + pts[0] * pts[2]));
      }
    }
    const bool output_dominates = out_bytes > 0.5 * dofs * bytes_per_dof_estimate(degree, P.dim());
    if (output_dominates && root["output"] && root["output"]["samples_per_element"])
      R.fits("output.samples_per_element", root["output"]["samples_per_element"], dofs, degree, out_bytes, P.dim());
    else
      R.fits("bodies", bodies, dofs, degree, out_bytes, P.dim());
  }

  // Rigid-body motion: a body that no contact pair touches must be held by its supports.
  for (size_t b = 0; b < P.bodies.size(); ++b) {
    bool in_contact = false;
    for (const auto& c : P.contact) in_contact = in_contact || c.master.body == (int)b || c.slave.body == (int)b;
    if (!in_contact && rigid_rank(P.bodies[b]) < num_rigid_modes(P.dim()))
      R.fail("bodies[" + std::to_string(b) + "].boundary", bodies[b]["boundary"],
             "body '" + P.bodies[b].name +
                 "' is free to move as a rigid body (singular system): prescribe " +
                 std::string(P.dim() == 3 ? "x, y and z" : "x and y") + " displacements that fix translation and rotation");
  }

  // Bodies joined by contact pairs move together as a rigid body along a direction none of
  // them is held in: contact is internal to them, so the system is singular whatever the
  // loads (a support block without boundary conditions under a block held in x only ran to
  // MUMPS' null pivot, exit 3, 11 files written and no body named; found by a problem written
  // from the docs). Translations only: a rotation can be held by contact against a supported
  // body (a wheel on a block).
  {
    const int nb = static_cast<int>(P.bodies.size());
    std::vector<int> root_of(nb);
    for (int b = 0; b < nb; ++b) root_of[b] = b;
    const auto find = [&](int b) {
      while (root_of[b] != b) b = root_of[b] = root_of[root_of[b]];
      return b;
    };
    for (const auto& c : P.contact) root_of[find(c.master.body)] = find(c.slave.body);
    const char* axis = "xyz";
    for (int r = 0; r < nb; ++r) {
      if (find(r) != r) continue;
      std::vector<int> members;
      for (int b = 0; b < nb; ++b)
        if (find(b) == r) members.push_back(b);
      if (members.size() < 2) continue;   // (a body alone: the check above)
      for (int c = 0; c < P.dim(); ++c) {
        bool held = false;
        for (int b : members) {
          const Body& body = P.bodies[b];
          for (size_t k = 0; k < body.patches.size() && !held; ++k) {
            for (const SideCondition& sc : body.sides[k]) held = held || sc.fixed[c];
            if (P.dim() == 2)
              for (const SideCondition& sc : body.corners[k]) held = held || sc.fixed[c];
          }
        }
        if (held) continue;
        std::string names;
        for (size_t i = 0; i < members.size(); ++i)
          names += (i == 0 ? "'" : i + 1 == members.size() ? "' and '" : "', '") + P.bodies[members[i]].name;
        names += "'";
        const int first = members.front();
        R.fail("bodies[" + std::to_string(first) + "].boundary", bodies[first]["boundary"],
               "bodies " + names + ", joined by contact, have no displacement " + axis[c] +
                   " prescribed on any side: together they are free to move along " + axis[c] +
                   " (singular system); prescribe " + axis[c] + " on a side of one of them");
      }
    }
  }
}

// MemAvailable of /proc/meminfo in bytes (0 where unknown), or less where the environment's
// IGACONTACT_MEMORY_LIMIT (bytes) says so: a shared machine, or the fuzzer, which must not
// spend its time refining a valid 2e7-dof mesh.
double available_memory_bytes() {
  std::ifstream in("/proc/meminfo");
  std::string key;
  double kib = 0, bytes = 0;
  std::string unit;
  while (in >> key >> kib >> unit)
    if (key == "MemAvailable:") { bytes = kib * 1024.0; break; }
  if (const char* lim = std::getenv("IGACONTACT_MEMORY_LIMIT")) {
    char* end = nullptr;
    const double l = std::strtod(lim, &end);
    if (end != lim && l > 0 && std::isfinite(l)) bytes = bytes > 0 ? std::min(bytes, l) : l;
  }
  return bytes;
}

}  // namespace detail

}  // namespace iga
