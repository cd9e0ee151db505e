#!/usr/bin/env bash
# scripts/gpu/results.sh (`make gpu-results`) without a GPU: every stage passes its check (CHECK=1); a call past its
# time budget starts nothing and exits 3 naming what is left; the CPU-only stage (the replays) runs, leaves its marker
# and a provenance.json with this commit, and is skipped by the next call; a failing stage leaves no marker.
set -euo pipefail
src=$1; work=$2; semlb=$3
build=$(dirname "$(dirname "$semlb")")
rm -rf "$work"; mkdir -p "$work"
fail() { echo "FAIL: $*"; exit 1; }
CHECK=1 BUILD=$build bash "$src/scripts/gpu/results.sh" "$work/check" > "$work/check.log" 2>&1 || { cat "$work/check.log"; fail "CHECK=1"; }
grep -q "^gpu-results: $(bash "$src/scripts/gpu/results.sh" "$work/x" list | wc -l) stage(s) checked$" "$work/check.log" || fail "not every stage checked"
[ ! -e "$work/check/.stages" ] || fail "CHECK=1 wrote markers"
rc=0; BUILD=$build BUDGET_S=0 bash "$src/scripts/gpu/results.sh" "$work/out" controller_eval_engine > "$work/budget.log" 2>&1 || rc=$?
[ "$rc" = 3 ] && grep -q "1 stage(s) left (controller_eval_engine)" "$work/budget.log" || { cat "$work/budget.log"; fail "budget: exit $rc"; }
rc=0; REPLAY_SET="--set ranks=2 --set seed=0" BUILD=$build PYTHON=/nonexistent bash "$src/scripts/gpu/results.sh" "$work/out" controller_eval_engine > "$work/bad.log" 2>&1 || rc=$?
[ "$rc" != 0 ] && [ ! -e "$work/out/.stages/controller_eval_engine.done" ] || { cat "$work/bad.log"; fail "a failed stage left a marker"; }
REPLAY_SET="--set ranks=2 --set seed=0" BUILD=$build bash "$src/scripts/gpu/results.sh" "$work/out" controller_eval_engine > "$work/run.log" 2>&1 || { cat "$work/run.log"; fail "stage"; }
[ -s "$work/out/.stages/controller_eval_engine.done" ] || fail "no marker"
head=$(git -C "$src" rev-parse HEAD 2>/dev/null || echo unknown)
grep -q "\"semlb_commit\": \"$head\"" "$work/out/workloads/provenance.json" || { cat "$work/out/workloads/provenance.json"; fail "provenance"; }
[ "$(tail -n +2 "$work/out/workloads/controller_eval_engine_paper.csv" | wc -l)" -gt 0 ] || fail "no replay rows"
REPLAY_SET="--set ranks=2 --set seed=0" BUILD=$build bash "$src/scripts/gpu/results.sh" "$work/out" controller_eval_engine > "$work/again.log" 2>&1
! grep -q "^gpu-results: controller_eval_engine (" "$work/again.log" || fail "a done stage ran again"
echo "1 passed, 0 failed"
