#!/usr/bin/env bash
# build_peers.sh PROGRAM: prints the path of build-peers/PROGRAM, building build-peers/ (the peer
# programs' own CMake project, nice, -j1) first where it is missing. Used by compare_*.sh.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
PEERS=$ROOT/build-peers
if [ ! -x "$PEERS/$1" ]; then
  echo "building $PEERS/$1" >&2
  nice cmake -S "$ROOT/benchmarks/peers" -B "$PEERS" -DCMAKE_BUILD_TYPE=Release >&2
  nice cmake --build "$PEERS" -j1 >&2
fi
echo "$PEERS/$1"
