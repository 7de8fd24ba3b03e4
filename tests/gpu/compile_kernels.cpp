// Kernels compiled for the execution space but not run by the GPU check: the frictionless 3-D
// contact kernels (kernels/contact_kts3.hpp, contact_mortar3.hpp), the 2-D contact kernels
// (contact_kts.hpp, contact_mortar.hpp) and the 2-D element kernels (elasticity.hpp,
// elasticity_sf.hpp) at P = 2 and 5. The solver fills their inputs from Tpetra, which a bare
// Kokkos build lacks; here they are compiled for the device, where ptxas reports each one's
// registers, stack frame and spills (the cost of its per-thread arrays, scripts/gpu-check).
// Nothing calls instantiate_kernels: their numbers are tested through the solver
// (tests/test_kts3d.cpp, test_contact.cpp, test_mortar.cpp, test_kernels.cpp). The friction
// kernels (Sacado) are not built here.
#include <KokkosSparse_CrsMatrix.hpp>

#include "kernels/contact_kts3.hpp"
#include "kernels/contact_mortar.hpp"
#include "kernels/contact_mortar3.hpp"
#include "kernels/elasticity.hpp"
#include "kernels/elasticity_sf.hpp"

namespace {

using Crs = KokkosSparse::CrsMatrix<double, int, Kokkos::Device<iga::ExecSpace, iga::MemSpace>, void, size_t>;
using FView = Kokkos::View<double*, iga::MemSpace>;

template <class K>
void launch_empty(const char* name, const K& k) {
  Kokkos::parallel_for(name, Kokkos::RangePolicy<iga::ExecSpace>(0, 0), k);
}

template <int P>
void instantiate_2d() {
  launch_empty("iga::AssembleKts", iga::AssembleKts<P, Crs, FView>{});
  iga::AssembleInternalT<2, P, Crs>{}.run(0);          // e_end <= e_begin: returns at once
  iga::SumFactorizedTangent<P, Crs>{}.run(iga::SumFactorRows{});
}

}  // namespace

void instantiate_kernels();
void instantiate_kernels() {
  launch_empty("iga::MortarSegments3", iga::MortarSegments3{});
  launch_empty("iga::ProjectSlavePoints3", iga::ProjectSlavePoints3{});
  launch_empty("iga::MortarGaps3", iga::MortarGaps3{});
  launch_empty("iga::MortarPointPressure3", iga::MortarPointPressure3{});
  launch_empty("iga::AssembleKts3", iga::AssembleKts3<Crs, FView>{});
  Kokkos::parallel_for("iga::AssembleMortarPressure3", Kokkos::TeamPolicy<iga::ExecSpace>(0, 1), iga::AssembleKts3<Crs, FView>{});
  launch_empty("iga::AssembleMortarEdge3", iga::AssembleMortarEdge3<Crs>{});
  launch_empty("iga::AssembleMortarGap3", iga::AssembleMortarGap3<Crs>{});
  launch_empty("iga::ProjectSlavePoints", iga::ProjectSlavePoints{});
  launch_empty("iga::MortarSegments", iga::MortarSegments{});
  launch_empty("iga::MortarGaps", iga::MortarGaps{});
  launch_empty("iga::MortarPointPressure", iga::MortarPointPressure{});
  launch_empty("iga::AssembleMortarGap", iga::AssembleMortarGap<Crs>{});
  instantiate_2d<2>();
  instantiate_2d<5>();
}
