#!/usr/bin/env bash
# Trains several variants of the GRU recipe in parallel (one `semlb train` per variant, two cores each)
# and scores each on VALIDATION seeds against reactive, per rank count.
# Usage: [EVAL_EVENTS=100] scripts/train_variants.sh SEMLB OUTDIR STEPS "name:key=v,key=v" ["name:..." ...]
# Each line: imbalance difference to reactive, migration ratio, and the GRU's last/first-quarter imbalance.
set -euo pipefail
semlb=$1; out=$2; steps=$3; shift 3
eval_events=${EVAL_EVENTS:-100}
mkdir -p "$out"
for spec in "$@"; do
  name=${spec%%:*}; sets=()
  IFS=',' read -ra kvs <<< "${spec#*:}"
  for kv in "${kvs[@]}"; do [ -n "$kv" ] && sets+=(--set "$kv"); done
  ( "$semlb" train --quiet --config surrogate/train/default.yaml --steps "$steps" "${sets[@]}" --out "$out/$name.h5" \
      > "$out/$name.train.log" 2>&1 &&
    "$semlb" surrogate --quiet --policies reactive,gru --weights "$out/$name.h5" --ranks 2,4,8,16 --seeds 8000-8039 \
      --events "$eval_events" --no-timing --out "$out/$name" > /dev/null 2>&1 ) &
done
wait
for spec in "$@"; do
  name=${spec%%:*}
  tail -1 "$out/$name.train.log"
  awk -F, -v n="$name" 'NR > 1 { k = $1 "," $2; imb[k] += $7; mig[k] += $8; fq[k] += $10; lq[k] += $11; cnt[k]++ }
    END { for (P = 2; P <= 16; P *= 2) { r = "reactive," P; g = "gru," P;
      printf "%-10s P=%-2d reactive %6.3f%% %7.1f | gru %6.3f%% %7.1f | d_imb %+6.3f pp  mig ratio %5.1fx  quarters %4.2f\n", n, P,
        100*imb[r]/cnt[r], mig[r]/cnt[r], 100*imb[g]/cnt[g], mig[g]/cnt[g], 100*(imb[g]/cnt[g]-imb[r]/cnt[r]),
        (mig[r]/cnt[r]) / (mig[g]/cnt[g] + 1e-9), lq[g] / (fq[g] + 1e-12) } }' "$out/$name/controller_eval.csv"
done
