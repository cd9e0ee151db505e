#!/usr/bin/env bash
# Regenerates the committed single-GPU results (`make gpu-results`) on a machine with one NVIDIA GPU, in stages that
# each fit one 10-minute device call: a stage that finished leaves OUT/.stages/STAGE.done (commit, date) and is
# skipped next time; a sweep cut off mid-stage resumes from its own .partial file. A call starts no new stage once
# BUDGET_S seconds (default 420) have passed and exits 3 saying what is left: run it again until it exits 0.
# Each stage writes a provenance.json (semlb commit, date, device) beside what it made (analysis/provenance.py).
# Usage: bash scripts/gpu/results.sh [OUT=results/gpu] [STAGE ...]   (default: every stage; `list` prints them)
#   YALLA=DIR: the folder holding a ya||a clone as DIR/yalla (the peer stage is skipped without it: no network there).
#   BUILD=DIR: where semlb is built (Release, no tests, no torch; default /tmp/semlb-gpu, as scripts/gpu_sweep.sh).
#   REPLAY_SET="--set KEY=VALUE ...": extra settings of the replay sweep (a quick run: --set ranks=2 --set seed=0).
#   JOBS=N (default 1): the workload stages still to do run N at once, taking turns on the device, as one step of the
#   call (on the H200, 2026-12-04, before turns worked for them: six recordings three at once in 410 s, 10-12
#   minutes one at a time).
#   CHECK=1: check every stage without a GPU (the sweeps' `--check`, the scripts present), write nothing, exit 0.
#   PACK=DIR: on the way out (finished, failed or out of budget), what this call made under OUT goes to DIR as tar
#   parts (scripts/gpu/pack_results.sh), for a machine whose files come back from one folder: unpacked beside OUT
#   here, the next call (on a fresh machine) resumes where this one stopped.
set -euo pipefail
here=$(cd "$(dirname "$0")/../.." && pwd)
OUT=${1:-$here/results/gpu}; shift || true
BUDGET_S=${BUDGET_S:-420}
JOBS=${JOBS:-1}
[[ $JOBS =~ ^[1-9][0-9]*$ ]] || { echo "gpu-results: JOBS='$JOBS' is not a whole number >= 1" >&2; exit 2; }
BUILD=${BUILD:-/tmp/semlb-gpu}
PY=${PYTHON:-/usr/bin/python3}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OCL_ICD_FILENAMES=${OCL_ICD_FILENAMES:-libnvidia-opencl.so.1}
# The GPU variants of the workload library (scripts/gpu/workload_library.sh), one stage each.
WORKLOADS="dev_v24.8_s1 dev_v24.8_s2 dev_v12.4_s1 dev_v6.2_s1 dev_v3.1_s1 dev_centre_v12.4_s1 epidermis_s1 epidermis_long_s2
epidermis_long_s3 epidermis_half_s1 epidermis_half3k_s2"
STAGES="single_device effects_cost accuracy_vs_time development force_step peer_yalla measured_time $(for w in $WORKLOADS; do
  printf 'workload:%s ' "$w"; done)controller_eval_engine"
if [ "${1:-}" = list ]; then printf '%s\n' $STAGES; exit 0; fi
want=${*:-$STAGES}
start=$(date +%s)
# SEMLB_COMMIT=HASH: the commit of a copy without .git (a device machine's copy of a clean checkout)
commit=${SEMLB_COMMIT:-$(git -C "$here" rev-parse HEAD 2>/dev/null || echo unknown)}
dirty=; [ -n "${SEMLB_COMMIT:-}" ] || dirty=$(git -C "$here" status --porcelain -- engine controllers cli 2>/dev/null | head -1)
[ -z "$dirty" ] || echo "gpu-results: the engine or controllers differ from $commit (uncommitted): provenance says so" >&2
S=$BUILD/cli/semlb
BUILD=$BUILD bash "$here/scripts/gpu/build.sh"
device=$(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -1 || echo "?")

