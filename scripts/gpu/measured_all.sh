#!/usr/bin/env bash
# Every measured-time result (docs/measured_time.md) on one OpenCL GPU: the paper's regime scene (every stage) and a
# Day 2-3 window of the development scene at the paper's size, then the tables under RESULTS (default
# results/gpu/measured). Resumable: scripts/gpu/measured_time.sh skips the runs already under RUNS.
# Usage: bash scripts/gpu/measured_all.sh SEMLB RUNS [RESULTS]
#   SCENES="epidermis_half epidermis_development" (the default: both); POLICIES (default: static reactive gru
#   persistence all_tensor learned_repartition); NO_TABLES=1: the runs only; TABLES_ONLY=1: the tables only, from RUNS
#   (the tables need numpy, scipy and h5py: make them where those are, from RUNS brought back)
set -euo pipefail
S=$1; RUNS=$2; here=$(cd "$(dirname "$0")/../.." && pwd); RESULTS=${3:-$here/results/gpu/measured}
PY=${PYTHON:-/usr/bin/python3}
SCENES=${SCENES:-epidermis_half epidermis_development}
export POLICIES=${POLICIES:-static reactive gru persistence all_tensor learned_repartition}
for scene in $SCENES; do
  [ -z "${TABLES_ONLY:-}" ] || break
  case $scene in
    epidermis_half) bash "$here/scripts/gpu/measured_time.sh" "$S" "$RUNS/epidermis_half" tissue cost turns record e2e ;;
    epidermis_development)
      SCENE=epidermis_development START=960 STEPS=400 EVERY=20 SKIN=1 GROWTH="--set effects.growth.front.speed=24.8" \
        bash "$here/scripts/gpu/measured_time.sh" "$S" "$RUNS/epidermis_development" tissue record e2e ;;
    *) echo "measured_all.sh: unknown scene '$scene' (epidermis_half epidermis_development)" >&2; exit 2 ;;
  esac
done
[ -z "${NO_TABLES:-}" ] || exit 0
for scene in $SCENES; do
  "$PY" "$here/analysis/measured_time.py" "$RUNS/$scene" "$RESULTS/$scene" --semlb "$S" --scene "$scene"
done
"$PY" "$here/analysis/measured_time.py" --combine "$RESULTS"
