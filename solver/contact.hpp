#pragma once
// Contact pairs on the Tpetra system: replicated boundary displacements, the search and
// projection kernels, and assembly of the contact residual and tangent into owned objects.
#include <stdexcept>
#include <vector>

#include <memory>

#include "kernels/contact_friction.hpp"
#include "solver/contact3d.hpp"
#include "solver/system.hpp"

namespace iga {

/// A contact state the discretisation cannot represent (thrown by update / assembly); the
/// Newton loop reports it as non-convergence of the load step.
struct ContactError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Host copy of one pair's slave point state, for output and convergence checks.
/// tangential: traction on the slave along the unit master tangent (tx, ty) (increasing
/// master parameter); slip: accumulated, same sign; state: 0 open, 1 stick, 2 slip.
/// 3-D (solids): z, eta (the second slave face parameter), nz, face (the slave face's index in
/// the pair's list) and X (the reference point, x y z per point) as well; with friction,
/// (tx, ty, tz) is the tangential traction vector on the slave, tangential its length, slip
/// the accumulated slip path and slip_increment the length of this step's slip |g_T|.
struct ContactPointState {
  std::vector<double> x, y, xi, gap, pressure, weight, nx, ny, tangential, slip, tx, ty;
  std::vector<double> z, eta, nz, X, tz, slip_increment;
  std::vector<int> active, state, face;
};

/// A pair's summary at its last update and assembly. fx, fy: the force on the slave body, the
/// sum over the slave dofs of the pair's assembled contact residual (-f_c), so it equals the
/// reactions; normal_force / tangential_force: the sums of each point's share of it along the
/// master's outward normal / unit tangent there (increasing master parameter): the integral
/// of the pressure, and of the tangential traction as the weak form applies it (tau d(ds)/dx_s
/// along the tangent: tau (|t| + (eta - eta_n) e.rho'') |t| / H, H = |t|^2 - g n.rho'').
/// 3-D: fz as well, and contact_length is the contact area (the measure of the active slave
/// points).
/// 3-D with friction: tangential (Tx, Ty, Tz), the slave rows' sum of the friction part of -f_c
/// (the integral of the tangential traction as the weak form applies it); stick_length and
/// slip_length are areas.
struct ContactSummary {
  double normal_force = 0, fx = 0, fy = 0, fz = 0, max_pressure = 0, contact_length = 0, max_penetration = 0;
  double tangential[3] = {0, 0, 0};
  double tangential_force = 0, stick_length = 0, slip_length = 0;
  int active_points = 0;
};

/// Friction state counts of a pair (all points, every rank holds them): stick, slip, and the
/// points whose state changed since the previous update.
struct FrictionCounts {
  int stick = 0, slip = 0, switches = 0;
};

class ContactPairData {
 public:
  ContactPairData(const System& sys, int index);
  const ContactPair& pair() const { return pair_; }
  /// The slave surface as one curve: its parameter is the xi of the slave points.
  const SurfaceChain& slave_chain() const { return slave_chain_; }
  int num_points() const { return s3_ ? s3_->num_points() : static_cast<int>(sp_.xi.extent(0)); }
  /// The global dofs of both sides' control points (sorted, the same on every rank): the rows
  /// and columns where the pair's K_c has entries.
  std::vector<GO> side_dofs() const;
  /// Current displacements of the two curves from the owned solution, then search + projection.
  void update(const Vector& u);
  /// ALM (mortar_alm and kts_alm, both on the mortar path): the multipliers' update (lbar <-
  /// lambda per slave control point, the penalty's scale at partly covered ones; friction:
  /// lamTA <- tauA); returns max_active_gap_ratio().
  double augment();
  /// ALM, frictionless: the penalty of the next Newton solves x factor (the method of
  /// multipliers' update when the gaps fall slowly; the converged answer does not depend on
  /// it). penalty_raised(): the penalty now over the problem file's.
  void raise_penalty(double factor);
  double penalty_raised() const { return pair_.penalty / penalty0_; }
  void reset_multipliers();
  /// History: the state a load step starts from (ALM multipliers, the projections that warm
  /// start the search, and friction's: the reference projections eta_n, the committed
  /// tangential tractions and the accumulated slip). commit() at a converged load step,
  /// restore() when one fails and is cut.
  void commit();
  void restore();
  /// ALM convergence: the largest weighted gap of the slave control points in contact and,
  /// with friction, the largest weighted stick slip, relative to the smallest slave element
  /// size (0 for kts_penalty, which has no multipliers).
  double max_active_gap_ratio() const;
  bool friction() const { return s3_ ? s3_->friction : fr_.mu > 0; }
  FrictionCounts friction_counts() const {
    return s3_ ? FrictionCounts{s3_->counts[0], s3_->counts[1], s3_->counts[2]} : counts_;
  }
  /// Slave points (KTS: quadrature points; mortar: segment quadrature points in use). A point
  /// without a projection on the master (beyond its ends) has no gap: NaN, and with
  /// projected_only (what the outputs write) it is left out.
  ContactPointState state(bool projected_only = false) const;
  ContactSummary summary() const;
  /// "" or one warning line where the final contact zone covers fewer than about three slave
  /// or master elements (3-D: four), so that the pressure's peak and shape are not resolved
  /// (the forces are): a Hertz zone narrower than one element gave max_pressure +199 % (2-D)
  /// and +150 % (3-D), one of two slave elements -43 %, one of 1.1 master elements +46 %,
  /// exit 0. KTS and kts_alm count their active points (3 x, 3-D 4 x the points of an
  /// element), mortar the slave elements with pressure; on the master, the elements those
  /// points project onto. Collective in 3-D.
  std::string unresolved_zone(int index, const Problem& P) const;
  /// "contact[index] (slave.side on master.side)": how warnings name the pair.
  std::string pair_text(int index, const Problem& P) const;
  /// The slave elements with a point (slot) under pressure (3-D: all ranks', collective).
  int active_slave_elements() const;
  /// The master elements those points project onto (3-D: collective).
  int active_master_elements() const;
  /// The contact potential at the last update: KTS sum_q w <-eps g>^2 / (2 eps),
  /// mortar sum_A w_A lambda_A^2 / (2 eps) (the penalty potential when the multipliers are 0).
  double potential() const;
  bool mortar() const { return mortar_; }
  /// The contact tangent at the last update is symmetric: false where a 2-D mortar pair's
  /// master ends inside a slave element whose covered part it bounds (the boundary terms of
  /// kernels/contact_mortar.hpp, MortarEnds), and for 3-D mortar (the same terms; the loader
  /// already asks for L U there). Frictionless KTS and mortar elsewhere: true.
  bool symmetric_tangent() const { return !ends_found_; }
  /// Gaps up to `band` count as touching: such a point is active with zero pressure (the
  /// tangent gets its penalty stiffness, the residual no force); band <= 0: round-off, 1e-12
  /// of the smallest slave element (the default). The Newton core widens it for one tangent
  /// where a body held only by contact has no active point (NewtonCore::close_gaps). Takes
  /// effect at the next update().
  void set_touch(double band);
  /// The smallest gap of this rank's slave points with a projection (+inf if none).
  double local_min_gap() const;
  /// Mortar: weighted gaps g_A, weights w_A and multipliers lambda_A per slave control point.
  std::vector<double> weighted_gaps() const;
  std::vector<double> mortar_weights() const;
  std::vector<double> mortar_multipliers() const;

