#!/usr/bin/env bash
# The end-to-end benchmark (docs/performance.md "End to end on one node with 2 H200s"): scenes/epidermis.yaml (all effects) and scenes/mechanics.yaml at CELLS cells, STEPS steps,
# float, opencl-binned on 1..G GPUs of one node (one rank per GPU), no snapshots or checkpoints; then one CSV row
# per run (analysis/end_to_end_epidermis.py). Usage:
#   bash scripts/gpu/end_to_end_epidermis.sh SEMLB OUT_DIR "MACHINE TEXT" [GPUS="1 2"] [CELLS=435661] [STEPS=1000]
# PLATFORM (default NVIDIA) picks the OpenCL platform by name: PLATFORM=Portable runs the same on PoCL (CPU), one
# "GPU" meaning one rank. SETS (default empty) adds settings to every run, e.g. SETS="--set decomposition.overlap=false"
# times the blocking ghost exchange (docs/performance.md). Writes OUT_DIR/end_to_end_epidermis.csv and OUT_DIR/end_to_end_mechanics.csv (+ the run folders under OUT_DIR/runs).
set -euo pipefail
S=$1; OUT=$2; MACHINE=$3; GPUS=${4:-1 2}; CELLS=${5:-435661}; STEPS=${6:-1000}
here=$(cd "$(dirname "$0")/../.." && pwd)
PY=${PYTHON:-python3}
PLATFORM=${PLATFORM:-NVIDIA}
read -ra sets <<< "${SETS:-}"
icd=(); [ "$PLATFORM" = NVIDIA ] && icd=(-x OCL_ICD_FILENAMES=libnvidia-opencl.so.1)
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
mkdir -p "$OUT/runs"
for scene in epidermis mechanics; do
  for g in $GPUS; do
    d="$OUT/runs/${scene}_${g}gpu"; rm -rf "$d"
    args=(sim --scene "$here/scenes/$scene.yaml" --out "$d" --steps "$STEPS" --backend opencl-binned --platform "$PLATFORM"
          --precision float --quiet --set tissue.cells="$CELLS" --set output.snapshot_every=0
          --set output.checkpoint_every=0 --set output.log_every=100 "${sets[@]}")
    if [ "$g" = 1 ]; then "$S" "${args[@]}"
    else mpirun --oversubscribe -np "$g" --bind-to none "${icd[@]}" "$S" "${args[@]}"; fi
  done
  rm -f "$OUT/end_to_end_$scene.csv"
  for g in $GPUS; do
    gpus=$g; [ "$PLATFORM" = NVIDIA ] || gpus=0  # PoCL: ranks on the CPU
    $PY "$here/analysis/end_to_end_epidermis.py" --append --machine "$MACHINE" --gpus "$gpus" \
        --out "$OUT/end_to_end_$scene.csv" "$OUT/runs/${scene}_${g}gpu"
  done
  cat "$OUT/end_to_end_$scene.csv"
done
