// Problem file: contact surfaces (chains of patch sides) and the contact pairs.
#include "model/yaml_reader.hpp"
#include "model/configuration_check.hpp"

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

SurfaceChain surface_chain(const Problem& P, const ContactSurface& s) {
  const Body& b = P.bodies[s.body];
  return make_chain(b.patches, s.sides, b.tolerance);
}

namespace detail {

ContactSurface read_surface(const Reader& R, const Problem& P, const YAML::Node& n, const std::string& path) {
  R.keys(n, path, {"body", "side"});
  if (!n["body"]) R.missing(path + ".body");
  if (!n["side"]) R.missing(path + ".side");
  ContactSurface s;
  s.body = P.find_body(R.string(n["body"], path + ".body"));
  if (s.body < 0) R.fail(path + ".body", n["body"], "no body of that name");
  const Body& b = P.bodies[s.body];
  const YAML::Node sd = n["side"];
  std::vector<std::pair<std::string, YAML::Node>> names;
  if (sd.IsSequence()) {
    if (sd.size() == 0) R.fail(path + ".side", sd, "expected a side or a list of patch sides");
    for (size_t k = 0; k < sd.size(); ++k) names.push_back({R.string(sd[k], path + ".side[" + std::to_string(k) + "]"), sd[k]});
  } else {
    names.push_back({R.string(sd, path + ".side"), sd});
  }
  for (const auto& [name, node] : names) {
    for (const auto& pl : boundary_places(R, b, name, path + ".side", node, false)) {
      if (b.is_interface(pl.first))
        R.fail(path + ".side", node, patch_side_name(pl.first) + " is an interface between patches, inside the body: no contact there");
      s.sides.push_back(pl.first);
    }
    s.label += (s.label.empty() ? "" : "+") + name;
  }
  if (R.dim == 3) {   // a solid: a list of patch faces (kernels/contact_kts3.hpp holds at most kMaxContactFaces)
    if (s.sides.size() > static_cast<size_t>(kMaxContactFaces))
      R.fail(path + ".side", sd, "a 3-D contact surface holds at most " + std::to_string(kMaxContactFaces) + " faces");
    for (const PatchSide& ps : s.sides)
      if (side_collapsed(b.patches[ps.patch], ps.side, b.tolerance))
        R.fail(path + ".side", sd, patch_side_name(ps) + " is collapsed (no area): no contact there");
    return s;
  }
  try {
    const SurfaceChain ch = make_chain(b.patches, s.sides, b.tolerance);
    // the joints must be shared control points (one dof), not two that merely touch
    const size_t np = ch.pieces.size(), joints = np > 1 ? np - 1 + (ch.closed ? 1 : 0) : 0;
    for (size_t k = 0; k < joints; ++k) {
      const auto& A = ch.pieces[k];
      const auto& B = ch.pieces[(k + 1) % np];
      const auto ia = b.patches[A.side.patch].side_indices(A.side.side), ib = b.patches[B.side.patch].side_indices(B.side.side);
      const int ea = A.reversed ? ia.front() : ia.back(), sb = B.reversed ? ib.back() : ib.front();
      if (b.cp_index[A.side.patch][ea] != b.cp_index[B.side.patch][sb])
        throw std::invalid_argument(patch_side_name(A.side) + " and " + patch_side_name(B.side) +
                                    " touch at a point that is not shared by an interface of their patches");
    }
  } catch (const std::invalid_argument& e) {
    R.fail(path + ".side", sd, e.what());
  }
  return s;
}

void read_contact_pairs(const Reader& R, const YAML::Node& root, Problem& P) {
  if (root["contact"]) {
    const YAML::Node c = root["contact"];
    if (!c.IsSequence()) R.fail("contact", c, "expected a list of contact pairs");
    for (size_t k = 0; k < c.size(); ++k) {
      const std::string path = "contact[" + std::to_string(k) + "]";
      const YAML::Node n = c[k];
      R.keys(n, path, {"master", "slave", "method", "penalty", "quadrature_points", "segment_cells", "augmentations",
                       "alm_tolerance", "friction", "tangential_penalty"});
      ContactPair cp;
      if (!n["master"]) R.missing(path + ".master");
      if (!n["slave"]) R.missing(path + ".slave");
      cp.master = read_surface(R, P, n["master"], path + ".master");
      cp.slave = read_surface(R, P, n["slave"], path + ".slave");
      // self-contact: two different sides (or chains of patch sides) of one body
      if (cp.master.body == cp.slave.body)
        for (const PatchSide& ps : cp.slave.sides)
          if (std::find(cp.master.sides.begin(), cp.master.sides.end(), ps) != cp.master.sides.end())
            R.fail(path + ".slave", n["slave"],
                   cp.master.sides == cp.slave.sides
                       ? std::string("master and slave are the same side of the same body")
                       : "master and slave share the side " + P.bodies[cp.slave.body].side_label(ps.patch, ps.side) +
                             " of body '" + P.bodies[cp.slave.body].name + "'");
      // an interface declared twice (repeated, or with the roles swapped): each pair carries
      // its own share of the contact, so each would report about half of it (found by a
      // problem written from the docs: pressure 5 reported on each of two pairs where 10 acts)
      for (size_t j = 0; j < P.contact.size(); ++j) {
        const ContactPair& o = P.contact[j];
        auto meet = [](const ContactSurface& a, const ContactSurface& b) {
          if (a.body != b.body) return false;
          for (const PatchSide& ps : a.sides)
            if (std::find(b.sides.begin(), b.sides.end(), ps) != b.sides.end()) return true;
          return false;
        };
        const bool same = meet(cp.slave, o.slave) && meet(cp.master, o.master);
        const bool swapped = meet(cp.slave, o.master) && meet(cp.master, o.slave);
        if (same || swapped)
          R.fail(path + ".slave", n["slave"],
                 "contact[" + std::to_string(j) + "] already joins " + P.bodies[o.slave.body].name + "." + o.slave.label +
                     " and " + P.bodies[o.master.body].name + "." + o.master.label +
                     (swapped ? " (with the roles swapped)" : "") +
                     ": each pair would carry its own share of that contact and report about half of it; declare each "
                     "interface once");
      }
      if (n["method"]) {
        const std::string m = R.string(n["method"], path + ".method");
        if (m == "kts_penalty") cp.method = ContactMethod::KtsPenalty;
        else if (m == "kts_alm") cp.method = ContactMethod::KtsAlm;
        else if (m == "mortar_penalty") cp.method = ContactMethod::MortarPenalty;
        else if (m == "mortar_alm") cp.method = ContactMethod::MortarAlm;
        else R.fail(path + ".method", n["method"], "expected kts_penalty, kts_alm, mortar_penalty or mortar_alm");
      }
      if (!n["penalty"]) R.missing(path + ".penalty");
      cp.penalty = R.positive(n["penalty"], path + ".penalty");
      if (n["quadrature_points"]) {
        cp.quadrature_points = R.integer(n["quadrature_points"], path + ".quadrature_points");
        if (cp.quadrature_points < 1 || cp.quadrature_points > kMaxContactQuadrature)
          R.fail(path + ".quadrature_points", n["quadrature_points"],
                 "must be 1.." + std::to_string(kMaxContactQuadrature));
      }
      if (n["segment_cells"]) {   // 3-D mortar: see solver/contact3d.hpp (ContactSurfaces3::cells)
        cp.segment_cells = R.integer(n["segment_cells"], path + ".segment_cells");
        if (cp.segment_cells < 1 || cp.segment_cells > kMaxSegmentCells)
          R.fail(path + ".segment_cells", n["segment_cells"], "must be 1.." + std::to_string(kMaxSegmentCells));
        if (P.dim() != 3 || (cp.method != ContactMethod::MortarPenalty && cp.method != ContactMethod::MortarAlm))
          R.fail(path + ".segment_cells", n["segment_cells"],
                 "applies to the mortar methods between solids (3-D) only: the cells of each master element in the segmentation");
      }
      if (n["augmentations"]) {
        cp.augmentations = R.integer(n["augmentations"], path + ".augmentations");
        if (cp.augmentations < 1) R.fail(path + ".augmentations", n["augmentations"], "must be >= 1");
      }
      if (n["alm_tolerance"]) cp.alm_tolerance = R.positive(n["alm_tolerance"], path + ".alm_tolerance");
      if (n["friction"]) {
        cp.friction = R.number(n["friction"], path + ".friction");
        if (!(cp.friction >= 0) || !std::isfinite(cp.friction))
          R.fail(path + ".friction", n["friction"], "the Coulomb coefficient must be a number >= 0");
      }
      cp.tangential_penalty = n["tangential_penalty"] ? R.positive(n["tangential_penalty"], path + ".tangential_penalty")
                                                      : cp.penalty;
      if (!(cp.tangential_penalty * P.thickness >= std::numeric_limits<double>::min()) ||
          !std::isfinite(cp.tangential_penalty * P.thickness))
        R.fail(path + ".tangential_penalty", n["tangential_penalty"] ? n["tangential_penalty"] : n["penalty"],
               "tangential_penalty x thickness is not a normal floating-point number; rescale the units");
      // a slave side that faces away from its master never touches it: the run would end
      // with no contact and exit 0
      std::string overlap;
      bool master_at_fault = false;
      const std::string facing = check_pair_facing(P, cp, &overlap, &master_at_fault);
      if (!facing.empty())
        R.fail(path + (master_at_fault ? ".master" : ".slave"), n[master_at_fault ? "master" : "slave"], facing);
      if (!overlap.empty()) P.warnings.push_back(R.file + ": " + path + ": " + overlap);
      P.contact.push_back(cp);
      const std::string warn = penalty_warning(P, static_cast<int>(P.contact.size()) - 1);
      if (!warn.empty()) P.warnings.push_back(R.file + ": " + warn);
    }
  }
}

}  // namespace detail

}  // namespace iga
