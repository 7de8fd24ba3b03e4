#!/usr/bin/env bash
# igacontact set-up: installs the Debian packages the project needs (idempotent),
# configures and builds into build/, and (unless --no-example) runs the main example.
# Usage: scripts/setup.sh [--no-example] [--build-type Release|Debug]
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$here"
run_example=1
build_type=Release
while [ $# -gt 0 ]; do
  case "$1" in
    --no-example) run_example=0 ;;
    --build-type) build_type="$2"; shift ;;
    *) echo "setup.sh: unknown option '$1'" >&2; exit 2 ;;
  esac
  shift
done

trilinos_pkgs=""
for x in tpetra belos ifpack2 amesos2 kokkos kokkos-kernels teuchos epetra epetraext aztecoo rtop \
         shylu thyra trilinosss triutils xpetra zoltan zoltan2 muelu amesos anasazi galeri ifpack \
         intrepid2 isorropia ml sacado shards stratimikos teko; do
  trilinos_pkgs="$trilinos_pkgs libtrilinos-$x-dev"
done
pkgs="build-essential cmake ninja-build pkg-config openmpi-bin libopenmpi-dev libhdf5-openmpi-dev \
      libptscotch-dev libmumps-dev libhypre-dev libopenblas0-serial libyaml-cpp-dev libgtest-dev libgmock-dev libbenchmark-dev \
      python3-matplotlib python3-h5py python3-numpy python3-yaml \
      nlohmann-json3-dev clang-14 libclang-rt-14-dev zlib1g-dev \
      paraview python3-paraview xvfb xauth $trilinos_pkgs"

missing=""
for p in $pkgs; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
if [ -n "$missing" ]; then
  echo "setup: installing:$missing"
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends $missing
else
  echo "setup: all Debian packages present"
fi

# optional: libdeflate compresses the .vtu's blocks in half zlib's time (the build falls back
# on zlib without it, so a failed install is only noted)
if ! dpkg-query -W -f='${Status}' libdeflate-dev 2>/dev/null | grep -q "install ok installed"; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends libdeflate-dev ||
    echo "setup: libdeflate-dev not installed: zlib compresses the .vtu files (slower, same format)"
fi

cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE="$build_type"
cmake --build build -j "$(nproc)"

if [ "$run_example" = 1 ]; then
  build/bin/igacontact run examples/wheel.yaml --output out/wheel
  /usr/bin/python3 scripts/plot out/wheel && echo "setup: pictures in out/wheel/*.png"
fi
