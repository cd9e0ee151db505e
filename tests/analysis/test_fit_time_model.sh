#!/usr/bin/env bash
# analysis/fit_time_model.py on hand-made 2-rank runs whose rank times follow the model exactly: T_r = s_r (W_r + g B_r)
# with g = 0.8 and s_1 / s_0 = 1.05 (one run) recovers both and the migration slope; with three such runs the
# leave-one-out errors are ~0 and the work-only model's are not; a bad trace is refused (exit 2), no CSV.
# Usage: test_fit_time_model.sh REPO_ROOT WORK_DIR
set -euo pipefail
src=$1; work=$2
py=${PYTHON:-/usr/bin/python3}
rm -rf "$work"; mkdir -p "$work"
"$py" - "$work" <<'PY'
import json, os, random, sys
work = sys.argv[1]
g, ratio, slope = 0.8, 1.05, 0.002
for run in range(3):
    d = os.path.join(work, f"run{run}")
    os.makedirs(d)
    rnd = random.Random(run)
    lines, rows = [], ["step,rank,compute_s,exchange_s,migrate_s,imbalance,moved_slices"]
    for e in range(15):
        S, band = 40, 4
        work_ = [rnd.uniform(0.5, 3.0) for _ in range(S)]
        b = rnd.randint(12, 28)
        W = [sum(work_[:b]), sum(work_[b:])]
        B = [sum(work_[b:b + band]), sum(work_[b - band:b])]
        t = [1.0 * (W[0] + g * B[0]), ratio * (W[1] + g * B[1])]
        scale = sum(t) / sum(work_)  # the engine scales W_s to the times
        lines.append(json.dumps({"event": e, "slices": S, "min_width": 1, "boundaries": [b], "times": t,
                                 "slice_work": [x * scale for x in work_]}))
        moved = rnd.randint(0, 20)
        for r in range(2):
            rows.append(f"{50 * (e + 1)},{r},{t[r]},0.1,{0.01 + slope * moved if r == 0 else 0.005},0.1,{moved}")
    open(os.path.join(d, "trace.jsonl"), "w").write("\n".join(lines) + "\n")
    open(os.path.join(d, "rank_times.csv"), "w").write("\n".join(rows) + "\n")
PY
"$py" "$src/analysis/fit_time_model.py" --runs "$work/run0" --out "$work/one.csv" --band 4 >/dev/null
"$py" - "$work/one.csv" <<'PY'
import csv, sys
r = next(csv.DictReader(open(sys.argv[1])))
assert abs(float(r["ghost_weight"]) - 0.8) <= 0.005, r
assert abs(float(r["speed_ratio"]) - 1.05) < 1e-6, r
assert float(r["jitter"]) < 1e-6, r
assert abs(float(r["migrate_s_per_slice"]) - 0.002) < 1e-9, r
PY
"$py" "$src/analysis/fit_time_model.py" --runs "$work/run0" "$work/run1" "$work/run2" --out "$work/three.csv" >/dev/null
"$py" - "$work/three.csv" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert rows[0]["run"] == "all" and len(rows) == 4, rows
for r in rows[1:]:
    assert float(r["mean_rel_error"]) < 1e-3, r
    assert float(r["mean_rel_error_work_only"]) > 0.01, r
PY
mkdir -p "$work/bad"; echo '{"event":0,"slices":4}' > "$work/bad/trace.jsonl"; : > "$work/bad/rank_times.csv"
if "$py" "$src/analysis/fit_time_model.py" --runs "$work/bad" --out "$work/bad.csv" 2> "$work/err"; then exit 1; fi
grep -q "trace.jsonl:1: field 'boundaries': missing" "$work/err"
test ! -e "$work/bad.csv"
echo "fit_time_model: ok"
