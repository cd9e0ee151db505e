#!/usr/bin/env bash
# The force step's A/B on one NVIDIA GPU (docs/performance.md "Half list", "Pair exp", "Slots grouped by list length"):
# opencl-binned with the full and the half neighbour list (backend.opencl-binned.newton), the pair force law's exp
# (backend.pair_exp) and the slots of each work-group taken longest list first (-DSEMLB_NL_GROUP_SORT), at
# scenes/mechanics.yaml's 435,661 cells (6,533,913 elements), skin 0.5 um: ROUNDS interleaved rounds of `semlb bench
# engine` (200 steps after 20 warm-up) over the variants, then one profiled run of each (SEMLB_OPENCL_PROFILE=1:
# device ms per kernel).
# Usage: bash scripts/gpu/force_step.sh SEMLB OUT   (ROUNDS, default 2; CELLS, default 435661; SETS: extra flags;
#   PLATFORM: the OpenCL platform name substring, default NVIDIA; VARIANTS: space-separated
#   PRECISION:NEWTON:PAIR_EXP[:sorted], default float and double with the full and the half list at each precision's
#   default exp, double's ranged exp with both lists and its native exp with the half list, and float's two lists and
#   double's half list with sorted slots; SETS must not set newton or pair_exp, which the CSV records)
# Writes OUT/force_step.csv (precision, newton, pair_exp, slots, round, elements, ms_per_step, machine),
# OUT/force_step.txt (the bench tables) and OUT/force_step_profile.txt.
set -uo pipefail
S=$1; OUT=$2
here=$(cd "$(dirname "$0")/../.." && pwd)
[ "${PLATFORM:-NVIDIA}" != NVIDIA ] || export OCL_ICD_FILENAMES=${OCL_ICD_FILENAMES:-libnvidia-opencl.so.1}
variants=${VARIANTS:-float:false:native float:true:native double:false:builtin double:true:builtin double:false:ranged
  double:true:ranged double:true:native float:false:native:sorted float:true:native:sorted double:true:builtin:sorted}
for v in $variants; do  # every variant checked before the first bench: a typo does not end the call midway
  [[ $v =~ ^(float|double):(false|true):(builtin|ranged|native)(:sorted)?$ ]] || { echo "force_step.sh: variant '$v' \
is not PRECISION:NEWTON:PAIR_EXP[:sorted] (float|double, false|true, builtin|ranged|native)" >&2; exit 2; }
done
mkdir -p "$OUT"
machine=$(nvidia-smi --query-gpu=name --format=csv,noheader 2>/dev/null | head -1)
bench() {  # PRECISION NEWTON PAIR_EXP SLOTS [more flags]
  local p=$1 n=$2 e=$3 o=${SEMLB_OPENCL_BUILD_OPTIONS:-}; shift 3
  [ "$1" != sorted ] || o="$o -DSEMLB_NL_GROUP_SORT"
  shift
  # shellcheck disable=SC2086
  SEMLB_OPENCL_BUILD_OPTIONS=$o "$S" bench engine --scene "$here/scenes/mechanics.yaml" --platform "${PLATFORM:-NVIDIA}" --backends opencl-binned \
    --cells "${CELLS:-435661}" --steps 200 --warmup 20 --precision "$p" --set backend.skin=0.5 \
    --set backend.opencl-binned.newton="$n" --set backend.pair_exp="$e" ${SETS:-} "$@"
}
split() { IFS=: read -r p n e o <<< "$1"; o=${o:-bins}; }  # VARIANT: p n e o (precision, newton, pair exp, slots)
echo "precision,newton,pair_exp,slots,round,elements,ms_per_step,machine" > "$OUT/force_step.csv"
: > "$OUT/force_step.txt"
for round in $(seq "${ROUNDS:-2}"); do
  for v in $variants; do
    split "$v"
    t=$(bench "$p" "$n" "$e" "$o" 2>&1) || { echo "$t" >&2; echo "force_step.sh: bench $v failed" >&2; exit 1; }
    echo "$t" >> "$OUT/force_step.txt"
    # the row: backend precision cells elements seconds elem-steps/s ms/step ...
    echo "$t" | awk -v p="$p" -v n="$n" -v e="$e" -v o="$o" -v r="$round" -v m="$machine" \
      '$1 == "opencl-binned" { printf "%s,%d,%s,%s,%d,%s,%s,%s\n", p, n == "true", e, o, r, $4, $7, m }' \
      >> "$OUT/force_step.csv"
  done
done
for v in $variants; do
  split "$v"
  echo "== $v"
  SEMLB_OPENCL_PROFILE=1 bench "$p" "$n" "$e" "$o"
done > "$OUT/force_step_profile.txt" 2>&1
cat "$OUT/force_step.csv"