  /// The contact tangent's geometric part, -p G (the foot and the normal moving with u: the
  /// consistent linearisation), on (1, the default) or off (0: eps N N^T alone). Far from the
  /// solution, where the pressures are many times their converged values, that part can turn
  /// the tangent indefinite; NewtonCore::newton turns it off at the start of each increment
  /// and after a consistent direction that failed the line search, and on again below 1e-3 of
  /// the increment's first residual. Takes effect at the next assembly.
  double geometric = 1;
  /// The normal force the last assembly put on the slave body (all ranks).
  double assembled_normal_force() const { return s3_ ? assembled_[3] : assembled_[2]; }

  // used by ContactAssembly
  CurveData slave, master;
  SlavePoints sp_;
  std::vector<GO> slave_gid, master_gid;   // global cp ids of the curves' control points
  int p_begin = 0, p_end = 0;              // this rank's slave points
  double thickness = 1;
  // mortar
  MortarState ms_;
  int slots = 0;                           // quadrature slots per slave element (grows)
  MortarScratch scratch_;                  // per-A rows of the assembly kernels (grows)
  MortarEnds ends_;                        // the master ends' images in slave elements (FindMortarEnds)
  bool ends_found_ = false;                // some slave element has one (at the last update)
  int kts_points_per_element_ = 0;         // 2-D KTS: quadrature points per slave element
  void mortar_scratch(int cap);            // (re)allocates scratch_ with cap entries per row
  int a_begin = 0, a_end = 0;              // this rank's slave control points
  // friction (every pair: the slip and state outputs; assembled only where mu > 0)
  FrictionData fr_;
  // the force on the slave body: summed by the assembly kernels on this rank (force_), all
  // ranks' sum after assemble_contact (assembled_: Fx, Fy, Fn, Ft in 2-D, Fx, Fy, Fz, Fn in
  // 3-D; ContactSummary)
  ForceSum force_;
  double assembled_[4] = {0, 0, 0, 0};
  // 3-D (a pair of solids' faces): the pair's state lives here and the methods above forward
  // to it; the 2-D members stay empty
  std::shared_ptr<ContactSurfaces3> s3_;