provenance() {  # DIR [HOW [DEPENDS]]: DIR/provenance.json for what the stage made; DEPENDS=kernels for a result that
               # times the engine alone (a later controller change leaves it current: analysis/provenance.py)
  mkdir -p "$1"
  printf '{"semlb_commit": "%s", "date": "%s", "how": "%s", "device": "%s"%s%s}\n' "$commit" "$(date -u +%F)" \
    "${2:-scripts/gpu/results.sh}" "$device" "${3:+, \"depends\": \"$3\"}" \
    "${dirty:+, \"note\": \"uncommitted changes under engine/ or controllers/\"}" \
    > "$1/provenance.json.tmp"
  mv "$1/provenance.json.tmp" "$1/provenance.json"
}
sweep() {  # MANIFEST [--set ...]: scripts/gpu_sweep.sh (the paper profile, in its precision, on the NVIDIA platform),
           # one job at a time (they share one GPU), results under OUT/NAME/
  local m=$1; shift
  BUILD=$BUILD bash "$here/scripts/gpu_sweep.sh" "$here/experiments/$m.yaml" --results "$OUT" --quiet --jobs 1 \
    ${CHECK:+--check} "$@"
}
GPU_ONLY="--set backend=opencl-allpairs,opencl-binned"
check_stage() {  # STAGE: what CHECK=1 verifies without a GPU
  case $1 in
    single_device) sweep "$1" $GPU_ONLY;;
    effects_cost) sweep "$1";;
    accuracy_vs_time) sweep "$1" && sweep accuracy_pair_exp;;
    development) [ -f "$here/scripts/gpu/neighbour_list.sh" ];;
    force_step) [ -f "$here/scripts/gpu/force_step.sh" ];;
    peer_yalla) [ -f "$here/scripts/gpu/peer_yalla/run.sh" ] && [ -f "$here/analysis/peer_yalla.py" ];;
    measured_time) [ -f "$here/scripts/gpu/measured_all.sh" ] || echo "gpu-results: measured_time: no script yet (skipped)";;
    workload:*) grep -q "^  \"${1#workload:}|" "$here/scripts/gpu/workload_library.sh";;
    controller_eval_engine) "$S" sweep "$here/experiments/controller_eval_engine.yaml" --profile paper --results "$OUT/.replay" --check;;
    *) echo "gpu-results: unknown stage '$1'" >&2; return 2;;
  esac
}

# whether PY has what analysis/measured_time.py needs (the tables, the region check of a measured workload)
has_analysis=1; "$PY" -c 'import h5py, numpy, scipy' 2> /dev/null || has_analysis=
marker_of() { echo "$OUT/.stages/${1//:/_}.done"; }  # STAGE: the file that says it is done

workload_provenance() {  # NAME: the library file's record in OUT/workloads/provenance.json (with a note where the
                         # timed regions could not be checked here: workload_library.sh said so)
  $PY - "$OUT/workloads/provenance.json" "$1" "$commit" "$(date -u +%F)" "$device" "$has_analysis" <<'EOF'
import json, os, sys
path, name, commit, date, device, checked = sys.argv[1:]
doc = json.load(open(path)) if os.path.exists(path) else {"how": "scripts/gpu/results.sh workload:NAME", "files": {}}
rec = {"semlb_commit": commit, "date": date, "how": f"scripts/gpu/results.sh workload:{name}", "device": device}
if not checked:
    rec["note"] = "timed regions not checked where it was made: analysis/measured_time.py --check-regions before use"
for ext in (".h5", ".run.csv", ".scene.yaml"):
    doc.setdefault("files", {})[name + ext] = rec
json.dump(doc, open(path + ".tmp", "w"), indent=1)
os.replace(path + ".tmp", path)
EOF
}

workload_group() {  # STAGE...: the workload stages named, JOBS at once taking turns on the device (workload_library.sh);
                    # each file kept gets its record and its stage's marker, also when the call is stopped (INT,
                    # TERM) midway; the others are retried by the next call
  local names=() st rc=0
  for st in "$@"; do names+=("${st#workload:}"); done
  group_stamp=$(mktemp); group_t0=$(date +%s); group=("$@"); sleep 1
  trap 'mark_kept; exit 130' INT TERM
  MEASURED=1 JOBS=$JOBS bash "$here/scripts/gpu/workload_library.sh" "$S" "$OUT/workloads" "${names[@]}" || rc=$?
  trap - INT TERM
  mark_kept
  return "$rc"
}

mark_kept() {  # the record and marker of each file of the group that workload_library.sh kept since it began
  local st
  for st in "${group[@]}"; do
    if [ "$OUT/workloads/${st#workload:}.h5" -nt "$group_stamp" ] && [ ! -f "$(marker_of "$st")" ]; then
      workload_provenance "${st#workload:}"
      echo "$commit $(date -u +%FT%TZ) $(( $(date +%s) - group_t0 )) s (JOBS=$JOBS)" > "$(marker_of "$st")"
    fi
  done
  rm -f "$group_stamp"
}

