// Null space of the elastic operator: rigid-body modes and the coordinates for aggregation.
#include "solver/system.hpp"
#include "solver/system_internal.hpp"
#include "kernels/numbering.hpp"
#include "model/rigid_modes.hpp"

#include <cmath>

namespace iga {

using namespace system_detail;

RCP<MultiVector> System::rigid_body_modes() const {
  const int nm = num_rigid_modes(dim());
  RCP<MultiVector> Z = rcp(new MultiVector(owned_, nm));
  auto h = Z->getLocalViewHost(Tpetra::Access::OverwriteAll);
  for (size_t l = 0; l < owned_->getNodeNumElements(); ++l) {
    const GO dof = owned_->getGlobalElement(l);
    const auto& cp = control_point(point_of_dof(dof, dim()));
    const int c = component_of_dof(dof, dim());
    for (int m = 0; m < nm; ++m) h(l, m) = rigid_mode(m, c, cp.x.data(), dim());
  }
  return Z;
}

RCP<MultiVector> System::aggregation_coordinates() const {
  // one row per owned control point: MueLu's node map (node g holds dofs dim g + c)
  const size_t n = owned_->getNodeNumElements() / dim();
  std::vector<GO> gids(n);
  for (size_t l = 0; l < n; ++l) gids[l] = point_of_dof(owned_->getGlobalElement(static_cast<LO>(dof_of(l, 0, dim()))), dim());
  RCP<const Map> nodes = rcp(new Map(Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid(), gids.data(), n, 0, comm_));
  const int dm = dim();
  RCP<MultiVector> X = rcp(new MultiVector(nodes, dm));

  // D: the diameter of all control nets together. Body b is moved by 1e3 D b along x, so
  // that the distance-Laplacian weight between two bodies, <= 1e-6 / D^2, is far below the
  // drop tolerance times the weights within a body (>= 1 / D^2). Each control point is also
  // nudged by 1e-6 D times its place (i / n_xi, j / n_eta) in the net: coincident control
  // points (a collapsed edge) then have distinct coordinates, strongly coupled to each other;
  // elsewhere the nudge is far below the element size.
  double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
  for (const auto& c : cp_pos_)
    for (int d = 0; d < dm; ++d) lo[d] = std::min(lo[d], c.x[d]), hi[d] = std::max(hi[d], c.x[d]);
  const double D = std::max(dm == 2 ? std::hypot(hi[0] - lo[0], hi[1] - lo[1])
                                    : std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                                                (hi[2] - lo[2]) * (hi[2] - lo[2])),
                            1e-300);
  // the nudge: each control point's place in the net of the first patch it belongs to
  std::vector<std::array<double, 3>> place(num_cps_, {-1.0, -1.0, -1.0});
  for (const PatchBlock& bd : blocks_) {
    const Patch& q = P_.bodies[bd.body].patches[bd.patch];
    for (size_t a = 0; a < bd.gid.size(); ++a)
      if (place[bd.gid[a]][0] < 0) {
        const int n[3] = {q.ncp(0), q.ncp(1), q.ncp(2)};
        int ij[3];
        tensor_ij(static_cast<int>(a), n, dm, ij);
        place[bd.gid[a]][0] = static_cast<double>(ij[0]) / q.ncp(0) + bd.patch;
        for (int d = 1; d < dm; ++d) place[bd.gid[a]][d] = static_cast<double>(ij[d]) / q.ncp(d);
      }
  }
  auto h = X->getLocalViewHost(Tpetra::Access::OverwriteAll);
  for (size_t l = 0; l < n; ++l) {
    const size_t b = body_of(gids[l]);
    const ControlPoint& c = cp_pos_[gids[l]];
    h(l, 0) = c.x[0] + 1e-6 * D * place[gids[l]][0] + 1e3 * D * static_cast<double>(b);
    for (int d = 1; d < dm; ++d) h(l, d) = c.x[d] + 1e-6 * D * place[gids[l]][d];
  }
  return X;
}


}  // namespace iga
