# Finds the Trilinos 13.2 stack (Kokkos, Tpetra, Belos, Ifpack2, Amesos2, MueLu), MPI,
# parallel HDF5, yaml-cpp and nlohmann-json, and defines one interface target
# `igacontact::stack` that carries all of it.
#
# Facts this relies on (Debian 12, measured):
#  * Trilinos 13.2 has no Trilinos::all_libs target, so we link ${Trilinos_LIBRARIES}
#    and ${Trilinos_TPL_LIBRARIES} by hand;
#  * the Kokkos::kokkos target carries a wrong include path, so we add
#    ${Trilinos_INCLUDE_DIRS} ourselves, as SYSTEM includes (silences their warnings);
#  * C++20 breaks Teuchos headers: the caller sets C++17 without extensions first.
#
# IGACONTACT_TRILINOS_PREFIX (cache) points at another Trilinos 13.2 install, e.g. the
# OpenMP build made by scripts/build-trilinos-openmp.sh; empty means the system one.

set(IGACONTACT_TRILINOS_PREFIX "" CACHE PATH
    "Prefix of a Trilinos 13.2 install to use instead of the system one (e.g. an OpenMP build)")
if(IGACONTACT_TRILINOS_PREFIX)
  list(PREPEND CMAKE_PREFIX_PATH "${IGACONTACT_TRILINOS_PREFIX}")
  set(Trilinos_DIR "${IGACONTACT_TRILINOS_PREFIX}/lib/cmake/Trilinos" CACHE PATH "" FORCE)
endif()

find_package(MPI REQUIRED COMPONENTS C CXX)
find_package(Trilinos 13.2 REQUIRED COMPONENTS Tpetra Belos Ifpack2 Amesos2 MueLu)
message(STATUS "Trilinos ${Trilinos_VERSION} from ${Trilinos_DIR}")

# Kokkos backends of this Trilinos, from its KokkosCore_config.h. With OpenMP our kernels
# (Kokkos headers with OpenMP pragmas) are compiled and linked with the compiler's OpenMP.
find_file(IGACONTACT_KOKKOS_CONFIG KokkosCore_config.h PATHS ${Trilinos_INCLUDE_DIRS} NO_DEFAULT_PATH)
set(IGACONTACT_KOKKOS_OPENMP OFF)
if(IGACONTACT_KOKKOS_CONFIG)
  file(STRINGS "${IGACONTACT_KOKKOS_CONFIG}" _omp REGEX "^#define KOKKOS_ENABLE_OPENMP")
  if(_omp)
    set(IGACONTACT_KOKKOS_OPENMP ON)
  endif()
endif()
if(IGACONTACT_KOKKOS_OPENMP)
  find_package(OpenMP REQUIRED COMPONENTS CXX)
  message(STATUS "Kokkos OpenMP backend: kernels run on OMP_NUM_THREADS threads per rank")
else()
  message(STATUS "Kokkos Serial backend only: one thread per MPI rank")
endif()

set(HDF5_PREFER_PARALLEL ON)
find_package(HDF5 REQUIRED COMPONENTS C)
if(NOT HDF5_IS_PARALLEL)
  message(WARNING "HDF5 is not the parallel build; install libhdf5-openmpi-dev")
endif()
find_package(yaml-cpp REQUIRED)
find_package(nlohmann_json 3 REQUIRED)

add_library(igacontact_stack INTERFACE)
add_library(igacontact::stack ALIAS igacontact_stack)
target_include_directories(igacontact_stack SYSTEM INTERFACE
  ${Trilinos_INCLUDE_DIRS} ${Trilinos_TPL_INCLUDE_DIRS} ${HDF5_C_INCLUDE_DIRS})
target_link_libraries(igacontact_stack INTERFACE
  ${Trilinos_LIBRARIES} ${Trilinos_TPL_LIBRARIES} ${HDF5_C_LIBRARIES}
  yaml-cpp nlohmann_json::nlohmann_json MPI::MPI_CXX)
if(IGACONTACT_KOKKOS_OPENMP)
  target_link_libraries(igacontact_stack INTERFACE OpenMP::OpenMP_CXX)
endif()

# MUMPS (Debian's libmumps-dev, MPI build): the sparse direct solver, through its C interface
# (Amesos2 in Debian's Trilinos has no MUMPS adapter). Its ordering libraries and ScaLAPACK
# come with its shared libraries.
find_path(MUMPS_INCLUDE_DIR dmumps_c.h PATH_SUFFIXES MUMPS)
find_library(MUMPS_DMUMPS_LIBRARY dmumps)
find_library(MUMPS_COMMON_LIBRARY mumps_common)
if(NOT MUMPS_INCLUDE_DIR OR NOT MUMPS_DMUMPS_LIBRARY OR NOT MUMPS_COMMON_LIBRARY)
  message(FATAL_ERROR "MUMPS not found: install libmumps-dev (scripts/setup.sh does)")
endif()
message(STATUS "MUMPS: ${MUMPS_DMUMPS_LIBRARY}")
target_include_directories(igacontact_stack SYSTEM INTERFACE ${MUMPS_INCLUDE_DIR})
target_link_libraries(igacontact_stack INTERFACE ${MUMPS_DMUMPS_LIBRARY} ${MUMPS_COMMON_LIBRARY} MPI::MPI_C)

# hypre (Debian's libhypre-dev, MPI build): BoomerAMG, the default preconditioner of gmres and cg
find_path(HYPRE_INCLUDE_DIR HYPRE.h PATH_SUFFIXES hypre)
find_library(HYPRE_LIBRARY HYPRE)
if(NOT HYPRE_INCLUDE_DIR OR NOT HYPRE_LIBRARY)
  message(FATAL_ERROR "hypre not found: install libhypre-dev (scripts/setup.sh does)")
endif()
message(STATUS "hypre: ${HYPRE_LIBRARY}")
target_include_directories(igacontact_stack SYSTEM INTERFACE ${HYPRE_INCLUDE_DIR})
target_link_libraries(igacontact_stack INTERFACE ${HYPRE_LIBRARY})
