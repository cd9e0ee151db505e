#!/usr/bin/env bash
# Kernel times of two source trees in one call on one NVIDIA GPU (does a refactor keep every kernel's time?):
# builds `semlb` from each tree, then ROUNDS rounds (default 2) alternating old and new of `semlb bench engine`
# (scenes/mechanics.yaml, ENGINE_RUNS precision:skin, default "float:0 float:0.5 double:0", SEMLB_OPENCL_PROFILE=1: device ms per kernel and step) and
# `semlb bench cells` (scenes/epidermis.yaml, float: ms per cell update of the stage and the grid), each output in
# OUT/{engine,cells}_{old,new}_{round}.txt; analysis/before_after.py turns them into OUT/before_after.csv.
# Usage: bash scripts/gpu/before_after.sh OUT OLD_SRC NEW_SRC [CELLS]   (CELLS: default 435661)
set -euo pipefail
OUT=$1; OLD=$2; NEW=$3; CELLS=${4:-435661}; ROUNDS=${ROUNDS:-2}
ENGINE_RUNS=${ENGINE_RUNS:-"float:0 float:0.5 double:0"}
here=$(cd "$(dirname "$0")/../.." && pwd)
export OCL_ICD_FILENAMES=${OCL_ICD_FILENAMES:-libnvidia-opencl.so.1}
mkdir -p "$OUT"
for src in "$OLD" "$NEW"; do
  cmake -S "$src" -B "$src/build-gpu" -DCMAKE_BUILD_TYPE=Release -DSEMLB_BUILD_TESTS=OFF -DSEMLB_WITH_TORCH=OFF > "$OUT/cmake_$(basename "$src").log"
  cmake --build "$src/build-gpu" -j"$(nproc)" --target semlb >> "$OUT/cmake_$(basename "$src").log"
done
for round in $(seq 1 "$ROUNDS"); do
  for which in old new; do
    src=$OLD; [ "$which" = new ] && src=$NEW
    S="$src/build-gpu/cli/semlb"
    for run in $ENGINE_RUNS; do  # precision:skin
      SEMLB_OPENCL_PROFILE=1 "$S" bench engine --scene "$src/scenes/mechanics.yaml" --platform NVIDIA \
        --backends opencl-binned --cells "$CELLS" --steps 200 --precision "${run%%:*}" --set backend.skin="${run##*:}"
    done > "$OUT/engine_${which}_$round.txt" 2>&1
    "$S" bench cells --scene "$src/scenes/epidermis.yaml" --platform NVIDIA --backends opencl-binned \
      --cells "$CELLS" --steps 10 --precision float > "$OUT/cells_${which}_$round.txt" 2>&1
  done
done
/usr/bin/python3 "$here/analysis/before_after.py" "$OUT" > "$OUT/before_after.csv" || python3 "$here/analysis/before_after.py" "$OUT" > "$OUT/before_after.csv"
cat "$OUT/before_after.csv"
