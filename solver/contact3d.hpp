#pragma once
// 3-D contact pairs (issue 36): surfaces made of patch faces of solids, knot-to-surface
// penalty and augmented Lagrangian (kernels/contact_kts3.hpp). ContactPairData holds one of
// these for a solid's pair and forwards to it; the Newton core, the assembly and the outputs
// see the same pair interface in 2-D and 3-D.
#include <vector>

#include "kernels/contact_mortar_friction3.hpp"
#include "solver/system.hpp"

namespace iga {

/// A rule of the reference triangle exact for polynomials of total degree `degree`: Intrepid2's
/// default (symmetric) rule of the lowest degree >= `degree` whose weights are positive and
/// whose points lie strictly inside (degree 4: 6 points, 8: 16; its degrees 3, 7, 10, 12, 15
/// and 16 fail that and are passed over), or the collapsed Gauss rule where Intrepid2 has none.
TriangleRule triangle_rule(int degree);

struct ContactPointState;

class ContactSurfaces3 {
 public:
  ContactSurfaces3(const System& sys, const ContactPair& pair);
  /// Current displacements of both surfaces from the owned solution, then search + projection.
  void update(const Vector& u);
  void refresh();
  int num_points() const { return static_cast<int>(sp.weight.extent(0)); }
  int points_per_element = 0;   // KTS and kts_alm: the largest nq0 x nq1 of the slave faces (0: mortar)
  /// The groups of coupled control points (global ids) of this rank's points with a
  /// projection, the master element widened by one control point each way; active: the
  /// number of this rank's active points.
  void groups(std::vector<std::vector<GO>>& out, int& active) const;
  /// Overlap LIDs of the faces' control points in the contact matrix's numbering cps.
  void set_lids(const std::vector<GO>& cps);
  /// Every slave point's state on every rank (collective: each rank projects only its own
  /// points (KTS) or segments its own slave elements (mortar), and the states of the others
  /// come by a sum over the ranks).
  void state(ContactPointState& s, bool projected_only) const;
  double h_min() const { return h_min_; }
  /// Mortar: the slave elements with a slot under pressure, all ranks' (collective).
  int active_elements() const;
  /// The master elements a point (slot) under pressure projects onto, all ranks' (collective).
  int active_master_elements() const;
  /// Global control point ids of both surfaces (sorted, unique).
  std::vector<GO> surface_gids() const;

  ContactPair pair;
  ContactFaces slave, master;
  SlavePoints3 sp;
  int p_begin = 0, p_end = 0;   // this rank's slave points (mortar: quadrature slots)
  // mortar (contact_mortar3.hpp): slots per slave element, the rule on each segment, the
  // per-control-point state, this rank's slave control points and their scratch rows
  bool mortar = false;
  bool segmented = true;   // mortar: slots on the clipped segments; false for kts_alm (the KTS points)
  int slots = 0;
  GaussRule gauss;      // n points: the edge points' rule, and the degree 2 n - 2 of tri
  TriangleRule tri;     // the rule of each fan triangle of a segment (triangle_rule)
  MortarState ms;
  MortarScratch scratch;
  int a_begin = 0, a_end = 0;
  // the points where the master face ends inside slave elements (the tangent's boundary
  // terms), `edges.per` per slave element; this rank's [e_begin, e_end)
  MortarEdges3 edges;
  int e_begin = 0, e_end = 0;
  // the slave elements this rank segments and projects (segment_range): its slots' and edge
  // points' elements and the support of its control points
  int c_begin = 0, c_end = 0;
  int cells = 0;   // cells per direction of a master element in the segmentation (0: 2 if curved, else 1; at most kMaxCells)
  // mortar: skip the slave elements whose control points are all certainly out of contact
  // (MortarFar3, MortarOut3; tests compare against false; any number of ranks); out_of_contact():
  // per control point A, whether it was out at the last update
  bool skip_out = true;
  std::vector<int> out_of_contact() const;
  // with friction: the edge points as slave points (their feet, references and slip vectors)
  SlavePoints3 esp;
  Friction3 efr;
  void mortar_scratch(int cap);
  /// sum_A w_A lambda_A^2 / (2 eps) (mortar), the penalty potential of the slots (KTS)
  double potential() const;
  /// The largest |g_A / w_A| of the slave control points in contact and, with friction, the
  /// largest weighted stick slip along the contact plane (every rank holds every control
  /// point's; 0 for kts_penalty, which has no multipliers).
  double max_active_gap() const;