run_stage() {  # STAGE: makes it; returns 0 when done, 77 when it cannot run here (and says why)
  case $1 in
    single_device)  # the device backends only: serial all-pairs at 2000 cells is 20 min of one host core
      sweep "$1" $GPU_ONLY && provenance "$OUT/$1" "scripts/gpu/results.sh $1 (semlb sweep experiments/$1.yaml --profile paper $GPU_ONLY)" kernels;;
    effects_cost)
      sweep "$1" && provenance "$OUT/$1" "scripts/gpu/results.sh $1 (semlb sweep experiments/$1.yaml --profile paper)" kernels;;
    accuracy_vs_time)  # and the pair force law's exp (experiments/accuracy_pair_exp.yaml: OUT/accuracy_vs_time/pair_exp.csv)
      sweep "$1" && sweep accuracy_pair_exp && provenance "$OUT/$1" "scripts/gpu/results.sh $1 (semlb sweep \
experiments/$1.yaml and experiments/accuracy_pair_exp.yaml --profile paper)" kernels;;
    development)  # Day 0-5 at the paper's size on one GPU (scripts/gpu/neighbour_list.sh dev): a fresh CSV row
      rm -rf "$OUT/development.tmp"
      # the scene's own settings (DEV_VARIANTS: ';'-separated flag sets, e.g. the half list, as measured in
      # docs/performance.md "Half list")
      DEV_VARIANTS=${DEV_VARIANTS:-} bash "$here/scripts/gpu/neighbour_list.sh" "$S" "$OUT/development.tmp" dev "0 0.5 1 1.5 2" "1"
      rm -rf "$OUT/development"; mv "$OUT/development.tmp" "$OUT/development"
      provenance "$OUT/development" "scripts/gpu/results.sh development (scripts/gpu/neighbour_list.sh dev)" kernels;;
    force_step)  # the defaults (full list; float's native, double's ranged exp) beside double's builtin exp and float's
      # sorted slots, two interleaved rounds (VARIANTS: force_step.sh's, e.g. the half list)
      rm -rf "$OUT/force_step.tmp"
      VARIANTS=${VARIANTS:-float:false:native double:false:ranged double:false:builtin float:false:native:sorted} \
        bash "$here/scripts/gpu/force_step.sh" "$S" "$OUT/force_step.tmp"
      rm -rf "$OUT/force_step"; mv "$OUT/force_step.tmp" "$OUT/force_step"
      provenance "$OUT/force_step" "scripts/gpu/results.sh force_step (scripts/gpu/force_step.sh)" kernels;;
    peer_yalla)  # semlb at the scene's settings (PEER_VARIANTS: ';'-separated flag sets), each round, against ya||a
      [ -n "${YALLA:-}" ] || { echo "gpu-results: peer_yalla needs YALLA=DIR holding a ya||a clone as DIR/yalla"; return 77; }
      mkdir -p "$OUT/peer_yalla"
      VARIANTS=${PEER_VARIANTS:-} bash "$here/scripts/gpu/peer_yalla/run.sh" "$S" "$here/scenes/mechanics.yaml" > "$OUT/peer_yalla/peer_yalla.log" 2>&1
      $PY "$here/analysis/peer_yalla.py" --machine "$device" "$OUT/peer_yalla/peer_yalla.log" > "$OUT/peer_yalla/peer_yalla.csv"
      provenance "$OUT/peer_yalla" "scripts/gpu/results.sh peer_yalla (scripts/gpu/peer_yalla/run.sh)" kernels;;
    measured_time)  # the measured end-to-end (docs/measured_time.md): runs under OUT/measured/runs, tables in OUT/measured
      [ -f "$here/scripts/gpu/measured_all.sh" ] || { echo "gpu-results: no scripts/gpu/measured_all.sh in this tree"; return 77; }
      notables=; [ -n "$has_analysis" ] || notables=1
      NO_TABLES=$notables bash "$here/scripts/gpu/measured_all.sh" "$S" "$OUT/measured/runs" "$OUT/measured"
      [ -z "$notables" ] || echo "gpu-results: measured_time: runs only ($PY lacks h5py, numpy or scipy): make the" \
        "tables where they are: TABLES_ONLY=1 bash scripts/gpu/measured_all.sh SEMLB OUT/measured/runs OUT/measured"
      provenance "$OUT/measured" "scripts/gpu/results.sh measured_time (scripts/gpu/measured_all.sh)";;
    workload:*)
      MEASURED=1 bash "$here/scripts/gpu/workload_library.sh" "$S" "$OUT/workloads" "${1#workload:}"  # version 3 or 4: measured seconds
      workload_provenance "${1#workload:}";;
    controller_eval_engine)  # the replays of the test workloads (CPU only), as workloads/controller_eval_engine_paper.*
      # shellcheck disable=SC2086
      "$S" sweep "$here/experiments/controller_eval_engine.yaml" --profile paper --results "$OUT/.replay" --quiet ${REPLAY_SET:-}
      mkdir -p "$OUT/workloads"
      cp "$OUT/.replay/controller_eval_engine/controller_eval_engine.csv" "$OUT/workloads/controller_eval_engine_paper.csv"
      $PY "$here/analysis/engine_eval.py" --csv "$OUT/workloads/controller_eval_engine_paper.csv" \
        --md "$OUT/workloads/controller_eval_engine_paper.md" > /dev/null
      $PY - "$OUT/workloads/provenance.json" "$commit" "$(date -u +%F)" <<'EOF'
