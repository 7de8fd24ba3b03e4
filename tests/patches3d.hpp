#pragma once
// Trivariate NURBS blocks built directly as the kernels' PatchDataT<3> (no 3-D model yet):
// a box and a quarter of a thick cylinder shell extruded along z; and the matrix graph of a
// block for the 3-D assembly kernel. Shared by tests/test_kernels_3d.cpp and
// benchmarks/bench_kernels.cpp.
#include <KokkosSparse_CrsMatrix.hpp>

#include <array>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "kernels/elasticity.hpp"
#include "model/nurbs.hpp"

namespace iga::test3d {

// A trivariate NURBS block on the host: degrees, knots, control points (x, y, z, w), the first
// direction fastest.
struct Block3 {
  int p[3] = {1, 1, 1};
  std::vector<double> U[3];
  std::vector<std::array<double, 4>> cp;
  int n(int d) const { return static_cast<int>(U[d].size()) - p[d] - 1; }
  int index(int i, int j, int k) const { return i + n(0) * (j + n(1) * k); }
  bool curved = false;
  double ri = 1, ro = 2, H = 1;   // the cylinder shell (curved)
  double L[3] = {1, 1, 1};       // the box
};

inline std::vector<double> greville(const std::vector<double>& U, int p) {
  const int n = static_cast<int>(U.size()) - p - 1;
  std::vector<double> g(n);
  for (int i = 0; i < n; ++i) {
    double s = 0;
    for (int k = 1; k <= p; ++k) s += U[i + k];
    g[i] = p > 0 ? s / p : U[i];
  }
  return g;
}

// Box [0, L0] x [0, L1] x [0, L2], degrees p, ne elements per direction (uniform open knots,
// control points at the Greville abscissae: the map is x_d = L_d xi_d exactly).
inline Block3 box(std::array<int, 3> p, std::array<int, 3> ne, std::array<double, 3> L = {1.0, 0.7, 1.3}) {
  Block3 b;
  std::vector<double> g[3];
  for (int d = 0; d < 3; ++d) {
    b.p[d] = p[d];
    b.U[d] = uniform_open_knots(p[d], ne[d]);
    g[d] = greville(b.U[d], p[d]);
    b.L[d] = L[d];
  }
  for (int k = 0; k < b.n(2); ++k)
    for (int j = 0; j < b.n(1); ++j)
      for (int i = 0; i < b.n(0); ++i) b.cp.push_back({L[0] * g[0][i], L[1] * g[1][j], L[2] * g[2][k], 1.0});
  return b;
}

// A quarter of a thick cylinder shell, radii ri..ro, height H: the bivariate quarter annulus
// (angle: rational quadratic, weights 1, sqrt(2)/2, 1; radius: linear) elevated to degree p in
// both directions and subdivided, extruded along z with degree p2 (z at the Greville abscissae).
inline Block3 shell(int p, std::array<int, 3> ne, int p2) {
  const double ri = 1.0, ro = 2.0, H = 0.8, w = std::sqrt(0.5);
  Patch a;
  a.degree = {2, 1};
  a.knots[0] = {0, 0, 0, 1, 1, 1};
  a.knots[1] = {0, 0, 1, 1};
  for (double r : {ri, ro}) {
    a.cp.push_back(ControlPoint({r, 0}, 1));
    a.cp.push_back(ControlPoint({r, r}, w));
    a.cp.push_back(ControlPoint({0, r}, 1));
  }
  if (p > 2) a.elevate(0, p - 2);
  if (p > 1) a.elevate(1, p - 1);
  a.subdivide(0, ne[0]);
  a.subdivide(1, ne[1]);
  Block3 b;
  b.curved = true;
  b.ri = ri; b.ro = ro; b.H = H;
  b.p[0] = a.degree[0]; b.p[1] = a.degree[1]; b.p[2] = p2;
  b.U[0] = a.knots[0]; b.U[1] = a.knots[1];
  b.U[2] = uniform_open_knots(p2, ne[2]);
  const auto gz = greville(b.U[2], p2);
  for (int k = 0; k < b.n(2); ++k)
    for (size_t g = 0; g < a.cp.size(); ++g) b.cp.push_back({a.cp[g].x[0], a.cp[g].x[1], H * gz[k], a.cp[g].w});
  return b;
}

template <class T, class Mem>
Kokkos::View<T*, Mem> to_view(const char* name, const std::vector<T>& v) {
  Kokkos::View<T*, Mem> d(std::string(name), v.size());
  auto h = Kokkos::create_mirror_view(d);
  for (size_t i = 0; i < v.size(); ++i) h(i) = v[i];
  Kokkos::deep_copy(d, h);
  return d;
}

// The kernels' patch data in memory space Mem (lid: the identity).
template <class Mem>
PatchDataT<3, Mem> patch_data(const Block3& b) {
  PatchDataT<3, Mem> pd;
  for (int d = 0; d < 3; ++d) {
    pd.p[d] = b.p[d];
    pd.n[d] = b.n(d);
    const auto spans = nonempty_spans(b.U[d], b.p[d]);
    pd.ne[d] = static_cast<int>(spans.size());
    pd.U[d] = to_view<double, Mem>("U", b.U[d]);
    pd.span[d] = to_view<int, Mem>("span", spans);
  }
  Kokkos::View<double* [4], Mem> cp("cp", b.cp.size());
  auto h = Kokkos::create_mirror_view(cp);
  for (size_t a = 0; a < b.cp.size(); ++a)
    for (int c = 0; c < 4; ++c) h(a, c) = b.cp[a][c];
  Kokkos::deep_copy(cp, h);
  pd.cp = cp;
  std::vector<int> lid(b.cp.size());
  for (size_t a = 0; a < lid.size(); ++a) lid[a] = static_cast<int>(a);
  pd.lid = to_view<int, Mem>("lid", lid);
  return pd;
}

using Crs = KokkosSparse::CrsMatrix<double, int, Kokkos::Device<ExecSpace, MemSpace>, void, size_t>;

// The matrix graph of the block: control points sharing an element, 3 x 3 blocks, sorted rows.
inline Crs make_matrix(const HostPatchData3& pd) {
  const int n = static_cast<int>(pd.cp.extent(0));
  std::vector<std::set<int>> adj(n);
  for (int e = 0; e < pd.num_elements(); ++e)
    for (int a = 0; a < pd.nen(); ++a)
      for (int c = 0; c < pd.nen(); ++c) adj[element_cp(pd, e, a)].insert(element_cp(pd, e, c));
  std::vector<size_t> rowmap(3 * n + 1, 0);
  std::vector<int> cols;
  for (int g = 0; g < n; ++g)
    for (int i = 0; i < 3; ++i) {
      for (int h : adj[g])
        for (int k = 0; k < 3; ++k) cols.push_back(3 * h + k);
      rowmap[3 * g + i + 1] = cols.size();
    }
  auto rm = to_view<size_t, MemSpace>("rowmap", rowmap);
  auto en = to_view<int, MemSpace>("entries", cols);
  Kokkos::View<double*, MemSpace> val("values", cols.size());
  return Crs("K", 3 * n, 3 * n, cols.size(), val, rm, en);
}

}  // namespace iga::test3d
