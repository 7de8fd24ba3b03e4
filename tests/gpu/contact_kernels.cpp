// The frictionless 3-D contact kernels (kernels/contact_kts3.hpp, contact_mortar3.hpp) compiled
// for the execution space: the solver (solver/contact3d.cpp, contact_assembly.cpp) fills their
// inputs from Tpetra, which a bare Kokkos build lacks, so the GPU check compiles them (ptxas
// reports each kernel's registers, stack frame and spills: the cost of their per-thread arrays,
// scripts/gpu-check). Nothing calls instantiate_contact_kernels3: these kernels are compiled for
// the device, not run on it (their numbers are tested in tests/test_kts3d.cpp through the
// solver). The friction kernels (Sacado) are not built here.
#include <KokkosSparse_CrsMatrix.hpp>

#include "kernels/contact_kts3.hpp"
#include "kernels/contact_mortar3.hpp"

namespace {

using Crs = KokkosSparse::CrsMatrix<double, int, Kokkos::Device<iga::ExecSpace, iga::MemSpace>, void, size_t>;
using FView = Kokkos::View<double*, iga::MemSpace>;

template <class K>
void launch_empty(const char* name, const K& k) {
  Kokkos::parallel_for(name, Kokkos::RangePolicy<iga::ExecSpace>(0, 0), k);
}

}  // namespace

void instantiate_contact_kernels3();
void instantiate_contact_kernels3() {
  launch_empty("iga::MortarSegments3", iga::MortarSegments3{});
  launch_empty("iga::ProjectSlavePoints3", iga::ProjectSlavePoints3{});
  launch_empty("iga::MortarGaps3", iga::MortarGaps3{});
  launch_empty("iga::MortarPointPressure3", iga::MortarPointPressure3{});
  launch_empty("iga::AssembleKts3", iga::AssembleKts3<Crs, FView>{});
  launch_empty("iga::AssembleMortarEdge3", iga::AssembleMortarEdge3<Crs>{});
  launch_empty("iga::AssembleMortarGap3", iga::AssembleMortarGap3<Crs>{});
}
