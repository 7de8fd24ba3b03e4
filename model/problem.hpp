#pragma once
// The problem: what a YAML problem file describes, validated. See docs/problem-file.md.
#include <array>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <Teuchos_RCP.hpp>

namespace Teuchos { class ParameterList; }

#include "model/input_error.hpp"
#include "model/multipatch.hpp"
#include "model/nurbs.hpp"

namespace iga {


/// analysis.type: plane_strain | plane_stress (2-D), solid (3-D)
enum class Analysis { PlaneStrain, PlaneStress, Solid };
/// analysis.kinematics: small strain (linear), or finite (total Lagrangian, plane strain)
enum class Kinematics { Small, Finite };
/// material.model; with finite kinematics `linear` means Saint Venant-Kirchhoff
enum class MaterialModel { Linear, SaintVenantKirchhoff, NeoHookean };
const char* material_model_name(MaterialModel m);   // linear, saint_venant_kirchhoff, neo_hookean
enum class LoadKind { None, Pressure, LinearPressure, Traction };
enum class ContactMethod { KtsPenalty, KtsAlm, MortarPenalty, MortarAlm };
enum class LinearMethod { CG, GMRES, Direct };
/// solver.linear.preconditioner; ControlNet: BoomerAMG of the stiffness of the degree-1 patches
/// on the same control nets (System::control_net_stiffness), without contact
enum class Preconditioner { MueLu, BoomerAMG, ILUT, Relaxation, None, ControlNet };
/// solver.quadrature: the element rule of the stiffness and internal force. Spline (the
/// default): per patch direction the generalised Gaussian rule of the spline space
/// (model/quadrature.hpp), about (p + 2) / 2 points per element; exact where Gauss is exact for
/// B-spline patches with an affine map, and falls back to Gauss (said in the run header) where
/// it cannot be built. Gauss: p + 1 Gauss-Legendre points per element and direction (the
/// reference).
enum class Quadrature { Gauss, Spline };
/// solver.formation: how the tangent is formed. SumFactorized (the default): row by row over
/// each patch, the quadrature sum factorised through the 1-D B-spline tables
/// (kernels/elasticity_sf.hpp). Elements: element by element (kernels/elasticity.hpp), the
/// reference; the same matrix to round-off.
enum class Formation { SumFactorized, Elements };

const char* contact_method_name(ContactMethod m);
const char* linear_method_name(LinearMethod m);       // cg, gmres, direct
const char* preconditioner_name(Preconditioner p);   // muelu, ilut, relaxation, none

/// What a side prescribes. Every value is given per stage (analysis.stages): entry k is the
/// value at the end of stage k + 1, reached linearly from the end of stage k (the first stage
/// starts from zero). Without stages there is one stage.
/// Components beyond the problem's dimension stay unset (2-D: z).
struct SideCondition {
  std::array<bool, kMaxDim> fixed{false, false, false};   // component prescribed?
  std::vector<std::array<double, kMaxDim>> value;  // prescribed displacement per stage end
  LoadKind load = LoadKind::None;
  std::vector<double> p0, p1;                // pressure (p0) or linear pressure p0 -> p1, per stage end
  std::vector<std::array<double, kMaxDim>> traction;   // per stage end
};

/// A body: one or several NURBS patches of one material. Patches meet along conforming
/// interfaces, where their control points are merged (one set of dofs), so the displacement
/// is continuous. Single-patch bodies are the case of one patch and no interfaces.

struct Body {
  std::string name;
  double E = 0, nu = 0;
  MaterialModel model = MaterialModel::Linear;
  std::vector<Patch> patches;                         // refined, in the file's order
  std::vector<std::array<SideCondition, 6>> sides;    // per patch, indexed by Side (2-D: the first 4)
  std::vector<std::array<SideCondition, 4>> corners;  // per patch, indexed by Corner (displacement only)
  std::vector<Interface> interfaces;                  // conforming (found or declared, checked)
  std::vector<std::pair<std::string, std::vector<PatchSide>>> named;   // named boundaries (geometry file)
  std::vector<std::vector<int>> cp_index;             // per patch: control point -> the body's merged one
  int num_cps = 0;                                    // merged control points
  double tolerance = 0;                               // coincidence of control points (relative to the body's size)
  bool multipatch() const { return patches.size() > 1; }
  /// "north" on a single-patch body, "patch1.north" on a multi-patch one.
  std::string side_label(int patch, Side s) const;
  /// The side is one side of an interface (inside the body).
  bool is_interface(const PatchSide& s) const;
  /// "south_west" on a single-patch body, "patch1.south_west" on a multi-patch one.
  std::string corner_label(int patch, Corner c) const;
  /// A patch's control point displacements (dim per control point) from the body's merged ones.
  std::vector<double> patch_values(int patch, const std::vector<double>& u) const;
  /// Space dimension of the body's patches (2 or 3).
  int dim() const { return patches.empty() ? 2 : patches[0].dim(); }
};

/// A contact surface: one side, or a chain of patch sides of a multi-patch body.
struct ContactSurface {
  int body = -1;
  std::vector<PatchSide> sides;
  std::string label;   // as written: "north", "patch0.south+patch1.south", a named boundary
};

struct ContactPair {
  ContactSurface master, slave;
  ContactMethod method = ContactMethod::KtsPenalty;
  double penalty = 0;
  int quadrature_points = 0;        // per slave knot span; 0 = degree + 2
  int segment_cells = 0;            // 3-D mortar: cells per direction of a master element (0: auto)
  int augmentations = 50;           // ALM: maximum multiplier updates
  double alm_tolerance = 1e-8;      // ALM: gap tolerance relative to slave element size
  double friction = 0;              // Coulomb coefficient mu (0: frictionless)
  double tangential_penalty = 0;    // eps_T (the loader sets it, default = penalty)
};

struct NewtonOptions {
  int max_iterations = 30;
  double tolerance = 1e-10;
  bool line_search = true;   // backtracking on the residual norm
  int max_cuts = 10;         // a failed load step is retried with half the increment, this many times
  /// solver.newton.extrapolate: the first iterate of an increment is the last converged
  /// increment of the same stage continued linearly (u_c + dt / dt_prev (u_c - u_prev));
  /// auto: off (extrapolated_start)
  enum class Extrapolate { Auto, On, Off } extrapolate = Extrapolate::Auto;
};

/// solver.linear.forcing: `tolerance` for every solve, or Eisenstat-Walker (the tolerance
/// follows Newton's progress; `tolerance` is its floor); auto: Eisenstat-Walker for gmres and
/// cg without friction on a nonlinear problem (contact or finite strain), else fixed
enum class Forcing { Auto, Fixed, EisenstatWalker };

struct LinearOptions {
  LinearMethod method = LinearMethod::CG;
  Preconditioner preconditioner = Preconditioner::BoomerAMG;
  double tolerance = 1e-12;
  int max_iterations = 1000;
  bool method_given = false;
  /// solver.linear.method: auto (the default): the loader chose `method` by the problem's size
  bool automatic = false;
  /// the tangent is symmetric (no friction): the direct solver factors L D L^T
  bool symmetric = true;
  bool reuse_preconditioner = true;   // keep the preconditioner over a load step's Newton iterations
  /// interleaved dofs per node for the AMG preconditioners: the problem's dimension (the loader sets it)
  int dofs_per_node = 2;
  /// solver.linear.forcing: the tolerance of each Newton step's Krylov solve
  Forcing forcing = Forcing::Auto;
  /// solver.linear.muelu_xml, read and checked with the problem: MueLu parameters set over
  /// the built-in ones (null: none)
  Teuchos::RCP<const Teuchos::ParameterList> muelu_parameters;
  /// control_net with contact pairs: the iterations a fresh preconditioner gets before the
  /// solve is taken up with BoomerAMG of the tangent (solver/linear_solver.cpp; API only)
  int control_net_contact_limit = 200;
  /// solver.linear.condense: direct at small strain with contact pairs: each solve condensed
  /// onto the contact sides' dofs (DirectSolver's "Condensed solves"; 0 false, 1 auto, 2 true:
  /// also where the sides hold more than 1 / kCondenseDofsPerSideDof of the dofs)
  int condense = 1;
  /// the most dofs a solve is condensed onto (the Schur complement is dense on rank 0: its LU
  /// and the columns of its inverse cost up to m^3), and the least share of all dofs for one
  /// contact-side dof: sides with a quarter of a problem's dofs (a long strip, thin plates)
  /// made it 3-21x slower than the ordinary factorisation (3,968 side dofs of 15,872: 29.7
  /// against 1.4 s), sides with 2-6 % of them (the wheel, the Hertz ball) faster
  static constexpr long long kCondenseMaxDofs = 2500;
  static constexpr long long kCondenseDofsPerSideDof = 12;
};

struct Probe {
  int body = -1;
  int patch = 0;
  std::array<double, kMaxDim> at{0, 0, 0};   // [xi, eta(, zeta)] in [0, 1]
};

struct OutputOptions {
  std::string directory;
  int samples_per_element = 0;   // 1..64; 0: auto (samples())
  bool all_steps = true;   // output.steps: all (a state per converged load step) | last
  /// output.cells (3-D only): faces (false, the default: the boundary faces of the patches as
  /// Bezier quadrilaterals) | volume (true: every element as a Bezier hexahedron) in result_<n>.vtu
  bool volume_cells = false;
  /// output.compression of result_<n>.vtu's binary arrays: auto (-1, the default: zlib where
  /// the uncompressed cells would take more than kCompressAboveBytesPerDof bytes per dof, as
  /// the exact cells of degree 4 and up do) | none (0) | zlib (1)
  int compression = -1;
  static constexpr double kCompressAboveBytesPerDof = 400;
  std::vector<Probe> probes;

