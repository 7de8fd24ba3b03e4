// Patch data: the kernels' view of a patch (degrees, knots, spans, control points, the element
// rule), on the device for the System and on the host for the output.
#include "solver/system.hpp"
#include "solver/system_internal.hpp"

#include "model/quadrature.hpp"

#include <type_traits>

namespace iga {

namespace {

// Degrees, basis functions and elements per direction: the part of the kernels' patch data
// that is the same on the device and on the host.
template <class PD>
void set_patch_shape(PD& pd, const Patch& P) {
  for (int d = 0; d < 2; ++d) {
    pd.p[d] = P.degree[d];
    pd.n[d] = P.ncp(d);
    pd.ne[d] = static_cast<int>(P.element_spans(d).size());
  }
}

}  // namespace

namespace system_detail {

PatchData make_patch_data(const Patch& P) {
  PatchData pd;
  set_patch_shape(pd, P);
  pd.U[0] = to_device("U0", P.knots[0]);
  pd.U[1] = to_device("U1", P.knots[1]);
  pd.span[0] = to_device("span0", P.element_spans(0));
  pd.span[1] = to_device("span1", P.element_spans(1));
  // the kernels' rows: coordinates, then the weight (column kMaxDim)
  Kokkos::View<double* [kMaxDim + 1], MemSpace> cp("cp", P.cp.size());
  auto h = Kokkos::create_mirror_view(cp);
  for (size_t a = 0; a < P.cp.size(); ++a) {
    for (int c = 0; c < kMaxDim; ++c) h(a, c) = P.cp[a].x[c];
    h(a, kMaxDim) = P.cp[a].w;
  }
  Kokkos::deep_copy(cp, h);
  pd.cp = cp;
  return pd;
}

// The element rule of the patch (solver.quadrature): Gauss leaves PatchData's rule empty
// (the kernels map the Gauss rule onto each span); spline puts each direction's generalised
// Gaussian rule there, or keeps Gauss in a direction where it cannot be built.
void set_quadrature(PatchBlock& bd, const Patch& pt, Quadrature q) {
  int nodes[2];
  std::string what[2];
  for (int d = 0; d < 2; ++d) {
    nodes[d] = static_cast<int>(pt.element_spans(d).size()) * (pt.degree[d] + 1);
    what[d] = "gauss";
    if (q != Quadrature::Spline) continue;
    const SplineRule r = spline_gauss_rule(pt.knots[d], pt.degree[d]);
    if (!r.failure.empty()) {
      what[d] = "gauss (the spline rule: " + r.failure + ")";
      continue;
    }
    what[d] = "spline";
    nodes[d] = static_cast<int>(r.x.size());
    bd.pd.qx[d] = to_device(d == 0 ? "qx0" : "qx1", r.x);
    bd.pd.qw[d] = to_device(d == 0 ? "qw0" : "qw1", r.w);
    bd.pd.qoff[d] = to_device(d == 0 ? "qoff0" : "qoff1", r.off);
  }
  bd.quadrature_points = nodes[0] * nodes[1];
  bd.quadrature = what[0] == what[1] ? what[0] : what[0] + " x " + what[1];
}

}  // namespace system_detail

HostPatchData host_patch_data(const Patch& P) {
  HostPatchData pd;
  set_patch_shape(pd, P);
  pd.U[0] = Kokkos::View<const double*, Kokkos::HostSpace>(P.knots[0].data(), P.knots[0].size());
  pd.U[1] = Kokkos::View<const double*, Kokkos::HostSpace>(P.knots[1].data(), P.knots[1].size());
  // the patch's own control points, seen as rows {x..., w} of kMaxDim + 1 doubles (no copy)
  static_assert(sizeof(ControlPoint) == (kMaxDim + 1) * sizeof(double) && std::is_standard_layout_v<ControlPoint>,
                "ControlPoint is laid out as the kernels' control point rows {x..., w}");
  pd.cp = Kokkos::View<const double* [kMaxDim + 1], Kokkos::HostSpace>(reinterpret_cast<const double*>(P.cp.data()), P.cp.size());
  return pd;
}

}  // namespace iga
