// Patch data: the kernels' view of a patch (degrees, knots, spans, control points, the element
// rule), on the device for the System and on the host for the output.
#include "solver/system.hpp"
#include "solver/system_internal.hpp"

#include "model/quadrature.hpp"

#include <stdexcept>
#include <string>
#include <type_traits>

namespace iga {

namespace {

// Degrees, basis functions and elements per direction: the part of the kernels' patch data
// that is the same on the device and on the host.
template <class PD>
void set_patch_shape(PD& pd, const Patch& P) {
  for (int d = 0; d < PD::dim; ++d) {
    pd.p[d] = P.degree[d];
    pd.n[d] = P.ncp(d);
    pd.ne[d] = P.num_elements(d);
  }
}

template <int D>
PatchDataT<D, MemSpace> make_patch_data_d(const Patch& P) {
  if (P.dim() != D) throw std::logic_error("make_patch_data: patch of dimension " + std::to_string(P.dim()));
  PatchDataT<D, MemSpace> pd;
  set_patch_shape(pd, P);
  static const char* uname[] = {"U0", "U1", "U2"};
  static const char* sname[] = {"span0", "span1", "span2"};
  for (int d = 0; d < D; ++d) {
    pd.U[d] = system_detail::to_device(uname[d], P.knots[d]);
    pd.span[d] = system_detail::to_device(sname[d], P.element_spans(d));
  }
  // the kernels' rows: coordinates, then the weight (column D)
  Kokkos::View<double* [D + 1], MemSpace> cp("cp", P.cp.size());
  auto h = Kokkos::create_mirror_view(cp);
  for (size_t a = 0; a < P.cp.size(); ++a) {
    for (int c = 0; c < D; ++c) h(a, c) = P.cp[a].x[c];
    h(a, D) = P.cp[a].w;
  }
  Kokkos::deep_copy(cp, h);
  pd.cp = cp;
  return pd;
}

}  // namespace

namespace system_detail {

PatchData make_patch_data(const Patch& P) { return make_patch_data_d<2>(P); }
PatchData3 make_patch_data3(const Patch& P) { return make_patch_data_d<3>(P); }

// The element rule of the patch (solver.quadrature): Gauss leaves PatchData's rule empty
// (the kernels map the Gauss rule onto each span); spline puts each direction's generalised
// Gaussian rule there, or keeps Gauss in a direction where it cannot be built.
template <class PD>
void set_quadrature_d(PatchBlock& bd, PD& pd, const Patch& pt, Quadrature q) {
  constexpr int D = PD::dim;
  static const char* xname[] = {"qx0", "qx1", "qx2"};
  static const char* wname[] = {"qw0", "qw1", "qw2"};
  static const char* oname[] = {"qoff0", "qoff1", "qoff2"};
  int nodes[D];
  std::string what[D];
  for (int d = 0; d < D; ++d) {
    nodes[d] = pt.num_elements(d) * (pt.degree[d] + 1);
    what[d] = "gauss";
    if (q != Quadrature::Spline) continue;
    const SplineRule r = spline_gauss_rule(pt.knots[d], pt.degree[d]);
    if (!r.failure.empty()) {
      what[d] = "gauss (the spline rule: " + r.failure + ")";
      continue;
    }
    what[d] = "spline";
    nodes[d] = static_cast<int>(r.x.size());
    pd.qx[d] = to_device(xname[d], r.x);
    pd.qw[d] = to_device(wname[d], r.w);
    pd.qoff[d] = to_device(oname[d], r.off);
  }
  bd.quadrature_points = 1;
  bool same = true;
  for (int d = 0; d < D; ++d) {
    bd.quadrature_points *= nodes[d];
    same = same && what[d] == what[0];
  }
  bd.quadrature = what[0];
  if (!same)
    for (int d = 1; d < D; ++d) bd.quadrature += " x " + what[d];
}

void set_quadrature(PatchBlock& bd, const Patch& pt, Quadrature q) {
  if (pt.dim() == 3)
    set_quadrature_d(bd, bd.pd3, pt, q);
  else
    set_quadrature_d(bd, bd.pd, pt, q);
}

}  // namespace system_detail

namespace {
template <int D>
PatchDataT<D, Kokkos::HostSpace> host_patch_data_d(const Patch& P) {
  if (P.dim() != D) throw std::logic_error("host_patch_data: patch of dimension " + std::to_string(P.dim()));
  PatchDataT<D, Kokkos::HostSpace> pd;
  set_patch_shape(pd, P);
  for (int d = 0; d < D; ++d) {
    pd.U[d] = Kokkos::View<const double*, Kokkos::HostSpace>(P.knots[d].data(), P.knots[d].size());
    const std::vector<int> spans = P.element_spans(d);
    Kokkos::View<int*, Kokkos::HostSpace> sp("span", spans.size());
    for (size_t k = 0; k < spans.size(); ++k) sp(k) = spans[k];
    pd.span[d] = sp;
  }
  static_assert(sizeof(ControlPoint) == (kMaxDim + 1) * sizeof(double) && std::is_standard_layout_v<ControlPoint>,
                "ControlPoint is laid out as rows {x, y, z, w}");
  if constexpr (D == kMaxDim) {
    // the patch's own control points, seen as rows {x, y, z, w} (no copy)
    pd.cp = Kokkos::View<const double* [D + 1], Kokkos::HostSpace>(reinterpret_cast<const double*>(P.cp.data()), P.cp.size());
  } else {
    // rows {x, y, w}: a copy without z
    Kokkos::View<double* [D + 1], Kokkos::HostSpace> cp("cp", P.cp.size());
    for (size_t a = 0; a < P.cp.size(); ++a) {
      for (int c = 0; c < D; ++c) cp(a, c) = P.cp[a].x[c];
      cp(a, D) = P.cp[a].w;
    }
    pd.cp = cp;
  }
  return pd;
}
}  // namespace

HostPatchData host_patch_data(const Patch& P) { return host_patch_data_d<2>(P); }
HostPatchData3 host_patch_data3(const Patch& P) { return host_patch_data_d<3>(P); }

}  // namespace iga
