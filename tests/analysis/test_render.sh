#!/usr/bin/env bash
# analysis/render.py on a fresh semlb sim state: a PNG comes out; a file that is not a state is refused (exit 2).
set -euo pipefail
src=$1; work=$2; semlb=$3
rm -rf "$work"; mkdir -p "$work"
"$semlb" sim --scene "$src/scenes/epidermis.yaml" --out "$work/run" --steps 20 --set tissue.cells=30 --quiet
"${PYTHON:-/usr/bin/python3}" "$src/analysis/render.py" "$work/run/final.h5" "$work/epidermis.png" --semlb "$semlb"
head -c 8 "$work/epidermis.png" | od -An -c | grep -q "P   N   G"
echo "not hdf5" > "$work/bad.h5"
set +e; "${PYTHON:-/usr/bin/python3}" "$src/analysis/render.py" "$work/bad.h5" "$work/bad.png" 2>/dev/null; rc=$?; set -e
[ "$rc" = 2 ] || { echo "bad file gave exit $rc"; exit 1; }
[ ! -e "$work/bad.png" ] || { echo "partial PNG left behind"; exit 1; }
echo "1 passed, 0 failed"
