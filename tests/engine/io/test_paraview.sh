#!/usr/bin/env bash
# ParaView's default reader (Xdmf3 of python3-paraview, no display needed) on semlb's XDMF indexes: snapshots.xmf
# (step 0 included, once, also after a restart and on 2 ranks), final.xmf, checkpoint.xmf and failure.xmf show
# every element as a point and a cell, with the cell id, type and slot and the states' times.
# Usage: test_paraview.sh SOURCE_DIR WORK_DIR SEMLB MPIEXEC
set -euo pipefail
src=$1; work=$2; semlb=$3; mpiexec=$4
rm -rf "$work"; mkdir -p "$work"
py=${PYTHON:-/usr/bin/python3}
check() { timeout 300 "$py" "$src/tests/engine/io/paraview_check.py" "$@"; }
snaps() { local dir=$1; shift; for s in "$@"; do printf '%s/snapshots/step_%09d.h5\n' "$dir" "$s"; done; }
once() { [ "$(grep -c "Name=\"step_$2\"" "$1")" = 1 ] || { echo "FAIL: $1 lists step $2 $(grep -c "Name=\"step_$2\"" "$1") times"; exit 1; }; }
run=(--scene "$src/scenes/epidermis.yaml" --quiet --set backend.cpu-binned.threads=1
     --set output.snapshot_every=10 --set output.checkpoint_every=10)

a=$work/single
timeout 300 "$semlb" sim "${run[@]}" --set tissue.cells=20 --out "$a" --steps 20
check "$a/snapshots.xmf" $(snaps "$a" 0 10 20)
check "$a/final.xmf" "$a/final.h5"
check "$a/checkpoint.xmf" "$a/checkpoint.h5"
once "$a/snapshots.xmf" 0

# A restart from step 20 into the same directory keeps the earlier snapshots and does not repeat step 20.
timeout 300 "$semlb" sim "${run[@]}" --set tissue.cells=20 --out "$a" --steps 30 --restart "$a/checkpoint.h5"
check "$a/snapshots.xmf" $(snaps "$a" 0 10 20 30)
check "$a/final.xmf" "$a/final.h5"
check "$a/checkpoint.xmf" "$a/checkpoint.h5"
for s in 0 20 30; do once "$a/snapshots.xmf" $s; done

b=$work/np2
OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 timeout 300 "$mpiexec" --oversubscribe -np 2 \
  "$semlb" sim "${run[@]}" --set tissue.cells=100 --out "$b" --steps 20
check "$b/snapshots.xmf" $(snaps "$b" 0 10 20)
check "$b/final.xmf" "$b/final.h5"
once "$b/snapshots.xmf" 0

c=$work/failure
set +e; timeout 300 "$semlb" sim --scene "$src/scenes/mechanics.yaml" --quiet --set tissue.cells=20 --set time.dt=5 \
  --out "$c" --steps 50 2>/dev/null; rc=$?; set -e
[ "$rc" = 1 ] || { echo "FAIL: the failing run exited $rc, expected 1"; exit 1; }
check "$c/failure.xmf" "$c/failure.h5"
echo "1 passed, 0 failed"
