#!/usr/bin/env bash
# Runs a paper-profile sweep on NVIDIA GPUs (the commands behind results/gpu/): builds semlb once in Release
# without tests or torch, then `semlb sweep MANIFEST --profile paper` on the NVIDIA OpenCL platform. The precision is
# the manifest's: each paper profile names it (float for the GPU runs; accuracy_vs_time compares both).
# Usage: scripts/gpu_sweep.sh experiments/strong_scaling.yaml [--set ranks=1,2,4] [--results DIR] [--keep-runs]
set -euo pipefail
[[ $# -ge 1 ]] || { echo "usage: $0 MANIFEST [semlb sweep options]" >&2; exit 2; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
# One ICD only: mpirun hands the ranks a colon-separated OCL_ICD_FILENAMES cut at the colon (docs/engine.md).
export OCL_ICD_FILENAMES=${OCL_ICD_FILENAMES:-libnvidia-opencl.so.1}
export BUILD=${BUILD:-/tmp/semlb-gpu}
bash "$(dirname "$0")/gpu/build.sh"
exec "$BUILD/cli/semlb" sweep "$@" --profile paper --set scene.backend.opencl-allpairs.platform=NVIDIA \
  --set scene.backend.opencl-binned.platform=NVIDIA
