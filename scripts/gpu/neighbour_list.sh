#!/usr/bin/env bash
# Measurements of opencl-binned's neighbour list on one NVIDIA GPU (docs/performance.md "Neighbour list"):
# `semlb bench engine` per skin (0 = the stencil over fresh bins every step) in float and double, one profiled run
# (SEMLB_OPENCL_PROFILE=1: device ms per kernel), and the paper-size development run (scenes/epidermis_development.yaml,
# 435,661 cells, Day 0-5, 2,400 steps of 0.05 h, float) as a CSV row of results/gpu/development_1gpu.csv.
# Usage: bash scripts/gpu/neighbour_list.sh SEMLB OUT [bench|dev|all] [SKINS] [DEV_SKINS]
#   (defaults: all, SKINS "0 0.5 1 1.5 2", DEV_SKINS "1"; BENCH_CELLS: the bench's --cells, default 11000,435661;
#   PROFILE_SKIN: the skin of the profiled run, default 0.5; DOUBLE_SKINS: default "0 PROFILE_SKIN"; VARIANTS:
#   ';'-separated PRECISION|BUILD_OPTIONS (e.g. "float|-cl-denorms-are-zero"), each benched at skin 0 and PROFILE_SKIN; DEV_PROFILE_SKINS: the development
#   runs with SEMLB_OPENCL_PROFILE=1, whose kernels.csv is kept as dev_skinS.kernels.csv; DEV_VARIANTS: ';'-separated
#   extra flags of the development runs, each a row per skin with the flags in its `variant` column, e.g.
#   "--set backend.opencl-binned.newton=false;--set backend.opencl-binned.newton=true")
set -uo pipefail
S=$1; OUT=$2; what=${3:-all}; skins=${4:-"0 0.5 1 1.5 2"}; dev_skins=${5:-"1"}
here=$(cd "$(dirname "$0")/../.." && pwd)
export OCL_ICD_FILENAMES=${OCL_ICD_FILENAMES:-libnvidia-opencl.so.1}
mkdir -p "$OUT"
cells=${BENCH_CELLS:-11000,435661}
pskin=${PROFILE_SKIN:-0.5}; double_skins=${DOUBLE_SKINS:-"0 $pskin"}
bench() { "$S" bench engine --platform NVIDIA --backends opencl-binned --cells "$cells" --steps 200 "$@"; }
if [ "$what" = bench ] || [ "$what" = all ]; then
  for s in $skins; do bench --precision float --set backend.skin="$s"; done > "$OUT/bench_float.txt" 2>&1
  for s in $double_skins; do bench --precision double --set backend.skin="$s"; done > "$OUT/bench_double.txt" 2>&1
  SEMLB_OPENCL_PROFILE=1 bench --precision float --set backend.skin="$pskin" > "$OUT/bench_profile.txt" 2>&1
  IFS=';' read -ra variants <<< "${VARIANTS:-}"
  for v in "${variants[@]}"; do  # PRECISION|OPTIONS: kernel build options, timed (and profiled) at skin 0 and the profile skin
    echo "# ${v%%|*}: SEMLB_OPENCL_BUILD_OPTIONS=${v#*|}"
    for s in 0 "$pskin"; do
      SEMLB_OPENCL_BUILD_OPTIONS="${v#*|}" SEMLB_OPENCL_PROFILE=1 bench --precision "${v%%|*}" --set backend.skin="$s"
    done
  done > "$OUT/bench_variants.txt" 2>&1
fi
if [ "$what" = dev ] || [ "$what" = all ]; then
  machine=$(nvidia-smi --query-gpu=name --format=csv,noheader | head -1)
  [ -f "$OUT/development_1gpu.csv" ] ||
    echo "cells_start,cells_end,elements_end,steps,precision,loop_s,mechanics_s,machine,skin,start_s,end_s,wall_s,variant" > "$OUT/development_1gpu.csv"
  IFS=';' read -ra dev_variants <<< "${DEV_VARIANTS:-}"
  [ ${#dev_variants[@]} -gt 0 ] || dev_variants=("")
  for s in $dev_skins; do
  for k in "${!dev_variants[@]}"; do
    v=${dev_variants[$k]}; tag=$s; [ ${#dev_variants[@]} -eq 1 ] || tag=${s}_v$k
    run=$(mktemp -d)
    prof=; case " ${DEV_PROFILE_SKINS:-} " in *" $s "*) prof=1;; esac
    t0=$(date +%s.%N)
    SEMLB_OPENCL_PROFILE=$prof "$S" sim --scene "$here/scenes/epidermis_development.yaml" --out "$run" --steps 2400 --backend opencl-binned \
      --platform NVIDIA --precision float --quiet --set tissue.cells=435661 --set effects.growth.front.speed=24.8 \
      --set output.snapshot_every=0 --set output.checkpoint_every=0 --set backend.skin="$s" $v > "$OUT/dev_skin$tag.log" 2>&1 ||
      { echo "neighbour_list.sh: the development run at skin $s ${v:+($v) }failed: $(tail -1 "$OUT/dev_skin$tag.log")" >&2
        rm -rf "$run"; continue; }
    t1=$(date +%s.%N)
    cp "$run/run.csv" "$OUT/dev_skin$tag.run.csv"
    [ -f "$run/kernels.csv" ] && cp "$run/kernels.csv" "$OUT/dev_skin$tag.kernels.csv"
    # loop_s: the logged wall seconds summed (the time-stepping loop); mechanics_s: the mechanics column summed;
    # start_s, end_s: from semlb sim's last line (process start to the first step, the last step to its exit);
    # wall_s: the process as this script timed it, from its launch to its exit
    python3 - "$run/run.csv" "$s" "$machine" "$OUT/dev_skin$tag.log" "$t0" "$t1" "$v" >> "$OUT/development_1gpu.csv" <<'EOF'
import csv, re, sys
rows = list(csv.DictReader(open(sys.argv[1])))
loop = sum(float(r["wall_s"]) for r in rows)
mech = sum(float(r["mechanics_s"]) for r in rows)
last = open(sys.argv[4]).read().strip().splitlines()[-1]
m = re.search(r"\(start ([0-9.e+-]+) s, loop [0-9.e+-]+ s, end ([0-9.e+-]+) s\)", last)
if not m:
    sys.exit(f"neighbour_list.sh: {sys.argv[4]}: the last line gives no start and end: {last}")
wall = float(sys.argv[6]) - float(sys.argv[5])
print(f"435661,{rows[-1]['cells']},{rows[-1]['elements']},{rows[-1]['step']},float,{loop:.3f},{mech:.3f},{sys.argv[3]},"
      f"{sys.argv[2]},{float(m[1]):.3f},{float(m[2]):.3f},{wall:.3f},\"{sys.argv[7]}\"")
EOF
    rm -rf "$run"
  done
  done
fi
