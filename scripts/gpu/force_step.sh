#!/usr/bin/env bash
# The force step's A/B on one NVIDIA GPU (docs/performance.md "Half list"): opencl-binned with the full and the half
# neighbour list (backend.opencl-binned.newton), float and double, at scenes/mechanics.yaml's 435,661 cells (6,533,913
# elements), skin 0.5 um: ROUNDS interleaved rounds of `semlb bench engine` (200 steps after 20 warm-up), then one
# profiled run of each (SEMLB_OPENCL_PROFILE=1: device ms per kernel).
# Usage: bash scripts/gpu/force_step.sh SEMLB OUT   (ROUNDS, default 2; CELLS, default 435661; SETS: extra flags;
#   PLATFORM: the OpenCL platform name substring, default NVIDIA)
# Writes OUT/force_step.csv (precision, newton, round, elements, ms_per_step, machine), OUT/force_step.txt (the
# bench tables) and OUT/force_step_profile.txt.
set -uo pipefail
S=$1; OUT=$2
here=$(cd "$(dirname "$0")/../.." && pwd)
[ "${PLATFORM:-NVIDIA}" != NVIDIA ] || export OCL_ICD_FILENAMES=${OCL_ICD_FILENAMES:-libnvidia-opencl.so.1}
mkdir -p "$OUT"
machine=$(nvidia-smi --query-gpu=name --format=csv,noheader 2>/dev/null | head -1)
bench() {  # PRECISION NEWTON [more flags]
  local p=$1 n=$2; shift 2
  # shellcheck disable=SC2086
  "$S" bench engine --scene "$here/scenes/mechanics.yaml" --platform "${PLATFORM:-NVIDIA}" --backends opencl-binned \
    --cells "${CELLS:-435661}" --steps 200 --warmup 20 --precision "$p" --set backend.skin=0.5 \
    --set backend.opencl-binned.newton="$n" ${SETS:-} "$@"
}
echo "precision,newton,round,elements,ms_per_step,machine" > "$OUT/force_step.csv"
: > "$OUT/force_step.txt"
for round in $(seq "${ROUNDS:-2}"); do
  for p in float double; do
    for n in false true; do
      t=$(bench "$p" "$n" 2>&1) || { echo "$t" >&2; echo "force_step.sh: bench $p newton=$n failed" >&2; exit 1; }
      echo "$t" >> "$OUT/force_step.txt"
      # the row: backend precision cells elements seconds elem-steps/s ms/step ...
      echo "$t" | awk -v p="$p" -v n="$n" -v r="$round" -v m="$machine" \
        '$1 == "opencl-binned" { printf "%s,%d,%d,%s,%s,%s\n", p, n == "true", r, $4, $7, m }' >> "$OUT/force_step.csv"
    done
  done
done
for p in float double; do
  for n in false true; do SEMLB_OPENCL_PROFILE=1 bench "$p" "$n"; done
done > "$OUT/force_step_profile.txt" 2>&1
cat "$OUT/force_step.csv"
