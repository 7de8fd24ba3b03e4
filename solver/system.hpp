#pragma once
#include <memory>
// The discretised problem on this rank: dof numbering, the Tpetra maps, the element
// partition, assembly of the elastic stiffness and loads, Dirichlet conditions.
//
// Numbering: control points of all bodies are numbered body after body, within a body in its
// merged numbering (Body::cp_index: patch after patch, xi fastest, a control point shared by
// patches at an interface once); global cp g has dofs 2 g (x) and 2 g + 1 (y). Control points are split into contiguous blocks
// over the ranks (the owned map); elements likewise, so that a rank's elements mostly touch
// its own control points. A rank assembles its elements into an overlapping matrix whose
// rows are the dofs its elements touch, and Tpetra exports (sums) that into the owned one.
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "model/problem.hpp"
#include "solver/types.hpp"

namespace iga {

/// One patch of one body: the unit of the element loops. A single-patch body is one block;
/// a multi-patch body has one per patch, whose control points on interfaces share global ids.
struct PatchBlock {
  PatchData pd;           // device data of a 2-D patch; pd.lid is the elasticity overlap numbering
  PatchData3 pd3;         // the same of a 3-D patch (the other one stays empty)
  int body = 0, patch = 0;
  std::vector<GO> gid;    // global control point id of each patch control point
  int e_begin = 0, e_end = 0;  // this rank's elements, in the patch's numbering
  int orientation = 1;
  Material mat;
  std::vector<int> lid;   // host copy of pd.lid
  int quadrature_points = 0;   // of the whole patch (both directions' nodes multiplied)
  std::string quadrature;      // "gauss", "spline", or "gauss (spline rule failed: ...)" per direction
};

/// A patch's data as the kernels see it, viewing the patch's host arrays (host evaluation:
/// output fields, host-integrated loads, references in tests). No lid.
HostPatchData host_patch_data(const Patch& P);
HostPatchData3 host_patch_data3(const Patch& P);

/// Slots of DirichletDof::side: 0 .. kCornerSlot - 1 a Side (4 in 2-D, 6 in 3-D), then a 2-D
/// Corner + kCornerSlot.
constexpr int kCornerSlot = 6;
/// A constrained dof, the patch block and place it is reported under (a Side, or a Corner +
/// kCornerSlot), and its prescribed value at the end of each stage.
struct DirichletDof {
  GO dof;
  int block, side;
  std::vector<double> values;
};

/// A point of the load path: pseudo-time t in [0, K] over the K stages; stage k (0-based)
/// covers (k, k + 1], and a prescribed value there is (1 - s) v_{k-1} + s v_k with s = t - k
/// and v_{-1} = 0 (v_k: its value at the end of stage k + 1).
struct LoadPoint {
  int stage = 0;
  double s = 1.0;
  static LoadPoint at(double t, int num_stages);
  double time() const { return stage + s; }
};

class System {
 public:
  System(const Problem& problem, RCP<const Comm> comm);

  const Problem& problem() const { return P_; }
  /// Space dimension: dofs per control point (kernels/numbering.hpp: dof = dim g + c).
  int dim() const { return P_.dim(); }
  RCP<const Comm> comm() const { return comm_; }
  RCP<const Map> owned_map() const { return owned_; }
  /// The patch blocks, body after body, patch after patch.
  const std::vector<PatchBlock>& blocks() const { return blocks_; }
  GO num_dofs() const { return static_cast<GO>(dim()) * num_cps_; }
  /// Global id of control point a of a body's patch.
  GO cp_gid(int body, int patch, int a) const { return body_offset_[body] + P_.bodies[body].cp_index[patch][a]; }
  /// Global id of a body's first control point; its control points are the next num_cps.
  GO body_offset(int body) const { return body_offset_[body]; }

