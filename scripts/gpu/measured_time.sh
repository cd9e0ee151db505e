#!/usr/bin/env bash
# Measured GPU time on one device (docs/measured_time.md): P ranks taking turns on one GPU with device timers, by
# default the paper's regime scene (the epidermis at CELLS cells, the left half proliferating; SCENE names another). Each stage writes under OUT and is
# skipped when its outputs are there already, so a stage list can be spread over several device calls.
#   bash scripts/gpu/measured_time.sh SEMLB OUT STAGE...
# Stages:
#   tissue  the scene's state at step START, made once (OUT/tissue/final.h5): every later run starts from it
#   cost    what the device timers cost: one rank, decomposition.timing measured against device, ROUNDS rounds
#   turns   turns validated: static on 1, 2 and 4 ranks taking turns (device timing), and each slab of the 2-rank run
#           alone (tissue.x_range) on one rank
#   record  the measured workload (output.workload with device timers) of the scene on one rank: OUT/record/workload.h5
#   e2e     the end-to-end runs: LAUNCHES launches x RANKS x POLICIES, interleaved (launch-major, then P, then policy)
# Each run keeps its small files (rank_times.csv, run.csv, scene.yaml, workload.h5) and its trace reduced to each
# event's boundaries, decision and times (boundaries.jsonl; KEEP_TRACES=1 keeps trace.jsonl whole), so that OUT can
# travel between device calls (scripts/gpu/pack_results.sh).
# Environment: SCENE (epidermis: scenes/SCENE.yaml), PLATFORM (NVIDIA; Portable runs the same on PoCL), CELLS (435661), STEPS (300), EVERY (10: steps per
# rebalancing event), SKIN (0.5), RANKS ("2 4 8"), POLICIES ("static reactive gru persistence all_tensor"),
# LAUNCHES (3; LAUNCH_FROM 1: the first launch number), ROUNDS (2), START (0: the runs cover steps START .. START + STEPS), GROWTH ("--set effects.growth.front.x0=2975 --set effects.growth.front.speed=0").
set -euo pipefail
S=$(realpath "$1"); OUT=$2; shift 2
SCENE=${SCENE:-epidermis}; START=${START:-0}
here=$(cd "$(dirname "$0")/../.." && pwd)
PLATFORM=${PLATFORM:-NVIDIA}; CELLS=${CELLS:-435661}; STEPS=${STEPS:-300}; EVERY=${EVERY:-10}; SKIN=${SKIN:-0.5}
RANKS=${RANKS:-2 4 8}; POLICIES=${POLICIES:-static reactive gru persistence all_tensor}; LAUNCHES=${LAUNCHES:-3}
ROUNDS=${ROUNDS:-2}
GROWTH=${GROWTH---set effects.growth.front.x0=2975 --set effects.growth.front.speed=0}  # set and empty: none
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
icd=(); [ "$PLATFORM" = NVIDIA ] && icd=(-x OCL_ICD_FILENAMES=libnvidia-opencl.so.1)
mkdir -p "$OUT"
OUT=$(realpath "$OUT")
read -ra growth <<< "$GROWTH"
scene=(--scene "$here/scenes/$SCENE.yaml" --backend opencl-binned --platform "$PLATFORM" --precision float --quiet
       --set backend.skin="$SKIN" --set decomposition.rebalance_every="$EVERY" --set output.snapshot_every=0
       --set output.checkpoint_every=0 --set output.log_every=100 "${growth[@]}")
from_tissue=(--set "tissue={file: $OUT/tissue/final.h5}")
timed=(--set decomposition.timing=device --set decomposition.device_sharing=turns)

