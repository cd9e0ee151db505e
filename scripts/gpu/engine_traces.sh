#!/usr/bin/env bash
# Engine traces on GPUs (docs/controllers.md "Engine traces"): scenes/epidermis.yaml at CELLS cells, STEPS steps, float, opencl-binned, RANKS
# ranks (one per GPU), an event every EVERY steps, one run per policy; keeps scene.yaml, run.csv, rank_times.csv and
# trace.jsonl under OUT/runs/policy=P/ (the layout analysis/trace_model.py and the replay_score runner read). Usage:
#   bash scripts/gpu/engine_traces.sh SEMLB OUT [RANKS=2] [CELLS=435661] [STEPS=1000] [EVERY=50] [POLICIES="static reactive gru gromacs_dlb"]
set -euo pipefail
S=$1; OUT=$2; RANKS=${3:-2}; CELLS=${4:-435661}; STEPS=${5:-1000}; EVERY=${6:-50}
POLICIES=${7:-static reactive gru gromacs_dlb}
here=$(cd "$(dirname "$0")/../.." && pwd)
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
for p in $POLICIES; do
  run=$(mktemp -d); keep="$OUT/runs/policy=$p"; mkdir -p "$keep"
  mpirun --oversubscribe -np "$RANKS" --bind-to none -x OCL_ICD_FILENAMES=libnvidia-opencl.so.1 "$S" sim \
    --scene "$here/scenes/epidermis.yaml" --out "$run" --steps "$STEPS" --backend opencl-binned --platform NVIDIA \
    --precision float --quiet --set tissue.cells="$CELLS" --set output.snapshot_every=0 --set output.checkpoint_every=0 \
    --set decomposition.policy="$p" --set decomposition.rebalance_every="$EVERY"
  for f in scene.yaml run.csv rank_times.csv trace.jsonl; do cp "$run/$f" "$keep/"; done
  rm -rf "$run"
done
