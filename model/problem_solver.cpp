// Problem file: solver options (Newton, the linear method and preconditioner, MueLu's XML),
// the automatic linear method and the symmetry of the tangent.
#include "kernels/sides.hpp"
#include "model/yaml_reader.hpp"
#include "solver/amg_loader.hpp"   // MueLu's parameter names, from the multigrid module
#include <Teuchos_XMLParameterListHelpers.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <functional>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

namespace iga {

// auto: not for the direct solver (its factorisations are exact, and its GMRES on kept factors
// solves to the tolerance), and not with friction: the inexact steps of the wheel with mortar
// friction 0.3 sent points through slip on the way, and the step ended in a different stick
// state (tangential force 1.3e-4 apart, whatever Newton's tolerance), where every exact path
// ended in the same one.
bool eisenstat_walker_forcing(const Problem& P) {
  if (P.linear.forcing != Forcing::Auto) return P.linear.forcing == Forcing::EisenstatWalker;
  // a linear problem (small strain, no contact) is solved by one linear solve to the fixed
  // tolerance, after which Newton's residual check passes: inexact steps took 3 (issue 34)
  const bool linear = P.contact.empty() && P.kinematics == Kinematics::Small;
  return P.linear.method != LinearMethod::Direct && !P.has_friction() && !linear;
}

// auto: off. Measured (docs/performance.md, "Extrapolated starts"): the sliding and friction
// examples at small strain took fewer Newton iterations (sliding box 3-D 18 -> 8, sliding
// block 22 -> 12, friction cycle 89 -> 68), but a contact zone that grows with the load does
// not continue linearly (Hertz ball 21 -> 22, the Cattaneo-Mindlin sphere's press far worse), and
// at finite strain the linearised predictor starts closer (2-D ironing 309 -> 441).
bool extrapolated_start(const Problem& P) {
  using E = NewtonOptions::Extrapolate;
  return P.newton.extrapolate == E::On;
}

bool Problem::has_friction() const {
  return std::any_of(contact.begin(), contact.end(), [](const ContactPair& c) { return c.friction > 0; });
}

// solver.linear.method: auto takes MUMPS up to this many dofs and GMRES/CG + BoomerAMG above:
// where the two cost the same, measured per degree p (the highest of any patch) by
// benchmarks/auto_crossover.py (docs/performance.md, "auto by degree"). A linear problem (small
// strain, no contact) is one CG solve to the fixed tolerance, and there the factorisation stays
// ahead far longer, the more so at high degree (on the Lame cylinder MUMPS was ahead or even
// up to 6e4-2.4e5 dofs at p = 2, 1.2e5-2.4e5 at p = 3, 4, and past 2.4e5 at p = 5; a plate
// at p = 1: 6e4). A nonlinear one (contact, finite strain) is solved by GMRES with inexact
// Newton, which won on two blocks in contact from 1e4 dofs at p <= 3 and from 1.5e4-3e4 at
// p = 4, 5. With friction the Krylov solves keep the fixed tolerance and MUMPS was 2x faster
// at 55,272 dofs: kAutoDirectMaxDofsFriction.
long long Problem::contact_side_dofs() const {
  // each patch side once (a master shared by two pairs too)
  std::vector<std::array<int, 3>> seen;
  long long n = 0;
  for (const ContactPair& c : contact)
    for (const ContactSurface* s : {&c.master, &c.slave})
      for (const PatchSide& ps : s->sides) {
        const std::array<int, 3> key{s->body, ps.patch, static_cast<int>(ps.side)};
        if (std::find(seen.begin(), seen.end(), key) != seen.end()) continue;
        seen.push_back(key);
        const Patch& pt = bodies[s->body].patches[ps.patch];
        long long cps = 1;
        for (int d = 0; d < pt.dim(); ++d)
          if (d != side_direction(static_cast<int>(ps.side))) cps *= pt.ncp(d);
        n += cps * pt.dim();
      }
  return n;
}

std::string Problem::not_condensed_reason() const {
  if (contact.empty() || kinematics != Kinematics::Small) return "not small strain with contact";
  if (linear.condense == 0) return "solver.linear.condense: false";
  long long dofs = 0;
  for (const Body& b : bodies) dofs += static_cast<long long>(dim()) * b.num_cps;
  const long long m = contact_side_dofs();
  if (m > LinearOptions::kCondenseMaxDofs)
    return "the contact sides hold " + std::to_string(m) + " dofs, more than " +
           std::to_string(LinearOptions::kCondenseMaxDofs);
  if (linear.condense == 1 && m * LinearOptions::kCondenseDofsPerSideDof > dofs)
    return "the contact sides hold " + std::to_string(m) + " of the " + std::to_string(dofs) + " dofs, more than 1/" +
           std::to_string(LinearOptions::kCondenseDofsPerSideDof);
  return "";
}

bool Problem::condensed_contact() const { return not_condensed_reason().empty(); }

long long Problem::auto_direct_max_dofs() const {
  int p = 1;
  for (const Body& b : bodies)
    for (const Patch& pt : b.patches)
      for (int d = 0; d < pt.dim(); ++d) p = std::max(p, pt.degree[d]);
  // condensed onto the contact sides (small strain): measured in 2-D up to 1.7e5 dofs (1.9x
  // faster than GMRES + BoomerAMG there), in 3-D at p = 2 (the Hertz ball, 3.5e4 dofs: 1.3x
  // faster than GMRES + control_net in 1.7x the memory); 3-D factors at p >= 3 fill more
  if (condensed_contact() && (dim() == 2 || p <= 2))
    return std::max(kAutoDirectMaxDofsCondensed[dim() == 3 ? 1 : 0], has_friction() ? kAutoDirectMaxDofsFriction : 0);
  if (has_friction()) return kAutoDirectMaxDofsFriction;
  const bool linear = contact.empty() && kinematics == Kinematics::Small;
  // 3-D: a sparse factorisation fills far more (separators of n^(2/3) against n^(1/2)
  // unknowns), but BoomerAMG needs more CG iterations as the degree rises (22-26 at p = 1, 2;
  // 53 at p = 3; ~150 at p = 4 on the unit cube): measured on one linear solve of the cube
  // (docs/performance.md, "3-D: auto by degree"), the bound per degree
  if (dim() == 3) {
    //                                         p = 1     2      3      4      5
    static constexpr long long kMaxDofs3D[5] = {5000, 5000, 10000, 30000, 30000};
    return kMaxDofs3D[std::min(p, 5) - 1];
  }
  //                                                 p = 1      2       3       4       5
  static constexpr long long kMaxDofs[2][5] = {/* nonlinear */ {10000, 10000, 20000, 20000, 30000},
                                               /* linear */ {60000, 60000, 150000, 150000, 240000}};
  return kMaxDofs[linear ? 1 : 0][std::min(p, 5) - 1];
}


namespace detail {

// solver.linear.muelu_xml: a MueLu XML parameter list (MueLu's own format), relative to the
// problem file's folder. Read and checked here, once, so that a bad file stops the run before
// anything is solved or written: it must parse, and every top-level name must be a MueLu
// parameter (MueLu's master list) or a "level N" sublist.
Teuchos::RCP<const Teuchos::ParameterList> muelu_xml(const Reader& R, const YAML::Node& n) {
  const std::string key = "solver.linear.muelu_xml";
  const std::string given = R.string(n, key);
  if (given.empty()) R.fail(key, n, "must not be empty");
  const std::string path = (std::filesystem::path(R.file).parent_path() / given).string();
  std::error_code ec;   // a regular file only: Teuchos' XML reader loops on a folder or a device
  if (!std::filesystem::is_regular_file(path, ec) || !std::ifstream(path)) R.fail(key, n, "cannot read " + path);
  Teuchos::RCP<Teuchos::ParameterList> list;
  try {
    list = Teuchos::getParametersFromXmlFile(path);
  } catch (const std::exception& e) {
    // Teuchos' message ends with the reason, after the throwing source line and test
    std::string why = e.what();
    while (!why.empty() && std::isspace(static_cast<unsigned char>(why.back()))) why.pop_back();
    why = why.substr(why.find_last_of('\n') + 1);
    R.fail(key, n, "not a Teuchos XML parameter list: " + why);
  }
  Teuchos::RCP<const Teuchos::ParameterList> master;
  try {
    master = muelu_master_list();
  } catch (const std::runtime_error& e) {
    R.fail(key, n, e.what());
  }
  for (auto it = list->begin(); it != list->end(); ++it) {
    const std::string& name = list->name(it);
    if (master->isParameter(name) || name.rfind("level ", 0) == 0) continue;
    R.fail(key, n, "'" + name + "' is not a MueLu parameter");
  }
  return list;
}

void read_solver(const Reader& R, const YAML::Node& root, Problem& P) {
  if (root["solver"]) {
    const YAML::Node s = root["solver"];
    R.keys(s, "solver", {"newton", "linear", "quadrature", "formation"});
    if (s["formation"]) {
      const std::string f = R.string(s["formation"], "solver.formation");
      if (f == "sum_factorized") P.formation = Formation::SumFactorized;
      else if (f == "elements") P.formation = Formation::Elements;
      else R.fail("solver.formation", s["formation"], "expected sum_factorized or elements");
    }
    if (s["quadrature"]) {
      const std::string q = R.string(s["quadrature"], "solver.quadrature");
      if (q == "gauss") P.quadrature = Quadrature::Gauss;
      else if (q == "spline") P.quadrature = Quadrature::Spline;
      else R.fail("solver.quadrature", s["quadrature"], "expected gauss or spline");
    }
    if (s["newton"]) {
      const YAML::Node n = s["newton"];
      R.keys(n, "solver.newton", {"max_iterations", "tolerance", "line_search", "max_cuts", "extrapolate"});
      if (n["line_search"]) P.newton.line_search = R.boolean(n["line_search"], "solver.newton.line_search");
      if (n["extrapolate"]) {
        const std::string e = R.string(n["extrapolate"], "solver.newton.extrapolate");
        if (e == "auto") P.newton.extrapolate = NewtonOptions::Extrapolate::Auto;
        else if (e == "true") P.newton.extrapolate = NewtonOptions::Extrapolate::On;
        else if (e == "false") P.newton.extrapolate = NewtonOptions::Extrapolate::Off;
        else R.fail("solver.newton.extrapolate", n["extrapolate"], "expected auto, true or false");
      }
      if (n["max_cuts"]) {
        P.newton.max_cuts = R.integer(n["max_cuts"], "solver.newton.max_cuts");
        if (P.newton.max_cuts < 0 || P.newton.max_cuts > 30) R.fail("solver.newton.max_cuts", n["max_cuts"], "must be 0..30");
      }
      if (n["max_iterations"]) {
        P.newton.max_iterations = R.integer(n["max_iterations"], "solver.newton.max_iterations");
        if (P.newton.max_iterations < 1) R.fail("solver.newton.max_iterations", n["max_iterations"], "must be >= 1");
      }
      if (n["tolerance"]) P.newton.tolerance = R.positive(n["tolerance"], "solver.newton.tolerance");
    }
    if (s["linear"]) {
      const YAML::Node l = s["linear"];
      R.keys(l, "solver.linear", {"method", "preconditioner", "tolerance", "max_iterations", "muelu_xml",
                                   "reuse_preconditioner", "forcing", "condense"});
      if (l["method"]) {
        const std::string m = R.string(l["method"], "solver.linear.method");
        if (m == "cg") P.linear.method = LinearMethod::CG;
        else if (m == "gmres") P.linear.method = LinearMethod::GMRES;
        else if (m == "direct") P.linear.method = LinearMethod::Direct;
        else if (m != "auto") R.fail("solver.linear.method", l["method"], "expected auto, direct, gmres or cg");
        P.linear.method_given = m != "auto";
      }
      if (l["preconditioner"]) {
        const std::string m = R.string(l["preconditioner"], "solver.linear.preconditioner");
        if (m == "muelu") P.linear.preconditioner = Preconditioner::MueLu;
        else if (m == "boomeramg") P.linear.preconditioner = Preconditioner::BoomerAMG;
        else if (m == "ilut") P.linear.preconditioner = Preconditioner::ILUT;
        else if (m == "relaxation") P.linear.preconditioner = Preconditioner::Relaxation;
        else if (m == "none") P.linear.preconditioner = Preconditioner::None;
        else if (m == "control_net") P.linear.preconditioner = Preconditioner::ControlNet;
        else R.fail("solver.linear.preconditioner", l["preconditioner"], "expected boomeramg, muelu, ilut, relaxation, control_net or none");
      }
      if (l["tolerance"]) P.linear.tolerance = R.positive(l["tolerance"], "solver.linear.tolerance");
      if (l["max_iterations"]) {
        P.linear.max_iterations = R.integer(l["max_iterations"], "solver.linear.max_iterations");
        if (P.linear.max_iterations < 1) R.fail("solver.linear.max_iterations", l["max_iterations"], "must be >= 1");
      }
      if (l["muelu_xml"]) {
        // MueLu's parameters choose MueLu where no preconditioner is named (the default is
        // BoomerAMG); beside another named one they would be ignored: bad input
        if (!l["preconditioner"]) P.linear.preconditioner = Preconditioner::MueLu;
        else if (P.linear.preconditioner != Preconditioner::MueLu)
          R.fail("solver.linear.muelu_xml", l["muelu_xml"],
                 std::string("MueLu parameters, but solver.linear.preconditioner is ") +
                     preconditioner_name(P.linear.preconditioner) + " (name muelu, or drop muelu_xml)");
        P.linear.muelu_parameters = muelu_xml(R, l["muelu_xml"]);
      }
      if (l["reuse_preconditioner"])
        P.linear.reuse_preconditioner = R.boolean(l["reuse_preconditioner"], "solver.linear.reuse_preconditioner");
      if (l["condense"]) {
        const std::string m = R.string(l["condense"], "solver.linear.condense");
        if (m == "false") P.linear.condense = 0;
        else if (m == "true") P.linear.condense = 2;
        else if (m != "auto") R.fail("solver.linear.condense", l["condense"], "expected auto, true or false");
      }
      if (l["forcing"]) {
        const std::string m = R.string(l["forcing"], "solver.linear.forcing");
        if (m == "eisenstat_walker") P.linear.forcing = Forcing::EisenstatWalker;
        else if (m == "fixed") P.linear.forcing = Forcing::Fixed;
        else if (m != "auto") R.fail("solver.linear.forcing", l["forcing"], "expected auto, eisenstat_walker or fixed");
      }
    }
  }
}

void choose_linear_method(const Reader& R, const YAML::Node& root, Problem& P) {
  // Default linear method (auto): the direct solver up to auto_direct_max_dofs() dofs; above, CG for
  // elasticity (SPD), GMRES with contact, whose consistent tangent (the -p G term of the
  // moving projection) is not positive definite far from the solution.
  if (!P.linear.method_given) {
    long long dofs = 0;
    for (const Body& b : P.bodies) dofs += static_cast<long long>(P.dim()) * b.num_cps;
    P.linear.automatic = true;
    // finite strain: the tangent may be indefinite (buckling) and, with follower pressure,
    // non-symmetric: GMRES
    P.linear.method = dofs <= P.auto_direct_max_dofs()                         ? LinearMethod::Direct
                      : P.contact.empty() && P.kinematics == Kinematics::Small ? LinearMethod::CG
                                                                               : LinearMethod::GMRES;
  }
  // solids: BoomerAMG of the control nets' degree-1 stiffness (with contact pairs + K_c, the
  // bodies' coupling) unless a preconditioner is named (2.1x faster than BoomerAMG of the
  // tangent at p = 2 on the cube, 1.2-1.4x at p = 3, 4; the Hertz ball's linear solve 2.2x:
  // docs/performance.md, "3-D: the control-net preconditioner", "... with contact")
  const bool named = root["solver"] && root["solver"]["linear"] &&
                     (root["solver"]["linear"]["preconditioner"] || root["solver"]["linear"]["muelu_xml"]);
  if (!named && P.dim() == 3) P.linear.preconditioner = Preconditioner::ControlNet;
  // a multigrid preconditioner comes from the module beside the program (solver/amg.hpp):
  // one that cannot be loaded stops the run here, before anything is solved or written
  const bool multigrid = P.linear.preconditioner == Preconditioner::BoomerAMG ||
                         P.linear.preconditioner == Preconditioner::MueLu ||
                         P.linear.preconditioner == Preconditioner::ControlNet;
  if (P.linear.method != LinearMethod::Direct && multigrid) {
    try {
      amg_module_symbol("igacontact_amg_module_v1");
    } catch (const std::runtime_error& e) {
      const YAML::Node l = root["solver"] && root["solver"]["linear"] ? root["solver"]["linear"] : YAML::Node();
      if (l && l["preconditioner"]) R.fail("solver.linear.preconditioner", l["preconditioner"], e.what());
      if (l && l["method"]) R.fail("solver.linear.method", l["method"], e.what());
      R.fail("solver.linear.method", YAML::Node(std::string("auto")),
             std::string(e.what()) + " (auto chose an iterative method above " +
                 std::to_string(P.auto_direct_max_dofs()) + " dofs)");
    }
  }
  // 3-D mortar: where the master face ends inside a slave element, the covered part's motion
  // gives the tangent non-symmetric terms (kernels/contact_mortar3.hpp)
  for (const ContactPair& c : P.contact)
    if (c.friction > 0 ||
        (P.dim() == 3 && (c.method == ContactMethod::MortarPenalty || c.method == ContactMethod::MortarAlm)))
      P.linear.symmetric = false;
  // a pressure following the deformed surface has a non-symmetric tangent
  bool follower = false;
  if (P.kinematics == Kinematics::Finite)
    for (const Body& b : P.bodies)
      for (const auto& sides : b.sides)
        for (const SideCondition& sc : sides)
        if (sc.load == LoadKind::Pressure || sc.load == LoadKind::LinearPressure) follower = true;
  if (follower) {
    P.linear.symmetric = false;
    if (P.linear.method == LinearMethod::CG)
      R.fail("solver.linear.method", root["solver"]["linear"]["method"],
             "cg needs a symmetric tangent, and a pressure with analysis.kinematics: finite follows the deformed "
             "surface, whose tangent is non-symmetric; use gmres or direct");
  }
  // friction in slip makes the tangent non-symmetric: CG does not apply
  for (size_t k = 0; k < P.contact.size(); ++k)
    if (P.contact[k].friction > 0 && P.linear.method == LinearMethod::CG)
      R.fail("solver.linear.method", root["solver"]["linear"]["method"],
             "cg needs a symmetric tangent, and friction (contact[" + std::to_string(k) +
                 "].friction > 0) makes it non-symmetric in slip; use gmres or direct");
}

}  // namespace detail

}  // namespace iga
