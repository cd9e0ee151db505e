#!/usr/bin/env bash
# analysis/list_warps.py: the lane efficiency of a warp on hand-made lengths (31 lists of 1 and one of 33: 64 / (32 x
# 33)), sorting within blocks never below it and reaching 1 for equal maxima; on a small tissue of `semlb sim` one line
# per list with the half list's mean about half the full one's; a missing file refused naming it.
# Usage: test_list_warps.sh REPO_ROOT WORK_DIR SEMLB
set -euo pipefail
src=$1; work=$2; semlb=$3
py=${PYTHON:-/usr/bin/python3}
rm -rf "$work"; mkdir -p "$work"
fail() { echo "FAIL: $*"; exit 1; }
PYTHONPATH=$src/analysis "$py" - <<'PYEOF' || fail "the efficiencies"
import numpy as np
import list_warps as w
one = [1] * 31 + [33]
assert abs(w.efficiency(one) - 64 / (32 * 33)) < 1e-12, w.efficiency(one)
two = one + [33] + [1] * 31  # two warps, each with one long list: sorted within 64 puts both long lists in one warp
assert abs(w.sorted_within(np.array(two), 64) - 128 / (32 * 33 + 32 * 1)) < 1e-12, w.sorted_within(np.array(two), 64)
rng = np.random.default_rng(3)
lengths = rng.integers(0, 100, 4096)
for b in w.BLOCKS:
    assert w.sorted_within(lengths, b) >= w.efficiency(lengths) - 1e-12, b
PYEOF
"$semlb" sim --quiet --scene "$src/scenes/mechanics.yaml" --out "$work/t" --steps 0 --backend serial \
  --set tissue.cells=300 > /dev/null 2>&1 || fail "sim"
"$py" "$src/analysis/list_warps.py" "$work/t/final.h5" --cutoff 8.75 --skin 0.5 --windows 2 --window-slots 1024 \
  > "$work/out.txt" || { cat "$work/out.txt"; fail "list_warps"; }
cat "$work/out.txt"
grep -q "^full list: mean [0-9.]* partners, max [0-9]*; warp efficiency 0\.[0-9]*; sorted within blocks of 64: " \
  "$work/out.txt" || fail "the full list's line"
full=$(sed -n 's/^full list on .*: mean \([0-9.]*\) partners.*/\1/p' "$work/out.txt")
half=$(sed -n 's/^half list on .*: mean \([0-9.]*\) partners.*/\1/p' "$work/out.txt")
"$py" -c "import sys; f, h = $full, $half; sys.exit(0 if 0.4 * f < h < 0.6 * f else 1)" || fail "half $half of full $full"
rc=0; "$py" "$src/analysis/list_warps.py" "$work/none.h5" --cutoff 8.75 --skin 0.5 2> "$work/err.txt" || rc=$?
[ "$rc" != 0 ] && grep -q "none.h5" "$work/err.txt" || fail "a missing file: exit $rc, $(cat "$work/err.txt")"
echo "list_warps: ok"
