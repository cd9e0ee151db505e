#!/usr/bin/env bash
# Peer benchmark: semlb's opencl-binned force step against ya||a's grid solver (github.com/germannp/yalla,
# MIT; not copied here: YALLA=PATH names a folder holding a clone as PATH/yalla) on the SAME tissue: the positions semlb generates for scenes/mechanics.yaml, the
# same cutoff (8.75 um, one grid cube) and the same Morse force law. ya||a's Heun step makes two force
# evaluations and two grid builds, so its time per force evaluation is half its step; semlb's bench step is
# one force evaluation plus binning and integration. Run on a machine with an NVIDIA GPU and nvcc:
#   git clone https://github.com/germannp/yalla /tmp/peer/yalla
#   YALLA=/tmp/peer bash scripts/gpu/peer_yalla/run.sh build/cli/semlb scenes/mechanics.yaml [CELLS...]
#   (default cells: 11000 435661); analysis/peer_yalla.py turns its output into results/gpu/peer_yalla.csv.
#   VARIANTS: ';'-separated extra flags of semlb's bench, each benched every round (default: one, the scene as it
#   is), e.g. VARIANTS="--set backend.opencl-binned.newton=false;--set backend.opencl-binned.newton=true".
set -u
S=$1; SCENE=$2; shift 2; CELLS=${*:-11000 435661}
here=$(cd "$(dirname "$0")" && pwd)
export OCL_ICD_FILENAMES=${OCL_ICD_FILENAMES:-libnvidia-opencl.so.1}
nvcc -O3 -std=c++17 -arch=sm_90 -I "${YALLA:?set YALLA to the folder holding the ya||a clone as yalla/}" "$here/bench_yalla.cu" -o /tmp/peer_yalla || exit 1
for c in $CELLS; do
  "$S" sim --scene "$SCENE" --out /tmp/peer_t$c --steps 1 --set tissue.cells=$c --backend opencl-binned \
      --platform NVIDIA --precision float --quiet >/dev/null 2>&1 || { echo "semlb sim failed at $c cells"; exit 1; }
  python3 "$here/to_bin.py" /tmp/peer_t$c/final.h5 /tmp/peer_t$c.bin >/dev/null || exit 1
done
IFS=';' read -ra variants <<< "${VARIANTS:-}"
[ ${#variants[@]} -gt 0 ] || variants=("")
for round in 1 2; do
  for v in "${variants[@]}"; do
    # shellcheck disable=SC2086
    "$S" bench engine --platform NVIDIA --backends opencl-binned --cells "${CELLS// /,}" --steps 200 --precision float $v
  done
  for c in $CELLS; do /tmp/peer_yalla /tmp/peer_t$c.bin; done
done
