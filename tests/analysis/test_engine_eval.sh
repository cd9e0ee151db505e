#!/usr/bin/env bash
# analysis/engine_eval.py on a hand-made CSV: the three targets of the shipped GRU and the two of the learned controller
# as the issues define them, and bad
# input (a short row, a non-number, a NaN, a missing file) refused with exit 2 naming the file and line.
# Usage: test_engine_eval.sh REPO_ROOT WORK_DIR
set -euo pipefail
src=$1; work=$2
py=${PYTHON:-/usr/bin/python3}
rm -rf "$work"; mkdir -p "$work"
csv=$work/e.csv
{
  echo "workload,policy,ranks,seed,mean_imbalance,migration,loop_s,reactive.tau,reactive.alpha,foresight.lambda,gru.weights,learned_repartition.weights"
  for s in 0 1; do
    echo "w.h5,static,2,$s,0.50,0,2.0,,,,,"
    echo "w.h5,reactive,2,$s,0.06,100,1.1,0.02,0.5,,,"
    echo "w.h5,reactive,2,$s,0.30,10,1.5,0.3,0.5,,,"
    echo "w.h5,foresight,2,$s,0.01,100,1.0,,,0,,"
    echo "w.h5,gru,2,$s,0.02,104,1.05,,,,,"
    echo "w.h5,gru,2,$s,0.04,50,1.05,,,,other.h5,"
    # the learned controller within 1% of the best other (the GRU, 1.05 s), with less imbalance and migration than reactive
    echo "w.h5,learned_repartition,2,$s,0.03,60,1.055,,,,,"
    echo "w.h5,learned_repartition,2,$s,0.00,0,0.5,,,,,other.h5"
    # at P = 4 the GRU moves 10% more than reactive and a reactive setting dominates it; the learned controller is
    # 14% slower than the best other and more imbalanced than reactive
    echo "w.h5,static,4,$s,0.50,0,2.0,,,,,"
    echo "w.h5,reactive,4,$s,0.10,100,1.1,0.02,0.5,,,"
    echo "w.h5,reactive,4,$s,0.05,100,1.1,0.1,0.5,,,"
    echo "w.h5,foresight,4,$s,0.02,90,1.0,,,0,,"
    echo "w.h5,gru,4,$s,0.08,110,1.05,,,,,"
    echo "w.h5,learned_repartition,4,$s,0.12,95,1.2,,,,,"
  done
} > "$csv"
out=$("$py" "$src/analysis/engine_eval.py" --csv "$csv")
expect() { grep -qF -- "$1" <<<"$out" || { echo "missing: $1"; echo "$out"; exit 1; }; }
expect "target front: holds"
expect "target reactive: holds (2.00% / 104 vs reactive 6.00% / 100)"
expect "target gap: holds (closes 0.80 of the gap"
expect "target front: misses (1 deployable settings dominate it"
expect "target reactive: misses (8.00% / 110 vs reactive 10.00% / 100)"
expect "target gap: misses (closes 0.25 of the gap"
expect "target learned loop: holds (1.055 s, +0.48% against the best other (gru default 1.050 s); static 2.000 s)"
expect "target learned reactive: holds (3.00% / 60 vs reactive 6.00% / 100)"
expect "target learned loop: misses (1.200 s, +14.29% against the best other (gru default 1.050 s); static 2.000 s)"
expect "target learned reactive: misses (12.00% / 95 vs reactive 10.00% / 100)"
bad() {  # FILE MESSAGE
  local rc=0 err
  err=$("$py" "$src/analysis/engine_eval.py" --csv "$1" 2>&1 >/dev/null) || rc=$?
  [ "$rc" = 2 ] || { echo "exit $rc for $1: $err"; exit 1; }
  grep -qF -- "$2" <<<"$err" || { echo "expected '$2', got: $err"; exit 1; }
  [ "$(wc -l <<<"$err")" = 1 ] || { echo "not one line: $err"; exit 1; }
}
sed '3s/.*/w.h5,static/' "$csv" > "$work/short.csv"; bad "$work/short.csv" "short.csv:3: field 'ranks': missing"
sed '3s/0.06/abc/' "$csv" > "$work/text.csv"; bad "$work/text.csv" "text.csv:3: field 'mean_imbalance': 'abc' is not a number"
sed '3s/0.06/nan/' "$csv" > "$work/nan.csv"; bad "$work/nan.csv" "nan.csv:3: field 'mean_imbalance': 'nan' is not finite"
bad "$work/absent.csv" "--csv $work/absent.csv: No such file or directory"
echo "engine_eval: ok"
