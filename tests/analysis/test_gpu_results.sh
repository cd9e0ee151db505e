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
# PACK=DIR: what a call made leaves as tar parts that unpack beside OUT to the same files; a call that made nothing
# packs nothing; more parts than MAX_PARTS leave none and fail
rm -rf "$work/out/.stages/controller_eval_engine.done" "$work/pack"
echo old > "$work/out/old.txt"  # made before the call: not packed
PACK=$work/pack REPLAY_SET="--set ranks=2 --set seed=0" BUILD=$build bash "$src/scripts/gpu/results.sh" "$work/out" \
  controller_eval_engine > "$work/pack.log" 2>&1 || { cat "$work/pack.log"; fail "pack run"; }
ls "$work/pack"/gpu-results.tgz.* > /dev/null || { cat "$work/pack.log"; fail "no parts"; }
mkdir -p "$work/unpacked" && cat "$work/pack"/gpu-results.tgz.* | tar xz -C "$work/unpacked"
for f in workloads/controller_eval_engine_paper.csv workloads/provenance.json .stages/controller_eval_engine.done; do
  cmp "$work/out/$f" "$work/unpacked/out/$f" || fail "packed $f differs"
done
[ ! -e "$work/unpacked/out/old.txt" ] || fail "packed a file older than the call"
since=$(mktemp); sleep 1
bash "$src/scripts/gpu/pack_results.sh" "$work/out" "$since" "$work/pack2" | grep -q "nothing under" || fail "packed old files"
touch "$work/out/workloads/controller_eval_engine_paper.csv"
head -c 3000000 /dev/urandom > "$work/out/noise.bin"
mkdir -p "$work/out/runs/r1" "$work/out/development.tmp"  # a run stopped mid-write, a stage's unfinished folder
echo partial > "$work/out/runs/r1/final.h5.tmp"; echo partial > "$work/out/development.tmp/x.csv"
rc=0; PART_MB=1 MAX_PARTS=2 bash "$src/scripts/gpu/pack_results.sh" "$work/out" "$since" "$work/pack3" 2> "$work/pack3.err" || rc=$?
# too many parts: the largest file is left out and named, what fits comes back, exit 1
[ "$rc" = 1 ] && grep -q "left out out/noise.bin" "$work/pack3.err" && ls "$work/pack3"/results.tgz.* > /dev/null \
  || { cat "$work/pack3.err"; fail "too many parts: exit $rc"; }
mkdir -p "$work/unpacked3" && cat "$work/pack3"/results.tgz.* | tar xz -C "$work/unpacked3"
cmp "$work/out/workloads/controller_eval_engine_paper.csv" "$work/unpacked3/out/workloads/controller_eval_engine_paper.csv" \
  || fail "what fits was not packed"
[ ! -e "$work/unpacked3/out/noise.bin" ] && [ ! -e "$work/unpacked3/out/runs/r1/final.h5.tmp" ] &&
  [ ! -e "$work/unpacked3/out/development.tmp" ] || fail "packed the left-out file or a partial write"
rm -rf "$since" "$work/out/noise.bin" "$work/out/runs" "$work/out/development.tmp"
# JOBS=3: the workload stages still to do run at once (one workload_library.sh call); each file kept gets its record
# and marker, a failed one neither (retried by the next call, which skips the done ones); a stand-in semlb (no GPU)
# writes an empty HDF5 file (no timed regions to check) and fails with --seed 2
mkdir -p "$work/fake/cli" && cp "$src/tests/analysis/stand_in_semlb.sh" "$work/fake/cli/semlb"
export FAKE_DIR=$work/fake/cli
rc=0; JOBS=3 BUILD=$work/fake bash "$src/scripts/gpu/results.sh" "$work/wl" workload:epidermis_s1 workload:epidermis_half_s1 \
  workload:dev_v24.8_s2 > "$work/wl.log" 2>&1 || rc=$?
[ "$rc" = 1 ] || { cat "$work/wl.log"; fail "a failed recording in the group: exit $rc"; }
[ "$(cut -d' ' -f1 "$work/fake/cli/calls" | sort -u | wc -l)" = 1 ] && [ "$(wc -l < "$work/fake/cli/calls")" = 3 ] \
  || { cat "$work/fake/cli/calls"; fail "not one workload_library.sh call for the three"; }
for n in epidermis_s1 epidermis_half_s1; do
  [ -s "$work/wl/.stages/workload_$n.done" ] && grep -q "\"$n.h5\"" "$work/wl/workloads/provenance.json" || fail "$n: no marker or record"
done
[ ! -e "$work/wl/.stages/workload_dev_v24.8_s2.done" ] && ! grep -q dev_v24.8_s2 "$work/wl/workloads/provenance.json" \
  || fail "the failed recording has a marker or a record"
rc=0; JOBS=3 BUILD=$work/fake bash "$src/scripts/gpu/results.sh" "$work/wl" workload:epidermis_s1 workload:epidermis_half_s1 \
  workload:dev_v24.8_s2 > "$work/wl2.log" 2>&1 || rc=$?
[ "$rc" = 1 ] && [ "$(wc -l < "$work/fake/cli/calls")" = 4 ] && grep -q "dev_v24.8_s2 (JOBS=3" "$work/wl2.log" \
  || { cat "$work/wl2.log"; fail "the next call did not retry only the failed one (exit $rc)"; }
# a call stopped midway (TERM to its process group, as timeout sends; a background job ignores INT) still marks what
# was kept: the stand-in's dev_v24.8_s1 ends at once, epidermis_s1 takes 30 s and is stopped
rm -rf "$work/wl3"; rc=0
FAKE_SLOW="*epidermis.yaml*" FAKE_SLOW_S=30 JOBS=2 BUILD=$work/fake setsid bash "$src/scripts/gpu/results.sh" "$work/wl3" workload:dev_v24.8_s1 \
  workload:epidermis_s1 > "$work/wl3.log" 2>&1 &
pid=$!; sleep 4; kill -TERM -- "-$pid"; wait "$pid" || rc=$?
[ "$rc" != 0 ] && [ -s "$work/wl3/.stages/workload_dev_v24.8_s1.done" ] && [ ! -e "$work/wl3/.stages/workload_epidermis_s1.done" ] \
  && grep -q '"dev_v24.8_s1.h5"' "$work/wl3/workloads/provenance.json" || { cat "$work/wl3.log"; fail "stopped midway: exit $rc, markers wrong"; }
rc=0; JOBS=x bash "$src/scripts/gpu/results.sh" "$work/wl" list > /dev/null 2>&1 || rc=$?
[ "$rc" = 2 ] || fail "JOBS=x: exit $rc"
echo "1 passed, 0 failed"