 private:
  ContactPair pair_;
  SurfaceChain slave_chain_;
  int index_ = 0;
  double penalty0_ = 1;   // the problem file's penalty
  bool mortar_ = false;
  GaussRule gauss_;
  bool segmented_ = true;   // mortar: slots on segments; false for kts_alm (one per element)
  struct Committed {
    Kokkos::View<double*, MemSpace> lambda, mxi, lbar, lamT, lamTA;
    Kokkos::View<int*, MemSpace> melem, mspan, valid;
  } committed_;
  // mortar friction: the committed curves (their displacements at the last converged step)
  // and search grid, onto which the slots' reference projections eta_n are computed
  CurveData slave_c_, master_c_;
  SearchGrid grid_c_;
  SlavePoints ref_sp_;
  Kokkos::View<int*, MemSpace> state_prev_;
  FrictionCounts counts_;
  int rank_ = 0, nranks_ = 1;
  int max_segments_ = 0;   // mortar: segments per slave element the slots hold
  Kokkos::View<double**, Kokkos::LayoutRight, MemSpace> cuts_;   // mortar: segment scratch
  void allocate_points(int n);   // every per-point (per-slot) view, for n points
  void refresh();          // search, projection and contact state at the curves' current u
  void update_friction();
  void find_mortar_ends();   // ends_, ends_found_ at the current slots' projections
  RCP<const Map> replicated_;
  RCP<Import> importer_;
  Kokkos::View<int* [2], MemSpace> slave_rep_, master_rep_;   // replicated dof LIDs of the curves' cps
  double h_min_ = 1;
};

/// Residual and tangent of all pairs: f_c and K_c on the owned map.
struct ContactContribution {
  RCP<Matrix> K;
  RCP<Vector> f;
  int active = 0;   // active points, all ranks
};

/// What assemble_contact keeps from one call to the next: the contact graph (overlap rows) of
/// the last call's coupled control points and their neighbours, reused while they stay the same.
struct ContactGraphCache {
  std::vector<GO> cps;
  std::vector<size_t> nptr;
  std::vector<LO> nbr;
  RCP<const Graph> graph;
};

ContactContribution assemble_contact(const System& sys, std::vector<ContactPairData>& pairs,
                                     ContactGraphCache* cache = nullptr);

}  // namespace iga