  /// Samples per element and direction of the sampled grid (result_<n>.h5, result.xdmf) of a
  /// patch of ne0 x ne1 elements with ncp control points: samples_per_element where the file
  /// gives it; auto: the largest s <= 4 whose grid (s ne0 + 1)(s ne1 + 1) has at most
  /// max(ncp, 4096) points. A large patch gets about one sample per control point (its exact
  /// picture is the rational Bezier cells of result_<n>.vtu), a small one a smooth grid.
  int samples(int ne0, int ne1, long long ncp) const {
    if (samples_per_element > 0) return samples_per_element;
    const double cap = ncp > 4096 ? static_cast<double>(ncp) : 4096.0;
    for (int s = 4; s > 1; --s)
      if ((s * static_cast<double>(ne0) + 1) * (s * static_cast<double>(ne1) + 1) <= cap) return s;
    return 1;
  }
};

struct Problem {
  std::string file;
  Analysis analysis = Analysis::PlaneStrain;
  Kinematics kinematics = Kinematics::Small;
  double thickness = 1.0;
  int load_steps = 1;              // all stages together
  std::vector<int> stages{1};      // load steps per stage (analysis.stages; else {load_steps})
  int num_stages() const { return static_cast<int>(stages.size()); }
  /// Space dimension of the problem: 2 (plane strain or plane stress) or 3 (solid).
  int dim() const { return analysis == Analysis::Solid ? 3 : 2; }
  std::vector<Body> bodies;
  std::vector<ContactPair> contact;
  NewtonOptions newton;
  LinearOptions linear;
  Quadrature quadrature = Quadrature::Spline;
  Formation formation = Formation::SumFactorized;
  OutputOptions output;
  /// Lines the loader warns about (`check` and `run` print them; summary.json `warnings`):
  /// e.g. a contact penalty far above E / h.
  std::vector<std::string> warnings;