# run NAME RANKS ARGS...: `semlb sim` under mpirun into OUT/NAME unless it finished before (OUT/NAME/done); keeps the small files.
run() {
  local name=$1 np=$2; shift 2
  local d="$OUT/$name"
  if [ -f "$d/done" ]; then return; fi
  rm -rf "$d"
  local t0; t0=$(date +%s.%N)
  mpirun --oversubscribe --bind-to none -np "$np" "${icd[@]}" "$S" sim "${scene[@]}" --out "$d" "$@"
  echo "$name: $(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }') s wall" | tee -a "$OUT/wall.log"
  rm -f "$d/final.h5" "$d"/*.xmf  # the final state is not needed afterwards (and large)
  if [ -z "${KEEP_TRACES:-}" ] && [ -f "$d/trace.jsonl" ]; then  # the tables read each event's boundaries only
    /usr/bin/env python3 - "$d/trace.jsonl" "$d/boundaries.jsonl" <<'PYEOF'
import json, os, sys
with open(sys.argv[1]) as f, open(sys.argv[2] + ".tmp", "w") as o:
    for line in f:
        if line.strip():
            e = json.loads(line)
            o.write(json.dumps({k: e[k] for k in ("event", "boundaries", "decision", "times") if k in e}) + "\n")
os.replace(sys.argv[2] + ".tmp", sys.argv[2])
os.remove(sys.argv[1])
PYEOF
  fi
  touch "$d/done"
}

# attr FILE NAME: a real attribute of an HDF5 file's root (h5py, else h5dump)
attr() {
  /usr/bin/env python3 -c "import h5py; print(repr(float(h5py.File('$1', 'r').attrs['$2'])))" 2>/dev/null ||
    h5dump -a "/$2" "$1" | grep -o '(0): [-0-9.e+]*' | cut -d' ' -f2
}

for stage in "$@"; do
  case $stage in
    tissue)
      [ -f "$OUT/tissue/final.h5" ] || "$S" sim "${scene[@]}" --set tissue.cells="$CELLS" --steps "$START" --out "$OUT/tissue" ;;
    cost)
      for round in $(seq 1 "$ROUNDS"); do
        for timing in measured device; do
          run "cost/${timing}_$round" 1 "${from_tissue[@]}" --steps "$((START + STEPS))" --set decomposition.timing=$timing
        done
      done ;;
    turns)
      for np in 1 2 4; do
        extra=(); [ "$np" = 2 ] && extra=(--set output.workload=true)  # its x0 and slice width place the slabs below
        run "turns/np$np" "$np" "${from_tissue[@]}" --steps "$((START + 100))" --set decomposition.rebalance_every=20 \
          --set decomposition.policy=static "${timed[@]}" "${extra[@]}"
      done
      # each slab of the 2-rank run alone: the cells of its first partition (the trace's first boundary)
      trace=$OUT/turns/np2/trace.jsonl; [ -f "$trace" ] || trace=$OUT/turns/np2/boundaries.jsonl
      b=$(grep -o '"boundaries": *\[[0-9]*' "$trace" | head -1 | grep -o '[0-9]*$')
      x0=$(attr "$OUT/turns/np2/workload.h5" x0_um); width=$(attr "$OUT/turns/np2/workload.h5" slice_width_um)
      xb=$(/usr/bin/env python3 -c "print($x0 + $b * $width)")
      echo "turns: the 2-rank run's first boundary: slice $b, x = $xb um" | tee "$OUT/turns/split.txt"
      run "turns/alone0" 1 --set "tissue={file: $OUT/tissue/final.h5, x_range: [-1e9, $xb]}" --steps "$((START + 100))" \
        --set decomposition.rebalance_every=20 --set decomposition.policy=static "${timed[@]}"
      run "turns/alone1" 1 --set "tissue={file: $OUT/tissue/final.h5, x_range: [$xb, 1e9]}" --steps "$((START + 100))" \
        --set decomposition.rebalance_every=20 --set decomposition.policy=static "${timed[@]}" ;;
    record)
      run record 1 "${from_tissue[@]}" --steps "$((START + STEPS))" "${timed[@]}" --set output.workload=true ;;
    e2e)
      for launch in $(seq "${LAUNCH_FROM:-1}" "$LAUNCHES"); do
        for np in $RANKS; do
          for policy in $POLICIES; do
            run "e2e/${policy}_np${np}_l$launch" "$np" "${from_tissue[@]}" --steps "$((START + STEPS))" "${timed[@]}" \
              --set decomposition.policy="$policy"
          done
        done
      done ;;
    *) echo "measured_time.sh: unknown stage '$stage' (tissue cost turns record e2e)" >&2; exit 2 ;;
  esac
done
