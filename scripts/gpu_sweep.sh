#!/usr/bin/env bash
# Runs a paper-profile sweep on NVIDIA GPUs (the commands behind results/gpu/): builds semlb once in Release
# without tests or torch, then `semlb sweep MANIFEST --profile paper` on the NVIDIA OpenCL platform, in float unless the
# manifest chooses its precision (a setting, an axis or a group's axis: experiments/accuracy_vs_time.yaml compares both).
# Usage: scripts/gpu_sweep.sh experiments/strong_scaling.yaml [--set ranks=1,2,4] [--results DIR] [--keep-runs]
set -euo pipefail
[[ $# -ge 1 ]] || { echo "usage: $0 MANIFEST [semlb sweep options]" >&2; exit 2; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
# One ICD only: mpirun hands the ranks a colon-separated OCL_ICD_FILENAMES cut at the colon (docs/engine.md).
export OCL_ICD_FILENAMES=libnvidia-opencl.so.1
here=$(cd "$(dirname "$0")/.." && pwd)
BUILD=${BUILD:-/tmp/semlb-gpu}
if [[ ! -x $BUILD/cli/semlb ]]; then
  cmake -S "$here" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DSEMLB_BUILD_TESTS=OFF -DSEMLB_WITH_TORCH=OFF >/dev/null
  cmake --build "$BUILD" -j"$(nproc)" --target semlb >/dev/null
fi
[[ -f $1 ]] || { echo "gpu_sweep.sh: $1: no such manifest" >&2; exit 2; }
# scene.backend.precision beside a precision the manifest sets is refused by the sweep (one key, two values)
float=(--set scene.backend.precision=float)
if grep -v '^[[:space:]]*#' "$1" | grep -qE '(^|[{ ,])precision:'; then float=(); fi
exec "$BUILD/cli/semlb" sweep "$@" --profile paper --set scene.backend.opencl-allpairs.platform=NVIDIA \
  --set scene.backend.opencl-binned.platform=NVIDIA "${float[@]}"
