// GoogleTest main for the kernel tests on a bare Kokkos (tests/gpu/CMakeLists.txt): Kokkos
// initialised on its default execution space, which it names first.
#include <gtest/gtest.h>
#include <Kokkos_Core.hpp>

#include <cstdio>

int main(int argc, char** argv) {
  Kokkos::ScopeGuard kokkos(argc, argv);
  ::testing::InitGoogleTest(&argc, argv);
  std::printf("Kokkos %d, default execution space %s, concurrency %d\n", KOKKOS_VERSION,
              Kokkos::DefaultExecutionSpace::name(), static_cast<int>(Kokkos::DefaultExecutionSpace().concurrency()));
  return RUN_ALL_TESTS();
}