  /// Internal force f_int(u) and tangent K_T(u) = d f_int / du of every body's material
  /// (owned rows, no boundary conditions), in one element loop: f_int into *f_int when given,
  /// K_T into *K when given (created with the stiffness graph when null, refilled in place
  /// after, so that holders of the RCP see the new values). u == nullptr: u = 0.
  /// Finite kinematics with a load point lp: pressures follow the deformed sides and enter
  /// here, as -f_ext(u, lp) and its (non-symmetric) tangent; assemble_loads leaves them out.
  void assemble_internal(const Vector* u, Vector* f_int, RCP<Matrix>* K, const LoadPoint* lp = nullptr) const;
  /// The tangent at u = 0, fill complete: the small-strain stiffness for every material.
  RCP<Matrix> assemble_stiffness() const;
  /// Every body's tangent is independent of u (small strain, linear): assembled once.
  bool constant_tangent() const;
  /// External load vector (Neumann conditions): lambda times the loads at the end of stage
  /// `stage` (0-based; -1: the last). Finite kinematics: tractions only (dead loads);
  /// pressures follow the surface (assemble_internal).
  RCP<Vector> assemble_loads(double lambda, int stage = -1) const;

  /// C++ API: a traction t(x, y) on a side, in addition to the problem file's loads
  /// (verification against analytic solutions; integrated on the host).
  using TractionFunction = std::function<std::array<double, 2>(double x, double y)>;
  void add_traction(int body, Side side, TractionFunction t, int patch = 0) {
    user_tractions_.push_back({body, patch, side, std::move(t)});
  }
  /// C++ API: a dead body force b(X, Y) per unit reference area (times the thickness) on a
  /// body, scaled by the load factor like the file's loads (manufactured solutions; host).
  using BodyForceFunction = std::function<std::array<double, 2>(double X, double Y)>;
  void add_body_force(int body, BodyForceFunction b) { user_body_forces_.push_back({body, std::move(b)}); }
  /// The same for a solid (3-D): b(X, Y, Z) per unit reference volume.
  using BodyForceFunction3 = std::function<std::array<double, 3>(double X, double Y, double Z)>;
  void add_body_force(int body, BodyForceFunction3 b) { user_body_forces3_.push_back({body, std::move(b)}); }

  /// The locally owned constrained dofs.
  const std::vector<DirichletDof>& dirichlet() const { return dirichlet_; }
  /// Sets u on constrained dofs to their prescribed values at a point of the load path.
  void set_dirichlet(Vector& u, const LoadPoint& lp) const;
  /// Zeroes constrained dofs of v.
  void zero_dirichlet(Vector& v) const;
  /// The entries of v on the constrained dofs (dirichlet() order), and writing them back:
  /// the reactions of a residual whose constrained rows were zeroed for the solve.
  std::vector<double> constrained_entries(const Vector& v) const;
  void set_constrained_entries(Vector& v, const std::vector<double>& entries) const;
  /// Symmetric elimination: rows and columns of constrained dofs become zero with the
  /// original diagonal kept, so CG still applies.
  void apply_dirichlet(Matrix& A) const;

  /// The small-strain stiffness of the degree-1 patches on the same control nets (the same
  /// dofs; 3^dim control points couple instead of (2p + 1)^dim), Dirichlet rows and columns
  /// eliminated: the matrix of solver.linear.preconditioner: control_net.
  RCP<Matrix> control_net_stiffness() const;

  /// Rigid-body modes (x, y translation, rotation) on the owned dofs: MueLu's nullspace.
  RCP<MultiVector> rigid_body_modes() const;
  /// MueLu's "Coordinates" for distance-Laplacian dropping, one row per owned control point:
  /// the control points, each body moved far from the others (so that aggregates never
  /// straddle a contact interface), nudged apart where they coincide (collapsed edges).
  RCP<MultiVector> aggregation_coordinates() const;

  /// The body that global control point g belongs to.
  size_t body_of(GO g) const;
  /// The block of a body's patch.
  size_t block_of(int body, int patch) const;
  /// Reference position of global control point g.
  const ControlPoint& control_point(GO g) const;

