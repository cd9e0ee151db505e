#!/usr/bin/env bash
# analysis/trace_model.py on hand-computed traces: R^2 around each event's mean and mean relative error per trace
# and pooled, modelled-timing traces listed but not pooled, a bad trace refused with FILE:LINE: field and no CSV,
# and report.py's tables from its CSV and a replay_score CSV. Usage: test_trace_model.sh REPO_ROOT WORK_DIR
set -euo pipefail
src=$1; work=$2
py=${PYTHON:-/usr/bin/python3}
rm -rf "$work"; mkdir -p "$work/r/load_balance/runs/a" "$work/r/gpu/x/runs/m"
# P = 2, S = 4, cut at 2. Event 0: predicted (2, 2), measured (1, 3): SS_res 2, SS_tot 2, rel. errors 1 and 1/3.
# Event 1: predicted (3, 1) = measured: SS_res 0, SS_tot 2. Trace: R^2 = 1 - 2/4 = 0.5, mean rel. error 1/3.
cat > "$work/r/load_balance/runs/a/trace.jsonl" <<'T'
{"event":0,"slices":4,"min_width":1,"boundaries":[2],"times":[1,3],"slice_work":[1,1,1,1]}
{"event":1,"slices":4,"min_width":1,"boundaries":[2],"times":[3,1],"slice_work":[2,1,0.5,0.5]}
T
printf 'name: s\ndecomposition:\n  policy: static  # timing: measured by default\n' > "$work/r/load_balance/runs/a/scene.yaml"
printf 'name: s\ndecomposition: {policy: static, timing: modelled}\n' > "$work/r/gpu/x/runs/m/scene.yaml"
cat > "$work/r/gpu/x/runs/m/trace.jsonl" <<'T'
{"event":0,"slices":4,"min_width":1,"boundaries":[1],"times":[1,3],"slice_work":[1,1,1,1]}
T
"$py" "$src/analysis/trace_model.py" --results "$work/r" --out "$work/r/trace_model/trace_model.csv" >/dev/null
csv=$work/r/trace_model/trace_model.csv
want="trace,timing,ranks,slices,events,points,r2,mean_rel_error,max_rel_error
gpu/x/runs/m,modelled,2,4,1,2,1,0,0
load_balance/runs/a,measured,2,4,2,4,0.5,0.333333,1
pooled_measured,measured,,,2,4,0.5,0.333333,1"
[ "$(cat "$csv")" = "$want" ] || { echo "FAIL: trace_model.csv"; cat "$csv"; exit 1; }
# report.py's tables from it and from a replay_score CSV.
mkdir -p "$work/r/replay_score"
printf 'policy,trace,ranks,slices,events,mean_imbalance,migration,mean_max_over_mean\nstatic,load_balance/runs/a,2,4,2,0.5,0,0.25\nreactive,load_balance/runs/a,2,4,2,0.25,3,0.125\n' \
  > "$work/r/replay_score/replay_score.csv"
"$py" "$src/analysis/report.py" --results "$work/r" >/dev/null
grep -qF '| load_balance/runs/a | fresh | measured | 2 | 2 | 4 | 0.500 | 33.3 | 100.0 |' "$work/r/tables/trace_model.md" || { cat "$work/r/tables/trace_model.md"; exit 1; }
grep -qF '| load_balance/runs/a | 2 | 2 | 50.00 / 0 | 25.00 / 3 |' "$work/r/tables/replay_score.md" || { cat "$work/r/tables/replay_score.md"; exit 1; }
# A line without slice_work: FILE:LINE: field, exit 2, the earlier CSV left as it was.
echo '{"event":2,"slices":4,"min_width":1,"boundaries":[2],"times":[3,1]}' >> "$work/r/load_balance/runs/a/trace.jsonl"
set +e
out=$("$py" "$src/analysis/trace_model.py" --results "$work/r" --out "$work/r/trace_model/trace_model.csv" 2>&1)
rc=$?
set -e
[ "$rc" = 2 ] || { echo "FAIL: exit $rc on a bad trace"; exit 1; }
grep -qF "load_balance/runs/a/trace.jsonl:3: field 'slice_work': missing" <<<"$out" || { echo "FAIL: $out"; exit 1; }
[ "$(cat "$csv")" = "$want" ] || { echo "FAIL: the CSV changed on bad input"; exit 1; }
# Committed traces (under cpu/, gpu/) and this run's are pooled apart, and replay_score averages them apart.
mkdir -p "$work/o/load_balance/runs/a" "$work/o/cpu/load_balance/runs/a"
head -2 "$work/r/load_balance/runs/a/trace.jsonl" > "$work/o/load_balance/runs/a/trace.jsonl"
cp "$work/r/load_balance/runs/a/scene.yaml" "$work/o/load_balance/runs/a/"
printf '%s\n' '{"event":0,"slices":4,"min_width":1,"boundaries":[2],"times":[2,2],"slice_work":[1,1,1,1]}' \
  > "$work/o/cpu/load_balance/runs/a/trace.jsonl"
cp "$work/r/load_balance/runs/a/scene.yaml" "$work/o/cpu/load_balance/runs/a/"
"$py" "$src/analysis/trace_model.py" --results "$work/o" --out "$work/o/trace_model/trace_model.csv" >/dev/null
grep -qx "pooled_measured,measured,,,2,4,0.5,0.333333,1" "$work/o/trace_model/trace_model.csv" || { cat "$work/o/trace_model/trace_model.csv"; exit 1; }
grep -q "^pooled_measured_committed,measured,,,1,2," "$work/o/trace_model/trace_model.csv" || { cat "$work/o/trace_model/trace_model.csv"; exit 1; }
mkdir -p "$work/o/replay_score"
printf 'policy,trace,ranks,slices,events,mean_imbalance,migration,mean_max_over_mean\nstatic,load_balance/runs/a,2,4,2,0.5,0,0.25\nstatic,cpu/load_balance/runs/a,2,4,1,0.1,0,0.05\n' \
  > "$work/o/replay_score/replay_score.csv"
"$py" "$src/analysis/report.py" --results "$work/o" >/dev/null
t="$work/o/tables/replay_score.md"
grep -qF "| **mean over these 1 traces** | | | **50.00 / 0.0** |" "$t" && grep -qF "| **mean over these 1 traces** | | | **10.00 / 0.0** |" "$t" \
  && grep -q "^## Traces committed, results/cpu" "$t" && grep -q "^## Traces fresh" "$t" || { echo "FAIL: origins mixed"; cat "$t"; exit 1; }
echo "analysis.trace_model: ok"
