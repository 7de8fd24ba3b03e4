#pragma once
// 3-D contact pairs (issue 36): surfaces made of patch faces of solids, knot-to-surface
// penalty and augmented Lagrangian (kernels/contact_kts3.hpp). ContactPairData holds one of
// these for a solid's pair and forwards to it; the Newton core, the assembly and the outputs
// see the same pair interface in 2-D and 3-D.
#include <vector>

#include "kernels/contact_kts3.hpp"
#include "solver/system.hpp"

namespace iga {

struct ContactPointState;

class ContactSurfaces3 {
 public:
  ContactSurfaces3(const System& sys, const ContactPair& pair);
  /// Current displacements of both surfaces from the owned solution, then search + projection.
  void update(const Vector& u);
  void refresh();
  int num_points() const { return static_cast<int>(sp.weight.extent(0)); }
  /// The groups of coupled control points (global ids) of this rank's points with a
  /// projection, the master element widened by one control point each way; active: the
  /// number of this rank's active points.
  void groups(std::vector<std::vector<GO>>& out, int& active) const;
  /// Overlap LIDs of the faces' control points in the contact matrix's numbering cps.
  void set_lids(const std::vector<GO>& cps);
  void state(ContactPointState& s, bool projected_only) const;
  double h_min() const { return h_min_; }
  /// Global control point ids of both surfaces (sorted, unique).
  std::vector<GO> surface_gids() const;

  ContactPair pair;
  ContactFaces slave, master;
  SlavePoints3 sp;
  int p_begin = 0, p_end = 0;   // this rank's slave points
  ForceSum3 force;

 private:
  struct HostFace {
    std::vector<GO> gid;        // per face control point
    int p[2], n[2], ne[2];
    std::vector<int> span[2];
  };
  std::vector<HostFace> hs_, hm_;
  RCP<const Map> replicated_;
  RCP<Import> importer_;
  std::vector<Kokkos::View<int* [3], MemSpace>> rep_s_, rep_m_;   // replicated dof LIDs per face cp
  double h_min_ = 1;
};

}  // namespace iga
