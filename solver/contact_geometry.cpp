// Contact surfaces as device curves, and the search grid over the master elements.
#include "solver/contact.hpp"
#include "solver/contact_internal.hpp"

#include <algorithm>
#include <cmath>

namespace iga::contact_detail {

using system_detail::to_device;

CurveData make_curve(const System& sys, const ContactSurface& s, const SurfaceChain& ch, std::vector<GO>& gids) {
  const Curve& c = ch.curve;
  CurveData d;
  d.p = c.degree;
  d.nb = c.ncp();
  const auto spans = c.element_spans();
  d.ne = static_cast<int>(spans.size());
  // the outward normal's sign: side_normal(East, sign) = sign (t_y, -t_x)
  d.side = static_cast<int>(Side::East);
  d.orientation = ch.normal_sign;
  d.U = to_device("U", c.knots);
  d.span = to_device("span", spans);
  d.X = Kokkos::View<double* [2], MemSpace>("X", d.nb);
  d.u = Kokkos::View<double* [2], MemSpace>("u", d.nb);
  std::vector<double> w(d.nb);
  auto hX = Kokkos::create_mirror_view(d.X);
  gids.resize(d.nb);
  for (int k = 0; k < d.nb; ++k) {
    hX(k, 0) = c.cp[k].x[0];
    hX(k, 1) = c.cp[k].x[1];
    w[k] = c.cp[k].w;
    gids[k] = sys.cp_gid(s.body, ch.cp_patch[k], c.patch_index[k]);
  }
  Kokkos::deep_copy(d.X, hX);
  d.w = to_device("w", w);
  d.lid = Kokkos::View<int*, MemSpace>("lid", d.nb);
  return d;
}
/// Search grid over the master element boxes (convex hull of their current control points).
SearchGrid build_search_grid(const CurveData& m) {
  Kokkos::View<double* [4], MemSpace> dbox("boxes", m.ne);
  {
    Kokkos::parallel_for("iga::MasterElementBoxes", Kokkos::RangePolicy<ExecSpace>(0, m.ne), KOKKOS_LAMBDA(const int e) {
      double b[4] = {1e300, 1e300, -1e300, -1e300};
      for (int k = m.span(e) - m.p; k <= m.span(e); ++k) {
        const double x = m.X(k, 0) + m.u(k, 0), y = m.X(k, 1) + m.u(k, 1);
        b[0] = x < b[0] ? x : b[0];
        b[1] = y < b[1] ? y : b[1];
        b[2] = x > b[2] ? x : b[2];
        b[3] = y > b[3] ? y : b[3];
      }
      for (int c = 0; c < 4; ++c) dbox(e, c) = b[c];
    });
  }
  // grid cells of twice the largest box size; each box, grown by that size, goes into the
  // cells it overlaps
  auto hbox = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), dbox);
  double ext = 0, X0 = 1e300, Y0 = 1e300, X1 = -1e300, Y1 = -1e300;
  for (int e = 0; e < m.ne; ++e) {
    ext = std::max({ext, hbox(e, 2) - hbox(e, 0), hbox(e, 3) - hbox(e, 1)});
    X0 = std::min(X0, hbox(e, 0)); Y0 = std::min(Y0, hbox(e, 1));
    X1 = std::max(X1, hbox(e, 2)); Y1 = std::max(Y1, hbox(e, 3));
  }
  const double margin = std::max(ext, 1e-12);
  SearchGrid grid;
  grid.h = 2 * margin;
  grid.x0 = X0 - margin;
  grid.y0 = Y0 - margin;
  grid.nx = std::max(1, static_cast<int>(std::ceil((X1 - X0 + 2 * margin) / grid.h)));
  grid.ny = std::max(1, static_cast<int>(std::ceil((Y1 - Y0 + 2 * margin) / grid.h)));
  // (cell, element) pairs sorted by cell: only the non-empty cells are stored
  std::vector<std::pair<long long, int>> pairs;
  pairs.reserve(4 * static_cast<size_t>(m.ne));
  for (int e = 0; e < m.ne; ++e) {
    const int i0 = std::max(0, grid.cell_of(hbox(e, 0) - margin, 0)), i1 = std::min(grid.nx - 1, grid.cell_of(hbox(e, 2) + margin, 0));
    const int j0 = std::max(0, grid.cell_of(hbox(e, 1) - margin, 1)), j1 = std::min(grid.ny - 1, grid.cell_of(hbox(e, 3) + margin, 1));
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) pairs.emplace_back(i + static_cast<long long>(grid.nx) * j, e);
  }
  std::sort(pairs.begin(), pairs.end());
  std::vector<long long> key;
  std::vector<int> start, elems(pairs.size());
  for (size_t k = 0; k < pairs.size(); ++k) {
    if (k == 0 || pairs[k].first != pairs[k - 1].first) {
      key.push_back(pairs[k].first);
      start.push_back(static_cast<int>(k));
    }
    elems[k] = pairs[k].second;
  }
  start.push_back(static_cast<int>(pairs.size()));
  grid.key = to_device("grid_key", key);
  grid.start = to_device("grid_start", start);
  grid.elems = to_device("grid_elems", elems);
  grid.box = dbox;
  return grid;
}

}  // namespace iga::contact_detail