  /// Builds an overlapping map from global control point ids (sorted, unique): dofs 2g, 2g+1.
  RCP<const Map> cp_dof_map(const std::vector<GO>& cps, bool replicated_ok = true) const;
  /// Sums an overlapping matrix/vector into owned ones (identity on one rank).
  RCP<Matrix> export_matrix(const RCP<Matrix>& overlap) const;
  RCP<Vector> export_vector(const Vector& overlap) const;

  /// Material D of body b (thickness included).
  const Material& material(int b) const { return materials_[b]; }

 private:
  Problem P_;
  RCP<const Comm> comm_;
  RCP<const Map> owned_;
  RCP<const Map> overlap_;   // elasticity overlap
  std::vector<PatchBlock> blocks_;
  std::vector<GO> body_offset_;
  std::vector<ControlPoint> cp_pos_;
  std::vector<Material> materials_;   // reference position of every global control point
  GO num_cps_ = 0;
  bool merged_ = false;   // some control points are shared by patches (interfaces)
  std::vector<DirichletDof> dirichlet_;
  std::vector<int> dirichlet_lids_;
  struct UserTraction { int body, patch; Side side; TractionFunction t; };
  std::vector<UserTraction> user_tractions_;
  struct UserBodyForce { int body; BodyForceFunction b; };
  std::vector<UserBodyForce> user_body_forces_;
  struct UserBodyForce3 { int body; BodyForceFunction3 b; };
  std::vector<UserBodyForce3> user_body_forces3_;
  // Several ranks: element rows of owned control points go straight into the owned rows'
  // global pattern, the few others into a "ghost" matrix whose rows are exported (built once).
  struct OwnedGhost {
    RCP<const Graph> owned, ghost;
    RCP<const Map> ghost_map;
    RCP<const Export> exporter;   // ghost rows -> owned rows
    std::vector<Kokkos::View<const int*, MemSpace>> orow, ocol, grow;   // per block, per cp
  };
  mutable std::unique_ptr<OwnedGhost> split_;
  mutable RCP<const Graph> graph_;          // the stiffness graph (owned rows), built once
  mutable int graph_sorted_ = -1, ghost_sorted_ = -1;   // their rows' column indices ascend (1), or not (0)
  mutable RCP<const Import> ov_import_;     // owned -> overlap (displacements)
  mutable RCP<const Export> ov_export_;     // overlap -> owned (forces, ADD)
  mutable RCP<Vector> u_ov_, f_ov_;         // several ranks: overlap displacements and forces
  // solver.formation: sum_factorized: per block, the 1-D tables and work arrays (built once)
  struct SumFactorCache;
  mutable std::vector<std::shared_ptr<SumFactorCache>> sum_factor_;
  // 3-D: the element loop's batched element-matrix work view, kept from one assembly to the
  // next (64 MB: allocating and zeroing its pages per Newton iteration costs)
  mutable Kokkos::View<double**, Kokkos::LayoutRight, MemSpace> element_work_;
  RCP<const Graph> stiffness_graph() const;

  struct CouplingRange { std::vector<int> lo, hi; };
  static CouplingRange coupling_range(const Patch& pt, int d);
  template <class RowOf, class F>
  void for_each_coupling(RowOf row_of, F f) const;
  template <class RowOf, class ColOf>
  void coupling_csr(LO nrows, RowOf row_of, ColOf col_of, Teuchos::ArrayRCP<size_t>& rowptr,
                    Teuchos::ArrayRCP<LO>& cols) const;
  std::unique_ptr<OwnedGhost> owned_ghost() const;
};

/// The kernels' material of body b: small-strain linear (plane strain or stress), or the body's
/// finite-strain model (analysis.kinematics: finite; `linear` is Saint Venant-Kirchhoff there).
Material body_material(const Problem& P, int b, double thickness);

/// Owned-range split of n items over `size` ranks: [begin, end) of `rank`.
inline std::pair<long long, long long> block_range(long long n, int rank, int size) {
  return {n * rank / size, n * (rank + 1) / size};
}

}  // namespace iga
