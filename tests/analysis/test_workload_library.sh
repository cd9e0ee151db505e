#!/usr/bin/env bash
# scripts/gpu/workload_library.sh with a stand-in for semlb (no GPU): recordings run JOBS at once and are all children
# of one process (what puts them on one device-turns lock, named from the parent's pid), with device timers and turns
# under MEASURED=1; a failed recording or one that fails --check-regions is not kept, the others are, and the exit
# status says so; where PYTHON cannot check (no h5py), files are kept with a line saying they were not checked; no
# temporary run folder is left behind.
set -euo pipefail
src=$1; work=$2
rm -rf "$work"; mkdir -p "$work/tmp"
fail() { echo "FAIL: $*"; exit 1; }
fake=$src/tests/analysis/stand_in_semlb.sh  # dev_v24.8_s1 runs 3 s (FAKE_SLOW), the others 1
# stand-in for PYTHON: has h5py and numpy (`-c` succeeds); --check-regions exits FAKE_CHECK (0: the file passes)
printf '#!/usr/bin/env bash\n[ "$1" = -c ] && exit 0\necho "check-regions $*" >> "$FAKE_DIR/checks"; exit "${FAKE_CHECK:-0}"\n' > "$work/py"
chmod +x "$work/py"
export FAKE_DIR=$work TMPDIR=$work/tmp FAKE_S=1 FAKE_SLOW="*speed=24.8 "
MEASURED=1 JOBS=3 PYTHON=$work/py bash "$src/scripts/gpu/workload_library.sh" "$fake" "$work/out" \
  dev_v24.8_s1 dev_v12.4_s1 dev_v6.2_s1 epidermis_s1 > "$work/ok.log" 2>&1 || { cat "$work/ok.log"; fail "four recordings"; }
[ "$(wc -l < "$work/calls")" = 4 ] || fail "not four calls"
[ "$(cut -d' ' -f1 "$work/calls" | sort -u | wc -l)" = 1 ] || { cat "$work/calls"; fail "recordings with different parents (different turn locks)"; }
[ "$(cut -d' ' -f2 "$work/calls" | sort -n | tail -1)" -ge 2 ] || { cat "$work/calls"; fail "JOBS=3 ran one at a time"; }
# under turns the fourth starts only when the first three have all ended (a batch): dev_v24.8_s1 runs 3 s, the others 1
[ "$(tail -1 "$work/calls" | cut -d' ' -f2)" = 1 ] || { cat "$work/calls"; fail "the fourth started while a batch ran"; }
[ "$(grep -c 'decomposition.timing=device --set decomposition.device_sharing=turns' "$work/calls")" = 4 ] || fail "MEASURED=1 JOBS=3 without device timers and turns"
[ "$(grep -c -- '--check-regions' "$work/checks")" = 4 ] || fail "not every measured file checked"
for n in dev_v24.8_s1 dev_v12.4_s1 dev_v6.2_s1 epidermis_s1; do
  for ext in h5 run.csv scene.yaml; do [ -s "$work/out/$n.$ext" ] || fail "$n.$ext not kept"; done
done
[ -z "$(ls -A "$work/tmp")" ] || fail "temporary run folders left"
# one recording fails (the stand-in exits 3 with --seed 2): the other is kept, exit status 1
rm -rf "$work/out" "$work/calls"; rc=0
JOBS=2 bash "$src/scripts/gpu/workload_library.sh" "$fake" "$work/out" dev_v24.8_s2 epidermis_s1 > "$work/bad.log" 2>&1 || rc=$?
[ "$rc" = 1 ] || { cat "$work/bad.log"; fail "a failed recording: exit $rc"; }
grep -q "dev_v24.8_s2: .* s wall, failed (exit 3)" "$work/bad.log" || { cat "$work/bad.log"; fail "the failure not named"; }
[ ! -e "$work/out/dev_v24.8_s2.h5" ] && [ -s "$work/out/epidermis_s1.h5" ] || fail "kept the failed one or lost the other"
! grep -q "device_sharing" "$work/calls" || fail "turns without MEASURED=1"
# a recording whose files cannot all be copied is not kept, and leaves nothing behind
rm -rf "$work/out"; rc=0
JOBS=2 bash "$src/scripts/gpu/workload_library.sh" "$fake" "$work/out" epidermis_long_s3 epidermis_s1 > "$work/cp.log" 2>&1 || rc=$?
[ "$rc" = 1 ] && [ ! -e "$work/out/epidermis_long_s3.h5" ] && [ -s "$work/out/epidermis_s1.h5" ] &&
  [ -z "$(ls -A "$work/out" | grep -v '^epidermis_s1\.')" ] || { cat "$work/cp.log"; ls -A "$work/out"; fail "a failed copy: exit $rc"; }
# SIGTERM (SIGINT alike; a background job ignores SIGINT): the running recordings stop, their run folders go, exit 130
rm -rf "$work/out"; rc=0
FAKE_SLOW_S=30 JOBS=2 bash "$src/scripts/gpu/workload_library.sh" "$fake" "$work/out" epidermis_s1 dev_v24.8_s1 > "$work/int.log" 2>&1 &
pid=$!; sleep 2.5; kill -TERM "$pid"; wait "$pid" || rc=$?
[ "$rc" = 130 ] && [ -z "$(ls -A "$work/tmp")" ] || { cat "$work/int.log"; ls "$work/tmp"; fail "SIGTERM: exit $rc, or run folders left"; }
# the region check refuses a file: nothing kept
rm -rf "$work/out"; rc=0
MEASURED=1 FAKE_CHECK=1 PYTHON=$work/py bash "$src/scripts/gpu/workload_library.sh" "$fake" "$work/out" epidermis_s1 \
  > "$work/check.log" 2>&1 || rc=$?
[ "$rc" = 1 ] && [ ! -e "$work/out/epidermis_s1.h5" ] || { cat "$work/check.log"; fail "a file failing the region check kept (exit $rc)"; }
# a PYTHON without h5py (PYTHON=false fails `-c 'import h5py, numpy'`): kept, saying it was not checked
rm -rf "$work/out"
MEASURED=1 PYTHON=false bash "$src/scripts/gpu/workload_library.sh" "$fake" "$work/out" epidermis_s1 > "$work/nocheck.log" 2>&1 \
  || { cat "$work/nocheck.log"; fail "no h5py: exit $?"; }
[ -s "$work/out/epidermis_s1.h5" ] && grep -q "epidermis_s1: timed regions not checked" "$work/nocheck.log" \
  || { cat "$work/nocheck.log"; fail "no h5py: not kept, or not said"; }
[ -z "$(ls -A "$work/tmp")" ] || fail "temporary run folders left after failures"
echo "workload_library.sh: ok"