  int find_body(const std::string& name) const;
  /// some contact pair has Coulomb friction (mu > 0)
  bool has_friction() const;
  /// the size up to which solver.linear.method: auto takes the direct solver
  long long auto_direct_max_dofs() const;
  /// dofs of the contact pairs' sides' control points (an upper bound: shared points counted
  /// per side): the set a direct solve at small strain condenses onto
  long long contact_side_dofs() const;
  /// a direct solve condenses onto the contact sides (small strain, contact pairs, the set
  /// within LinearOptions::kCondenseMaxDofs and at most 1 / kCondenseDofsPerSideDof of the
  /// dofs, solver.linear.condense not false)
  bool condensed_contact() const;
  /// why a direct solve at small strain with contact pairs is not condensed ("" where it is)
  std::string not_condensed_reason() const;
};

/// Limits on what a problem file may ask for (docs/problem-file.md).
constexpr size_t kMaxProblemFileBytes = 64u << 20;   // a patch of 10^6 control points listed inline fits
constexpr double kMaxDofs = 1e9;                      // besides the machine's memory (checked too)
/// solver.linear.method: with friction auto takes the direct solver up to this many dofs (the
/// Krylov solves keep the fixed tolerance there, no inexact Newton, and MUMPS was still 2x
/// faster at 55,272 dofs); without, Problem::auto_direct_max_dofs' table per degree.
constexpr long long kAutoDirectMaxDofsFriction = 200000;
/// solver.linear.method: auto takes the direct solver up to this many dofs (2-D, 3-D at p <= 2)
/// where its solves are condensed onto the contact sides (Problem::condensed_contact): the
/// 77,380-dof wheel 1.5x and a 171,356-dof one 1.9x faster than GMRES + BoomerAMG, the
/// 34,992-dof Hertz ball 1.3x faster than GMRES + control_net (docs/performance.md, "Solves
/// condensed onto the contact sides")
constexpr long long kAutoDirectMaxDofsCondensed[2] = {200000, 40000};
constexpr size_t kMaxInsertedKnots = 1000;            // per direction; subdivide refines uniformly
constexpr int kMaxLoadSteps = 10000;
constexpr int kMaxContactQuadrature = 12;             // contact quadrature points per slave span
constexpr int kMaxSegmentCells = 8;                   // 3-D mortar: cells per direction of a master element
constexpr int kMaxContactFaces = 6;                    // 3-D: patch faces of one contact surface

/// A body's geometry with its topology (interfaces, the outer sides, named boundaries), as a
/// geometry file holds it; with u (2 per merged control point): the deformed control nets.
MultiPatch body_geometry(const Body& b, const std::vector<double>* u = nullptr);

/// The curve of a contact surface (a side, or a chain of patch sides joined end to end).
SurfaceChain surface_chain(const Problem& P, const ContactSurface& s);

/// Whether Newton's Krylov solves take the Eisenstat-Walker forcing (solver.linear.forcing,
/// `auto` resolved: the iterative methods without friction).
bool eisenstat_walker_forcing(const Problem& P);
/// solver.newton.extrapolate resolved: whether an increment starts from the last one continued
bool extrapolated_start(const Problem& P);

/// Reads, overrides (`key.path=value`, as `--set`) and validates a problem file.
/// Throws InputError with a one-line message on any bad input.
Problem load_problem(const std::string& file, const std::vector<std::string>& overrides = {});
/// The same from YAML text (tests, fuzzing); `file` is only used in messages.
Problem parse_problem(const std::string& text, const std::string& file,
                      const std::vector<std::string>& overrides = {});

}  // namespace iga
