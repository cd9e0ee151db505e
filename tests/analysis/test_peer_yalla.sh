#!/usr/bin/env bash
# analysis/peer_yalla.py: each ya||a line paired with every semlb variant of its round (full and half list, the
# half one marked newton 1), rounds counted from the bench tables after ya||a lines, and a ya||a line without a semlb
# row of its size refused with exit 2 naming the line.
# Usage: test_peer_yalla.sh REPO_ROOT WORK_DIR
set -euo pipefail
src=$1; work=$2
py=${PYTHON:-/usr/bin/python3}
rm -rf "$work"; mkdir -p "$work"
table() {  # MS NEWTON: one bench table at 6,533,913 elements
  echo "# semlb bench engine: scenes/mechanics.yaml, 200 timed steps after 20 warm-up steps"
  echo "backend          precision     cells   elements    seconds   elem-steps/s    ms/step   skin builds/st    ratio  per_cube   candid.    neighb.  device"
  echo "opencl-binned    float        435661    6533913     0.5600      2.334e+09     $1   0.50    0.0500        -      9.00     294.0      60.0  NVIDIA H200"
  echo "    list: skin 0.5 um$([ "$2" = 1 ] && echo " (half: newton)"), 10 builds in 200 steps, at most 133 partners per element, 160 stored"
}
{ table 2.8000 0; table 2.2000 1; echo "yalla grid_solver n=6533913 steps=20 ms/force-eval=6.6"
  table 2.9000 0; table 2.0000 1; echo "yalla grid_solver n=6533913 steps=20 ms/force-eval=6.0"; } > "$work/peer.log"
"$py" "$src/analysis/peer_yalla.py" --machine H200 "$work/peer.log" > "$work/peer.csv"
want="elements,semlb_ms_per_step,yalla_ms_per_eval,ratio,precision,machine,round,skin,newton
6533913,2.8,6.6,2.36,float,H200,1,0.5,0
6533913,2.2,6.6,3,float,H200,1,0.5,1
6533913,2.9,6.0,2.07,float,H200,2,0.5,0
6533913,2.0,6.0,3,float,H200,2,0.5,1"
[ "$(cat "$work/peer.csv")" = "$want" ] || { echo "got:"; cat "$work/peer.csv"; echo "want:"; echo "$want"; exit 1; }
{ table 2.8000 0; echo "yalla grid_solver n=165278 steps=20 ms/force-eval=0.6"; } > "$work/bad.log"
rc=0; err=$("$py" "$src/analysis/peer_yalla.py" --machine H200 "$work/bad.log" 2>&1 > /dev/null) || rc=$?
[ "$rc" = 2 ] || { echo "exit $rc, want 2"; exit 1; }
[[ $err == *"bad.log:5: no semlb row"* ]] || { echo "message: $err"; exit 1; }
echo "peer_yalla.py: ok"