  // friction (KTS: kernels/contact_friction3.hpp, the law at this rank's points after each
  // projection; mortar: kernels/contact_mortar_friction3.hpp, the law per slave control point
  // after the weighted gaps): the history (committed foot or configuration, traction, slip)
  // moves on at commit() and comes back at restore(); augment(): lamTA <- tauA (ALM)
  Friction3 fr;
  MortarScratch fscratch;   // mortar friction: V_A and delta g_A per slave control point
  bool friction = false;
  int counts[3] = {0, 0, 0};        // stick, slip, state switches since the last update (all ranks)
  double assembled_t[3] = {0, 0, 0};   // [Tx, Ty, Tz] of the last assembly (all ranks)
  void commit();
  void restore();
  void augment();
  void reset_multipliers();
  /// the dofs of both surfaces' control points (replicated on every rank)
  const RCP<const Map>& surface_dofs() const { return replicated_; }

 private:
  void allocate_points(int n);
  void allocate_edges(int per);
  void segment_range();
  void balance_slots();
  void count_element_loads();
  RCP<const Comm> comm_;
  void update_friction();
  void update_mortar_friction();
  Kokkos::View<int*, MemSpace> state_prev_;
  struct Committed {
    Kokkos::View<double*, MemSpace> lambda;
    Kokkos::View<double* [2], MemSpace> lamT;
    Kokkos::View<double* [3], MemSpace> lamTA;
  } committed_;
  // mortar friction: the faces in the last converged configuration (the slots' reference feet
  // are projected onto it at every update) and the per-A states of the previous update
  ContactFaces slave_c_, master_c_;
  bool have_committed_ = false;
  Kokkos::View<int*, MemSpace> stateA_prev_;
  Kokkos::View<int*, MemSpace> seg_flags_;
  Kokkos::View<int**, Kokkos::LayoutRight, MemSpace> cand_;   // mortar: candidate master elements per slave element
  // mortar: per slave element, certainly out of contact (MortarFar3); per control point A, its
  // whole support out and no multiplier (MortarOut3): the segmentation skips elements of such A only
  Kokkos::View<int*, MemSpace> far_, out_;
  // mortar: the slave control points A (number_slave_control_points): how many, and A's
  // occurrences (face, face control point) in [a_ptr_h_[A], a_ptr_h_[A + 1]) of a_occ_h_ (pairs)
  void number_slave_control_points();
  int num_control_points_ = 0;
  std::vector<int> a_ptr_h_, a_occ_h_;
  std::vector<int> elem_load_;   // mortar on several ranks: active slots per slave element (last update, every rank's)
  int support_[2] = {0, 0};   // the slave elements in the support of this rank's control points
  int rank_ = 0, nranks_ = 1;
  struct HostFace {
    std::vector<GO> gid;        // per face control point
    int p[2], n[2], ne[2];
    std::vector<int> span[2];
  };
  std::vector<HostFace> hs_, hm_;
  /// The KTS rule's points along direction d of a slave face's elements: contact.quadrature_points,
  /// else 2 (p + 1) as in 2-D
  int kts_rule(const HostFace& h, int d) const {
    return pair.quadrature_points > 0 ? pair.quadrature_points : std::min(2 * (h.p[d] + 1), kMaxContactQuadrature);
  }
  RCP<const Map> replicated_;
  RCP<Import> importer_;
  std::vector<Kokkos::View<int* [3], MemSpace>> rep_s_, rep_m_;   // replicated dof LIDs per face cp
  double h_min_ = 1;
};

}  // namespace iga
