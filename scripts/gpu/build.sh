#!/usr/bin/env bash
# Builds semlb for the GPU scripts once: Release, no tests, no torch, into BUILD (default /tmp/semlb-gpu), unless
# BUILD/cli/semlb is there already. Usage: bash scripts/gpu/build.sh   (BUILD=DIR)
set -euo pipefail
here=$(cd "$(dirname "$0")/../.." && pwd)
BUILD=${BUILD:-/tmp/semlb-gpu}
[[ -x $BUILD/cli/semlb ]] && exit 0
cmake -S "$here" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DSEMLB_BUILD_TESTS=OFF -DSEMLB_WITH_TORCH=OFF >/dev/null
cmake --build "$BUILD" -j"$(nproc)" --target semlb >/dev/null
