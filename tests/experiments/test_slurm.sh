#!/usr/bin/env bash
# `semlb sweep --launcher slurm` against a real single-node Slurm started here (tests/experiments/slurm_cluster.sh):
# a surrogate (12 jobs, 2 per array task: MaxArraySize is 10) and a 2-rank engine manifest give the local run's
# CSV byte for byte; a task cancelled with scancel is resubmitted (alone) by a rerun; a failing job is reported
# with its array index, job id and log, its task's other job is kept, and a rerun completes it. Every Slurm command runs under `timeout`, so a broken Slurm fails the test instead of hanging.
# Usage: test_slurm.sh SOURCE_DIR WORK_DIR SEMLB
set -euo pipefail
src=$1; work=$2; semlb=$3
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
source "$src/tests/experiments/slurm_cluster.sh"
rm -rf "$work"; mkdir -p "$work"
trap slurm_stop EXIT
slurm_start "$work/cluster"

fail() { echo "FAIL: $*"; exit 1; }
cat >"$work/surrogate.yaml" <<YAML
name: slurm_surrogate
runner: surrogate
output: s/s.csv
axes:
  policy: [static, reactive, holt]
  ranks: [2, 4]
  seed: "9000-9001"
set:
  events: 20
YAML
cat >"$work/engine.yaml" <<YAML
name: slurm_engine
runner: mpi_intervals
output: e/e.csv
axes:
  policy: [static, reactive]
set:
  scene: $src/scenes/epidermis.yaml
  ranks: 2
  cells: 100
  steps: 40
  rebalance_every: 10
  timing: modelled
YAML
sweep() { timeout 180 "$semlb" sweep "$@" --no-timing; }
same() {  # RESULTS_A RESULTS_B OUTPUT: the CSVs and the manifest copies are byte-identical, no leftovers
  cmp "$1/$3.csv" "$2/$3.csv" || fail "$1/$3.csv differs from the local run's"
  cmp "$1/$3.manifest.yaml" "$2/$3.manifest.yaml" || fail "$1/$3.manifest.yaml differs"
  [[ ! -e $1/$3.csv.partial && ! -e $1/$3.csv.slurm ]] || fail "$1: .partial or .slurm left behind"
}

# 1. Surrogate and engine (2 ranks through srun --mpi=pmix) manifests: the local run's CSV.
for m in surrogate engine; do sweep "$work/$m.yaml" --quiet --results "$work/local" 2>/dev/null; done
sweep "$work/surrogate.yaml" --launcher slurm --results "$work/slurm" 2>"$work/surrogate.log" || { cat "$work/surrogate.log"; fail "surrogate sweep"; }
grep -q "12/12 jobs done, 0 running, 0 pending, 0 failed" "$work/surrogate.log" || { cat "$work/surrogate.log"; fail "no final progress line"; }
same "$work/slurm" "$work/local" s/s
sweep "$work/engine.yaml" --launcher slurm --quiet --results "$work/slurm" 2>"$work/engine.log" || { cat "$work/engine.log"; fail "engine sweep"; }
same "$work/slurm" "$work/local" e/e
[[ $(grep -c "^static,.*,1,0," "$work/slurm/e/e.csv") -gt 0 ]] || fail "no rank-1 rows in the engine CSV"

# 2. A task cancelled with scancel: the --no-wait submission returns at once; the rerun resubmits only its jobs.
out=$(sweep "$work/surrogate.yaml" --launcher slurm --quiet --no-wait --array-throttle 1 --results "$work/cancel" 2>&1)
job=$(sed -n 's/^submitted Slurm job \([0-9]*\): 12 of 12 jobs as array 0-5 (2 per task).*/\1/p' <<<"$out")
[[ -n $job ]] || fail "no submission line: $out"
[[ ! -e $work/cancel/s/s.csv ]] || fail "--no-wait wrote OUTPUT"
timeout 30 scancel "${job}_5"  # jobs 10 and 11, still pending behind the throttle
for _ in $(seq 1 50); do timeout 30 squeue -h -r -j "$job" -o %K | grep -qx 5 || break; sleep 0.2; done
! timeout 30 squeue -h -r -j "$job" -o %K | grep -qx 5 || fail "scancel left task 5 queued"
out=$(sweep "$work/surrogate.yaml" --launcher slurm --results "$work/cancel" 2>&1) || fail "rerun after scancel: $out"
grep -q "^submitted Slurm job [0-9]*: 2 of 12 jobs as array 0-1 (1 per task)" <<<"$out" || fail "the rerun did not resubmit exactly jobs 10 and 11: $out"
[[ $(grep -c "^submitted" <<<"$out") -eq 1 ]] || fail "more than one submission: $out"
same "$work/cancel" "$work/local" s/s

# 3. A failing job (3, in task 1 with job 2): reported with its array index, Slurm job id and log (which holds the
# error); job 2 is kept; the rerun resubmits job 3 alone and the CSV is complete, without duplicates.
out=$(SEMLB_SWEEP_FAIL_JOB=3 sweep "$work/surrogate.yaml" --launcher slurm --quiet --results "$work/fail" 2>&1) && fail "a failing task passed: $out"
line=$(grep "^  job 3: array index 1 of Slurm job [0-9]* ([0-9]*_1), log " <<<"$out") || fail "failure not reported: $out"
log=$(sed -n 's/.*, log \(.*\.out\): .*/\1/p' <<<"$line")
[[ -f $log ]] && grep -q "^job 3 failed: failure injected by SEMLB_SWEEP_FAIL_JOB" "$log" || fail "log $log lacks the error: $line"
grep -q "job 3 failed: failure injected" <<<"$line" || fail "the report does not quote the log: $line"
grep -q "1 of 12 jobs failed" <<<"$out" || fail "failure count: $out"
[[ $(($(wc -l <"$work/fail/s/s.csv.partial"))) -eq 12 ]] || fail "the 11 finished rows are not in .partial"
out=$(sweep "$work/surrogate.yaml" --launcher slurm --results "$work/fail" 2>&1) || fail "rerun after a failure: $out"
grep -q "^submitted Slurm job [0-9]*: 1 of 12 jobs as array 0-0 (1 per task)" <<<"$out" || fail "the rerun did not resubmit exactly job 3: $out"
same "$work/fail" "$work/local" s/s

# 4. --dry-run prints the batch script (the throttle, the engine's 2 ranks, GPUs per rank) and submits nothing.
out=$(sweep "$work/engine.yaml" --launcher slurm --dry-run --array-throttle 2 --gpus-per-rank 1 --time 00:10:00 \
  --sbatch-arg=--gres=gpu:2 --results "$work/dry" 2>&1)
for l in "#SBATCH --array=0-1%2" "#SBATCH --ntasks=2" "  0 1" "#SBATCH --gpus-per-task=1" "#SBATCH --time=00:10:00" "#SBATCH --gres=gpu:2"; do
  grep -qxF -- "$l" <<<"$out" || fail "dry run lacks '$l': $out"
done
[[ ! -e $work/dry ]] || fail "--dry-run wrote files"
echo "4 passed, 0 failed"
