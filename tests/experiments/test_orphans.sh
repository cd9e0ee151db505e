#!/bin/bash
# A sweep ended by SIGKILL or SIGTERM while its mpi_sim rows run mpiexec takes mpiexec and the ranks with it (they
# are gone within seconds); SIGTERM also removes its run folders and its results folder's lock, and the folders a
# SIGKILL left are removed by the next sweep's first launch. Usage: test_orphans.sh SOURCE_DIR WORK_DIR SEMLB
set -u
SRC=$1 WORK=$2 SEMLB=$3
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
rm -rf "$WORK" && mkdir -p "$WORK/tmp" && cd "$WORK" || exit 1
export TMPDIR=$WORK/tmp  # the run folders go here (std::filesystem::temp_directory_path)
cp "$SRC/scenes/mechanics.yaml" mech.yaml
manifest() {  # NAME STEPS RANKS...
  printf 'name: %s\nrunner: mpi_sim\noutput: %s/%s.csv\naxes:\n  cells: [300]\n  ranks: [%s]\nset:\n  scene: mech.yaml\n  steps: %s\n  policy: static\n  rebalance_every: 100\n' \
    "$1" "$1" "$1" "$3" "$2" > "$1.yaml"
}
manifest long 100000 "2, 1"
manifest short 20 1
running() { pgrep -f "semlb_mpi_$1_" > /dev/null; }
fail() {
  echo "FAIL: $*"
  ps -eo pid,ppid,pgid,etime,args | grep "semlb_mpi_" | grep -v grep
  exit 1
}
for sig in TERM KILL; do
  "$SEMLB" sweep long.yaml --results "r_$sig" --no-timing --quiet &
  P=$!
  for _ in $(seq 300); do running "$P" && break; sleep 0.1; done
  running "$P" || fail "$sig: no rank of sweep $P started"
  sleep 1
  kill "-$sig" "$P"
  wait "$P"
  rc=$?
  [ "$sig" = TERM ] && [ "$rc" != 143 ] && fail "SIGTERM: exit $rc, expected 143"
  for _ in $(seq 150); do running "$P" || break; sleep 0.1; done
  running "$P" && fail "$sig: mpiexec or ranks of the killed sweep $P still run 15 s later"
  if [ "$sig" = TERM ]; then
    ls -d "$TMPDIR/semlb_mpi_${P}_"* 2> /dev/null && fail "SIGTERM: run folders left"
    [ -e r_TERM/long/.semlb.lock ] && fail "SIGTERM: the lock file was left"
  else
    KILLED=$P
  fi
done
"$SEMLB" sweep short.yaml --results r_short --no-timing --quiet || fail "the next sweep failed"
ls -d "$TMPDIR/semlb_mpi_${KILLED}_"* 2> /dev/null && fail "SIGKILL: the next sweep left the dead sweep's run folders"
echo "ok"
