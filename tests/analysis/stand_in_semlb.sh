#!/usr/bin/env bash
# A stand-in for `semlb sim` in the GPU scripts' tests (no GPU): appends "PARENT_PID RUNNING ARGS..." to
# $FAKE_DIR/calls (RUNNING: how many stand-ins run at its start), sleeps FAKE_SLOW_S (3) when " ARGS " matches the
# glob FAKE_SLOW, else FAKE_S (0) seconds, exits 3 with --seed 2, and writes --out's workload.h5 (an empty HDF5 file:
# no timed regions to check), scene.yaml and, but with --seed 3 (a copy that then fails), run.csv.
set -u
out=; args=("$@")
for ((i = 0; i < ${#args[@]}; i++)); do [ "${args[$i]}" = --out ] && out=${args[$((i + 1))]}; done
touch "$FAKE_DIR/running.$$"
echo "$PPID $(ls "$FAKE_DIR"/running.* | wc -l) $*" >> "$FAKE_DIR/calls"
# shellcheck disable=SC2053
if [ -n "${FAKE_SLOW:-}" ] && [[ " $* " == $FAKE_SLOW ]]; then sleep "${FAKE_SLOW_S:-3}"; else sleep "${FAKE_S:-0}"; fi
rm -f "$FAKE_DIR/running.$$"
[[ " $* " == *" --seed 2 "* ]] && exit 3
/usr/bin/python3 -c 'import h5py, sys; h5py.File(sys.argv[1], "w")' "$out/workload.h5"
echo yaml > "$out/scene.yaml"
[[ " $* " == *" --seed 3 "* ]] || echo csv > "$out/run.csv"
