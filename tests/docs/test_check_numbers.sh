#!/usr/bin/env bash
# CTest docs.numbers: the docs' numbers match their committed sources, and the check catches a changed
# number and a cited results/ path that a checkout lacks. Usage: test_check_numbers.sh REPO_ROOT WORK_DIR
set -euo pipefail
root=$1 work=$2
py=${PYTHON:-/usr/bin/python3}
check=$root/tests/docs/check_numbers.py

"$py" "$check" "$root"

# A copy of what the check reads, with one number and one path broken.
rm -rf "$work" && mkdir -p "$work/tests"
cp -r "$root/README.md" "$root/docs" "$root/experiments" "$work/"
cp -r "$root/tests/docs" "$work/tests/"
# Tracked results/ files as empty stand-ins (the path check needs them tracked), then the sources' contents.
git -C "$root" ls-files results | while read -r f; do mkdir -p "$work/$(dirname "$f")"; : > "$work/$f"; done
"$py" -c 'import json,sys; print("\n".join(json.load(open(sys.argv[1]))["sources"].values()))' \
  "$root/tests/docs/numbers.json" | (cd "$root" && xargs cp --parents -t "$work")
git -C "$work" init -q && git -C "$work" add results

"$py" "$check" "$work" || { echo "FAIL: the unchanged copy does not pass"; exit 1; }

grep -q 'fewer than reactive at P=2, 4.1x at P=4' "$work/README.md"
sed -i 's/fewer than reactive at P=2, 4.1x at P=4/fewer than reactive at P=2, 4.3x at P=4/' "$work/README.md"
sed -i 's/computation-only time at 435,661 cells is 6.319 s/computation-only time at 435,661 cells is 6.391 s/' \
  "$work/README.md"
echo 'See `results/gpu/no_such_file.csv`.' >> "$work/docs/engine.md"
set +e
out=$("$py" "$check" "$work" 2>&1)
rc=$?
set -e
echo "$out"
[ "$rc" = 1 ] || { echo "FAIL: exit $rc on broken docs, expected 1"; exit 1; }
for want in "'4.3' in" "'6.391' in" "'results/gpu/no_such_file.csv' is neither tracked"; do
  grep -qF "$want" <<<"$out" || { echo "FAIL: no error containing: $want"; exit 1; }
done
echo "docs.numbers: ok"
