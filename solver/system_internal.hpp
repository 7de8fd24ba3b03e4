#pragma once
// Internal to solver/system*.cpp, solver/patch_data.cpp, solver/graph.cpp: host vectors
// copied into device views, and the patch data the System puts into each PatchBlock.
#include <string>
#include <vector>

#include "solver/system.hpp"

namespace iga::system_detail {

template <class T>
Kokkos::View<T*, MemSpace> to_device(const std::string& name, const std::vector<T>& v) {
  Kokkos::View<T*, MemSpace> d(name, v.size());
  auto h = Kokkos::create_mirror_view(d);
  for (size_t k = 0; k < v.size(); ++k) h(k) = v[k];
  Kokkos::deep_copy(d, h);
  return d;
}

PatchData make_patch_data(const Patch& P);
PatchData3 make_patch_data3(const Patch& P);
// The element rule of the patch (solver.quadrature), in solver/patch_data.cpp.
void set_quadrature(PatchBlock& bd, const Patch& pt, Quadrature q);

}  // namespace iga::system_detail
