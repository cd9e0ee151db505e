#!/usr/bin/env bash
# The library of engine workloads (issue 25; results/gpu/workloads/README.md): each variant of the developing epidermis
# at the paper's size (435,661 cells, Day 0-5, 2,400 steps of 0.05 h, an event every 20 steps) and of the epidermis
# scene, run on ONE device with output.workload (a decomposition of one rank: W_s does not depend on the partition, so
# one run serves every rank count). Writes OUT/NAME.h5 (workload), OUT/NAME.run.csv and OUT/NAME.scene.yaml per variant.
# Usage: bash scripts/gpu/workload_library.sh SEMLB OUT [VARIANT ...]   (default: every variant below)
set -euo pipefail
S=$1; OUT=$2; shift 2
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
here=$(cd "$(dirname "$0")/../.." && pwd)
dev="$here/scenes/epidermis_development.yaml"
epi="$here/scenes/epidermis.yaml"
common=(--backend opencl-binned --platform NVIDIA --precision float --quiet --set tissue.cells=435661
        --set output.snapshot_every=0 --set output.checkpoint_every=0 --set output.workload=true)
# NAME|scene|steps|overrides (the sheet spans x 0 .. ~5,950 um; 24.8 um/h = half of it in 120 h, the shipped speed)
variants=(
  "dev_v24.8_s1|$dev|2400|--set effects.growth.front.speed=24.8"
  "dev_v24.8_s2|$dev|2400|--set effects.growth.front.speed=24.8 --seed 2"
  "dev_v12.4_s1|$dev|2400|--set effects.growth.front.speed=12.4"
  "dev_v6.2_s1|$dev|2400|--set effects.growth.front.speed=6.2"
  "dev_v3.1_s1|$dev|2400|--set effects.growth.front.speed=3.1"
  "dev_centre_v12.4_s1|$dev|2400|--set effects.growth.front.x0=2975 --set effects.growth.front.speed=12.4"
  "epidermis_s1|$epi|1000|--set decomposition.rebalance_every=50"
  "epidermis_long_s2|$epi|4000|--set decomposition.rebalance_every=50 --seed 2"
)
want=("$@")
mkdir -p "$OUT"
for v in "${variants[@]}"; do
  IFS='|' read -r name scene steps extra <<<"$v"
  if [ ${#want[@]} -gt 0 ] && [[ " ${want[*]} " != *" $name "* ]]; then continue; fi
  run=$(mktemp -d)
  start=$(date +%s)
  # shellcheck disable=SC2086
  "$S" sim --scene "$scene" --out "$run" --steps "$steps" "${common[@]}" $extra
  echo "$name: $(( $(date +%s) - start )) s wall"
  cp "$run/workload.h5" "$OUT/$name.h5"
  cp "$run/run.csv" "$OUT/$name.run.csv"
  cp "$run/scene.yaml" "$OUT/$name.scene.yaml"
  rm -rf "$run"
done
