#!/usr/bin/env bash
# build_peers.sh PROGRAM: prints the path of build-peers/PROGRAM, configuring build-peers/ (the
# peer programs' own CMake project) first where it is missing, and bringing PROGRAM up to date
# (nice, -j1; a no-op when it is): dealii_assembly, dealii_lame, dealii_sphere, and iga_sphere,
# which links the main build's build/libigacontact_core.a (relinked when that changed). Used by
# compare_*.sh.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
PEERS=$ROOT/build-peers
if [ ! -f "$PEERS/CMakeCache.txt" ] || [ ! -x "$PEERS/$1" ]; then
  echo "configuring $PEERS for $1" >&2
  nice cmake -S "$ROOT/benchmarks/peers" -B "$PEERS" -DCMAKE_BUILD_TYPE=Release >&2
fi
nice cmake --build "$PEERS" -j1 --target "$1" >&2
echo "$PEERS/$1"
