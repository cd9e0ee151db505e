#!/usr/bin/env bash
# analysis/render.py on a fresh semlb sim state: a PNG comes out; a file that is not a state is refused (exit 2).
set -euo pipefail
src=$1; work=$2; semlb=$3
rm -rf "$work"; mkdir -p "$work"
"$semlb" sim --scene "$src/scenes/epidermis.yaml" --out "$work/run" --steps 20 --set tissue.cells=30 --quiet
"${PYTHON:-/usr/bin/python3}" "$src/analysis/render.py" "$work/run/final.h5" "$work/epidermis.png" --semlb "$semlb" \
  --summary "$work/summary.csv"
head -c 8 "$work/epidermis.png" | od -An -c | grep -q "P   N   G"
# Cell types are named as the binary lists them (`semlb list cell-types`), by type index.
[ "$(head -1 "$work/summary.csv")" = "time_h,step,cells,elements,basal,spinous,granular,thickness_um" ] ||
  { echo "summary header: $(head -1 "$work/summary.csv")"; exit 1; }
# Without the binary: exit 2 and one line naming it, no PNG.
set +e; out=$("${PYTHON:-/usr/bin/python3}" "$src/analysis/render.py" "$work/run/final.h5" "$work/none.png" --semlb "$work/none" 2>&1); rc=$?; set -e
[ "$rc" = 2 ] && [ "$(printf '%s\n' "$out" | wc -l)" = 1 ] && [[ "$out" == "render: "*"no binary at '$work/none'"* ]] ||
  { echo "no binary: exit $rc: $out"; exit 1; }
[ ! -e "$work/none.png" ] || { echo "PNG written without cell-type names"; exit 1; }
echo "not hdf5" > "$work/bad.h5"
set +e; "${PYTHON:-/usr/bin/python3}" "$src/analysis/render.py" "$work/bad.h5" "$work/bad.png" 2>/dev/null; rc=$?; set -e
[ "$rc" = 2 ] || { echo "bad file gave exit $rc"; exit 1; }
[ ! -e "$work/bad.png" ] || { echo "partial PNG left behind"; exit 1; }
echo "1 passed, 0 failed"
