#pragma once
// A sphere octant as a trivariate patch and a patch face as the contact kernels' SurfaceData
// (kernels/contact_surface.hpp): shared by tests/test_contact3d.cpp and benchmarks/bench_kernels.cpp.
#include <cmath>

#include "kernels/contact_surface.hpp"
#include "model/nurbs.hpp"

namespace iga::test3d {

// The octant of the sphere of radius R as one patch (xi the longitude, eta the latitude, zeta
// the radius from R / 2 to R), refined; its back face (zeta = 1) is the sphere of radius R.
inline Patch sphere_octant(double R, int n) {
  Patch P;
  P.pdim = 3;
  P.degree = {2, 2, 1};
  P.knots = {uniform_open_knots(2, 1), uniform_open_knots(2, 1), uniform_open_knots(1, 1)};
  const double w = std::sqrt(0.5), c[3][2] = {{1, 0}, {1, 1}, {0, 1}}, cw[3] = {1, w, 1};
  for (double r : {0.5 * R, R})
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i)
        P.cp.push_back(ControlPoint({r * c[j][0] * c[i][0], r * c[j][0] * c[i][1], r * c[j][1]}, cw[i] * cw[j]));
  P.subdivide(0, n);
  P.subdivide(1, n);
  return P;
}

inline SurfaceData surface_of(const Patch& F) {
  SurfaceData sd;
  for (int d = 0; d < 2; ++d) {
    sd.p[d] = F.degree[d];
    sd.n[d] = F.ncp(d);
    sd.ne[d] = F.num_elements(d);
    Kokkos::View<double*, MemSpace> U("U", F.knots[d].size());
    auto hU = Kokkos::create_mirror_view(U);
    for (size_t k = 0; k < F.knots[d].size(); ++k) hU(k) = F.knots[d][k];
    Kokkos::deep_copy(U, hU);
    sd.U[d] = U;
    const auto spans = F.element_spans(d);
    Kokkos::View<int*, MemSpace> sp("span", spans.size());
    auto hs = Kokkos::create_mirror_view(sp);
    for (size_t k = 0; k < spans.size(); ++k) hs(k) = spans[k];
    Kokkos::deep_copy(sp, hs);
    sd.span[d] = sp;
  }
  Kokkos::View<double* [4], MemSpace> cp("cp", F.cp.size());
  auto h = Kokkos::create_mirror_view(cp);
  for (size_t a = 0; a < F.cp.size(); ++a) {
    for (int c = 0; c < 3; ++c) h(a, c) = F.cp[a].x[c];
    h(a, 3) = F.cp[a].w;
  }
  Kokkos::deep_copy(cp, h);
  sd.cp = cp;
  return sd;
}


}  // namespace iga::test3d