import json, os, sys
path, commit, date = sys.argv[1:]
doc = json.load(open(path)) if os.path.exists(path) else {"files": {}}
rec = {"semlb_commit": commit, "date": date, "how": "scripts/gpu/results.sh controller_eval_engine (CPU replays)"}
for f in ("controller_eval_engine_paper.csv", "controller_eval_engine_paper.md"):
    doc.setdefault("files", {})[f] = rec
json.dump(doc, open(path + ".tmp", "w"), indent=1)
os.replace(path + ".tmp", path)
EOF
      ;;
    *) echo "gpu-results: unknown stage '$1' (bash scripts/gpu/results.sh OUT list)" >&2; return 2;;
  esac
}

if [ -n "${CHECK:-}" ]; then
  for st in $want; do check_stage "$st" > /dev/null || { echo "gpu-results: stage $st fails its check" >&2; exit 1; }; done
  echo "gpu-results: $(echo $want | wc -w) stage(s) checked"; exit 0
fi
mkdir -p "$OUT/.stages"
if [ -n "${PACK:-}" ]; then
  since=$(mktemp); sleep 1  # files made from the next second on are newer than it
  trap 'bash "$here/scripts/gpu/pack_results.sh" "$OUT" "$since" "$PACK" gpu-results; rm -f "$since"' EXIT
fi
# INT or TERM (timeout -s INT signals the whole process group): the running stage finishes its own way out first
# (a workload group marks what it kept), then this call exits, packing on the way (PACK)
trap 'echo "gpu-results: stopped by a signal; the next call resumes" >&2; exit 130' INT TERM
left=() grouped=" "
for st in $want; do
  marker=$(marker_of "$st")
  [ -f "$marker" ] && continue
  case $grouped in *" $st "*) continue;; esac  # tried in this call's group (below): the next call retries it
  if [ $(( $(date +%s) - start )) -ge "$BUDGET_S" ]; then left+=("$st"); continue; fi
  if [[ $st == workload:* ]] && [ "$JOBS" -gt 1 ]; then  # every workload stage still to do, at once
    group=(); for w in $want; do [[ $w == workload:* ]] && [ ! -f "$(marker_of "$w")" ] && group+=("$w"); done
    grouped+="${group[*]} "
    echo "gpu-results: ${group[*]} (JOBS=$JOBS at once, $(( $(date +%s) - start )) s into this call)"
    set +e; (set -e; workload_group "${group[@]}"); rc=$?; set -e
    [ "$rc" = 0 ] || { echo "gpu-results: workload group failed (exit $rc); the next call retries what it did not keep" >&2; exit "$rc"; }
    continue
  fi
  echo "gpu-results: $st ($(( $(date +%s) - start )) s into this call)"
  t0=$(date +%s)
  set +e; (set -e; run_stage "$st"); rc=$?; set -e  # in a subshell of its own: any failing command fails the stage
  if [ "$rc" = 0 ]; then
    echo "$commit $(date -u +%FT%TZ) $(( $(date +%s) - t0 )) s" > "$marker"
  elif [ "$rc" = 77 ]; then
    echo "gpu-results: $st skipped"
  else
    echo "gpu-results: $st failed (exit $rc); the next call retries it" >&2; exit "$rc"
  fi
done
if [ ${#left[@]} -gt 0 ]; then
  echo "gpu-results: ${#left[@]} stage(s) left (${left[*]}); run the same command again"
  exit 3
fi
echo "gpu-results: every stage done under $OUT (markers in $OUT/.stages; remove one to redo its stage)"
