#!/usr/bin/env bash
# analysis/report.py on fresh surrogate CSVs: the table holds every policy x P cell, the figure is a PNG, and the
# lazy oracle's frontier carries the target computed from reactive's rows.
set -euo pipefail
src=$1; work=$2; semlb=$3
rm -rf "$work"; mkdir -p "$work/controller_eval"
"$semlb" surrogate --policies static,reactive,oracle --ranks 2,4 --seeds 9000-9002 --events 20 --quiet \
  --out "$work/controller_eval"
"${PYTHON:-/usr/bin/python3}" "$src/analysis/report.py" --results "$work" --semlb "$semlb"
table="$work/tables/controller_eval.md"
for p in static reactive oracle; do grep -q "^| $p | [0-9.]* ± [0-9.]* | [0-9]* ± [0-9]* |" "$table" || { echo "missing row $p"; cat "$table"; exit 1; }; done
grep -q "P=4 imbalance" "$table"
head -c 8 "$work/figures/controller_eval.png" | od -An -c | grep -q "P   N   G"
# The lazy oracle's frontier, with the GRU target read from the controller_eval CSV beside it.
"$semlb" sweep "$src/experiments/foresight_frontier.yaml" --set ranks=2,4 --set seed=9000-9002 --set events=20 \
  --results "$work" --quiet
"${PYTHON:-/usr/bin/python3}" "$src/analysis/report.py" --results "$work" --semlb "$semlb" >/dev/null
frontier="$work/tables/foresight_frontier.md"
for p in 2 4; do for tau in 0.05 0.4; do
  grep -q "^| $p | $tau | [0-9.]* | [0-9.]* | [0-9.]* | [0-9.]* |$" "$frontier" || { echo "missing frontier row P=$p tau=$tau"; cat "$frontier"; exit 1; }
done; done
# The development scene's accuracy table (engine_observables) from the committed small-profile CSV: one summary row
# per run with its largest errors over the sample times (float: 2.66% of the work profile, at Day 5), a row per run
# and sample time, and a section in REPORT.md.
mkdir -p "$work/accuracy_vs_time"
cp "$src/results/cpu/accuracy_vs_time/development.csv" "$work/accuracy_vs_time/"
"${PYTHON:-/usr/bin/python3}" "$src/analysis/report.py" --results "$work" --semlb "$semlb" >/dev/null
dev="$work/tables/accuracy_development.md"
grep -q "^| double | 0.05 | 8.75 | [0-9.]* | 147 (115/24/8) | 0 | 0 | 0 | 0 |$" "$dev" || { echo "reference row"; cat "$dev"; exit 1; }
grep -q "^| float | 0.05 | 8.75 | [0-9.]* | 146 (114/24/8) | 0.68 | 0.00445 | 0.0227 | 2.66 |$" "$dev" || { echo "float row"; cat "$dev"; exit 1; }
test "$(grep -c '^| [0-9]* | \(double\|float\) |' "$dev")" -eq 24 || { echo "not 4 runs x 6 sample times"; cat "$dev"; exit 1; }
grep -qF "| cells Day 5 (basal/spinous/granular) |" "$dev" || { echo "cell types not from the binary"; cat "$dev"; exit 1; }
grep -qF "| h | precision | dt (h) | cutoff (um) | basal | spinous | granular | thickness (um) |" "$dev" || { echo "per-type columns"; cat "$dev"; exit 1; }
# The cell-type names come from the binary: without it the report stops with one line naming it (exit 2).
set +e; out=$("${PYTHON:-/usr/bin/python3}" "$src/analysis/report.py" --results "$work" --semlb "$work/none" 2>&1 >/dev/null); rc=$?; set -e
[ "$rc" = 2 ] && [ "$(printf '%s\n' "$out" | wc -l)" = 1 ] && [[ "$out" == "report: "*"no binary at '$work/none'"* ]] ||
  { echo "no binary: exit $rc: $out"; exit 1; }
grep -q "^## [0-9]*\. What accuracy costs on the developing epidermis, Day 0-5$" "$work/REPORT.md"
head -c 8 "$work/figures/accuracy_development.png" | od -An -c | grep -q "P   N   G"
grep -q "^!\[figures/accuracy_development.png\]" "$work/REPORT.md"
if "${PYTHON:-/usr/bin/python3}" "$src/analysis/report.py" --results "$work/empty" 2>/dev/null; then echo "empty results accepted"; exit 1; fi
echo "1 passed, 0 failed"
