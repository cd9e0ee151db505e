#!/usr/bin/env bash
# analysis/report.py on a fresh surrogate CSV: the table holds every policy x P cell, the figure is a PNG.
set -euo pipefail
src=$1; work=$2; semlb=$3
rm -rf "$work"; mkdir -p "$work/controller_eval"
"$semlb" surrogate --policies static,reactive,oracle --ranks 2,4 --seeds 9000-9002 --events 20 --quiet \
  --out "$work/controller_eval"
"${PYTHON:-/usr/bin/python3}" "$src/analysis/report.py" --results "$work"
table="$work/tables/controller_eval.md"
for p in static reactive oracle; do grep -q "^| $p | [0-9.]* ± [0-9.]* | [0-9]* ± [0-9]* |" "$table" || { echo "missing row $p"; cat "$table"; exit 1; }; done
grep -q "P=4 imbalance" "$table"
head -c 8 "$work/figures/controller_eval.png" | od -An -c | grep -q "P   N   G"
if "${PYTHON:-/usr/bin/python3}" "$src/analysis/report.py" --results "$work/empty" 2>/dev/null; then echo "empty results accepted"; exit 1; fi
echo "1 passed, 0 failed"
