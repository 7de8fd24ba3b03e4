#!/usr/bin/env bash
# Optional: Trilinos 13.2 with the Kokkos OpenMP backend, from Debian's own source package,
# into a prefix of its own (default /opt/trilinos-openmp). Then build igacontact against it:
#   cmake -S . -B build-omp -G Ninja -DIGACONTACT_TRILINOS_PREFIX=/opt/trilinos-openmp
#   cmake --build build-omp
#   OMP_NUM_THREADS=2 build-omp/bin/igacontact examples/wheel.yaml
# Only Tpetra, Belos, Ifpack2, MueLu, Amesos2 and Sacado (the friction tangent's forward AD),
# and what they need, are enabled; Tpetra is
# instantiated for double / int / long long on OpenMP (its default node then), shared
# libraries, no tests or examples. CI stays on the Debian binaries.
set -euo pipefail
prefix="${1:-/opt/trilinos-openmp}"
work="${WORK:-/tmp/trilinos-src}"
SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"

# deb-src for the same archive as the binaries
src=/etc/apt/sources.list.d/debian.sources
if [ -f "$src" ] && ! grep -q "^Types:.*deb-src" "$src"; then
  $SUDO sed -i 's/^Types: deb$/Types: deb deb-src/' "$src"
fi
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends \
  dpkg-dev cmake ninja-build gfortran libopenmpi-dev libblas-dev liblapack-dev
mkdir -p "$work" && cd "$work"
[ -d trilinos-13.2.0 ] || apt-get source -qq trilinos
cd trilinos-13.2.0
start=$(date +%s)
cmake -S . -B build -G Ninja \
  -DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_PREFIX="$prefix" -DBUILD_SHARED_LIBS=ON \
  -DCMAKE_CXX_STANDARD=17 -DCMAKE_CXX_EXTENSIONS=OFF \
  -DTPL_ENABLE_MPI=ON -DTPL_ENABLE_BLAS=ON -DTPL_ENABLE_LAPACK=ON \
  -DTrilinos_ENABLE_ALL_OPTIONAL_PACKAGES=OFF -DTrilinos_ENABLE_TESTS=OFF -DTrilinos_ENABLE_EXAMPLES=OFF \
  -DTrilinos_ENABLE_OpenMP=ON -DKokkos_ENABLE_OPENMP=ON -DKokkos_ENABLE_SERIAL=ON \
  -DTrilinos_ENABLE_Tpetra=ON -DTrilinos_ENABLE_Belos=ON -DTrilinos_ENABLE_Ifpack2=ON \
  -DTrilinos_ENABLE_MueLu=ON -DTrilinos_ENABLE_Amesos2=ON -DTrilinos_ENABLE_Sacado=ON \
  -DTpetra_INST_DOUBLE=ON -DTpetra_INST_INT_INT=OFF -DTpetra_INST_INT_LONG_LONG=ON \
  -DTpetra_INST_SERIAL=OFF -DTpetra_INST_OPENMP=ON -DTpetra_INST_COMPLEX_DOUBLE=OFF
nice -n 19 cmake --build build -j "$(nproc)"
$SUDO cmake --install build
echo "build-trilinos-openmp: built and installed into $prefix in $(( ($(date +%s) - start) / 60 )) min"
