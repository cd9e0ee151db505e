#!/usr/bin/env bash
# The library of engine workloads (results/gpu/workloads/README.md): each variant of the developing epidermis
# at the paper's size (435,661 cells, Day 0-5, 2,400 steps of 0.05 h, an event every 20 steps) and of the epidermis
# scene, run on ONE device with output.workload (a decomposition of one rank: W_s does not depend on the partition, so
# one run serves every rank count). Writes OUT/NAME.h5 (workload), OUT/NAME.run.csv and OUT/NAME.scene.yaml per variant.
# Variants named small_* are the CPU versions for `make experiments` (2,500-4,900 cells, cpu-binned, results/cpu/workloads/).
# Usage: bash scripts/gpu/workload_library.sh SEMLB OUT [VARIANT ...]   (default: every variant below but small_*)
# JOBS=N runs N variants at once (default 1). With MEASURED=1 they take turns on the device
# (decomposition.device_sharing: turns, one lock for the children of this script's shell, in batches of N started
# together): each run's device timers time its own kernels alone, while the host parts (the per-event download and
# counting) overlap. Each measured file is checked
# (analysis/measured_time.py --check-regions: no timed region far above the others) before it is kept; where PYTHON
# (default /usr/bin/python3) lacks h5py or numpy (a bare GPU machine) the check is skipped, saying so for each file:
# run it where they are before committing the files.
set -euo pipefail
if [ $# -lt 2 ]; then echo "usage: bash scripts/gpu/workload_library.sh SEMLB OUT [VARIANT ...]" >&2; exit 2; fi
S=$1; OUT=$2; shift 2
JOBS=${JOBS:-1}
[[ $JOBS =~ ^[1-9][0-9]*$ ]] || { echo "workload_library.sh: JOBS='$JOBS' is not a whole number >= 1" >&2; exit 2; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
here=$(cd "$(dirname "$0")/../.." && pwd)
dev="$here/scenes/epidermis_development.yaml"
epi="$here/scenes/epidermis.yaml"
common=(--quiet --set output.snapshot_every=0 --set output.checkpoint_every=0 --set output.workload=true)
# MEASURED=1: measured seconds per slice too (decomposition.timing: device, workload version 3, 4 with opencl-binned's list; docs/measured_time.md),
# with opencl-binned's neighbour list (backend.skin 0.5 unless the scene sets one): the fastest engine, the same tissue
read -ra timing <<< "${MEASURED:+--set decomposition.timing=device}"
[ -n "${MEASURED:-}" ] && [ "$JOBS" -gt 1 ] && timing+=(--set decomposition.device_sharing=turns)
gpu=(--backend opencl-binned --platform NVIDIA --precision float --set tissue.cells=435661)
cpu=(--backend cpu-binned --precision double)
# NAME|scene|steps|overrides (the sheet spans x 0 .. ~5,950 um; 24.8 um/h = half of it in 120 h, the shipped speed)
variants=(
  "dev_v24.8_s1|$dev|2400|--set effects.growth.front.speed=24.8"
  "dev_v24.8_s2|$dev|2400|--set effects.growth.front.speed=24.8 --seed 2"
  "dev_v12.4_s1|$dev|2400|--set effects.growth.front.speed=12.4"
  "dev_v6.2_s1|$dev|2400|--set effects.growth.front.speed=6.2"
  "dev_v3.1_s1|$dev|2400|--set effects.growth.front.speed=3.1"
  "dev_centre_v12.4_s1|$dev|2400|--set effects.growth.front.x0=2975 --set effects.growth.front.speed=12.4"
  "epidermis_s1|$epi|1000|--set decomposition.rebalance_every=50"
  "epidermis_long_s2|$epi|4000|--set decomposition.rebalance_every=50 --seed 2"
  "epidermis_long_s3|$epi|4000|--set decomposition.rebalance_every=50 --seed 3"
  # the paper's regime (static about 10-15% at P = 8): the epidermis scene with the left half of the sheet
  # proliferating (front fixed at x0 = 2,975 um, the middle), the right half quiescent; 750 steps of 0.01 h, an event
  # every 10 steps. Over 3,000 steps static reaches 51% at P = 8 (out of the regime): that longer run, seed 2, trains.
  "epidermis_half_s1|$epi|750|--set decomposition.rebalance_every=10 --set effects.growth.front.x0=2975 --set effects.growth.front.speed=0"
  "epidermis_half3k_s2|$epi|3000|--set decomposition.rebalance_every=50 --set effects.growth.front.x0=2975 --set effects.growth.front.speed=0 --seed 2"
  # the CPU versions (wide enough for 16 ranks of 13 slices): the development scene on a 50 x 50 sheet (~450 um) at
  # dt 0.1 h (the small profile's) with the front at half the sheet in 120 h (1.9 um/h), an event every 10 steps; the
  # epidermis scene on a 70 x 70 sheet as epidermis_s1
  "small_dev_s1|$dev|1200|--set tissue.cells=2500 --set time.dt=0.1 --set time.cell_update_every=5 --set decomposition.rebalance_every=10 --set effects.growth.front.speed=1.9"
  "small_epidermis_s1|$epi|1000|--set tissue.cells=4900 --set decomposition.rebalance_every=50"
)
want=("$@")
# Every `semlb sim` is started from this shell itself (never from a subshell), so that all of them are children of
# one process: under turns that is what puts them on one lock (the lock is named from the parent's pid,
# DeviceTurns::path_for), and what keeps a recording's timed launches clear of the others' device work.
# Under turns (MEASURED=1, JOBS > 1) they start in batches of JOBS and a batch waits for all of its recordings before
# the next starts: a semlb before fdb9146 removed the lock file when a recording ended (DeviceTurns' destructor), and
# one started after that locked a new file of the same name while the others still held the old one. Since fdb9146
# the file goes under the lock and a waiter re-checks it, so batches only keep older binaries correct.
(( BASH_VERSINFO[0] > 5 || (BASH_VERSINFO[0] == 5 && BASH_VERSINFO[1] >= 1) )) ||
  { echo "workload_library.sh: needs bash 5.1 or newer (wait -n -p), this is $BASH_VERSION" >&2; exit 2; }
declare -A run_of=() name_of=() t0_of=()
py=${PYTHON:-/usr/bin/python3}; can_check=
"$py" -c 'import h5py, numpy, scipy' 2> /dev/null && can_check=1  # analysis/measured_time.py's imports
launch() {  # NAME SCENE STEPS EXTRA: starts one variant's recording in the background (run_of/name_of/t0_of by pid)
  local name=$1 scene=$2 steps=$3 extra=$4 run size skin
  if [[ $name == small_* ]]; then size=("${cpu[@]}"); else size=("${gpu[@]}"); fi
  run=$(mktemp -d)
  skin=(); [ -n "${MEASURED:-}" ] && ! grep -q "skin:" "$scene" && skin=(--set backend.skin=0.5)
  # shellcheck disable=SC2086
  "$S" sim --scene "$scene" --out "$run" --steps "$steps" "${common[@]}" "${size[@]}" "${timing[@]}" "${skin[@]}" $extra &
  run_of[$!]=$run; name_of[$!]=$name; t0_of[$!]=$(date +%s)
}
keep() {  # PID STATUS: a finished recording's files into OUT (none when it failed or its timed regions overlapped)
  local pid=$1 rc=$2 run=${run_of[$1]} name=${name_of[$1]}
  local note=; [ "$rc" = 0 ] || note=", failed (exit $rc)"
  echo "$name: $(( $(date +%s) - t0_of[$pid] )) s wall$note"
  unset "name_of[$pid]" "t0_of[$pid]"
  local ok=1
  if [ "$rc" != 0 ]; then
    ok=
  elif [ -n "${MEASURED:-}" ] && [ -z "$can_check" ]; then
    echo "$name: timed regions not checked ($py lacks h5py, numpy or scipy): run analysis/measured_time.py" \
      "--check-regions $OUT/$name.h5 where they are"
  elif [ -n "${MEASURED:-}" ] && ! "$py" "$here/analysis/measured_time.py" --check-regions "$run/workload.h5"; then
    ok=  # a timed region overlapped other device work: not kept
  fi
  # the three files under temporary names first, the workload last: an interrupted copy leaves no OUT/NAME.h5
  if [ -n "$ok" ] && ! { cp "$run/run.csv" "$OUT/.$name.run.csv.tmp" && cp "$run/scene.yaml" "$OUT/.$name.scene.yaml.tmp" &&
    cp "$run/workload.h5" "$OUT/.$name.h5.tmp" && mv "$OUT/.$name.run.csv.tmp" "$OUT/$name.run.csv" &&
    mv "$OUT/.$name.scene.yaml.tmp" "$OUT/$name.scene.yaml" && mv "$OUT/.$name.h5.tmp" "$OUT/$name.h5"; }; then
    echo "$name: its files could not be copied into $OUT" >&2; ok=
  fi
  rm -rf "$run" "$OUT/.$name".*.tmp
  unset "run_of[$pid]"
  [ -n "$ok" ]
}
reap() {  # waits for one recording to end and keeps it; returns 1 when it was not kept
  local pid rc=0
  wait -n -p pid "${!run_of[@]}" || rc=$?
  keep "$pid" "$rc"
}
# the variants named, in the order named (default: every variant but small_*, in the order above)
order=()
if [ ${#want[@]} -eq 0 ]; then
  for v in "${variants[@]}"; do [[ $v == small_* ]] || order+=("$v"); done
else
  for name in "${want[@]}"; do
    found=
    for v in "${variants[@]}"; do [[ $v == "$name|"* ]] && order+=("$v") && found=1; done
    [ -n "$found" ] || { echo "workload_library.sh: unknown variant '$name'" >&2; exit 2; }
  done
fi
mkdir -p "$OUT"
failed=0
trap 'kill "${!run_of[@]}" 2> /dev/null || true; wait 2> /dev/null || true; rm -rf "${run_of[@]}" "$OUT"/.*.tmp; exit 130' INT TERM
batches=; [ -n "${MEASURED:-}" ] && [ "$JOBS" -gt 1 ] && batches=1
for v in "${order[@]}"; do
  IFS='|' read -r name scene steps extra <<<"$v"
  if [ "${#run_of[@]}" -ge "$JOBS" ]; then
    reap || failed=1
    if [ -n "$batches" ]; then while [ "${#run_of[@]}" -gt 0 ]; do reap || failed=1; done; fi
  fi
  launch "$name" "$scene" "$steps" "$extra"
done
while [ "${#run_of[@]}" -gt 0 ]; do reap || failed=1; done
exit "$failed"
