#!/usr/bin/env bash
# analysis/provenance.py status(): a result is stale when the kernel or controller paths differ at HEAD from its own
# commit, current when they hold the same (a change undone since), and a kernels-only result ignores the controllers.
# Usage: test_provenance.sh REPO_ROOT WORK_DIR
set -euo pipefail
src=$1; work=$2
py=${PYTHON:-/usr/bin/python3}
rm -rf "$work"; mkdir -p "$work/engine/backends" "$work/controllers" "$work/docs"
cd "$work"
git init -q && git config user.email t@t && git config user.name t
commit() { git add -A && git commit -qm "$1" && git rev-parse HEAD; }
echo 1 > engine/backends/k.cl; echo 1 > controllers/p.cpp; a=$(commit a)
echo 2 > engine/backends/k.cl; b=$(commit b)
echo 1 > engine/backends/k.cl; c=$(commit c)           # b's change undone
echo 2 > controllers/p.cpp; d=$(commit d)              # a controller change
echo doc > docs/x.md; e=$(commit e)                    # outside the paths
"$py" - "$src" "$work" "$a" "$b" "$c" "$d" "$e" <<'PY'
import sys
sys.path.insert(0, sys.argv[1] + "/analysis")
import provenance as p
repo, a, b, c, d, e = sys.argv[2:]
def st(commit, paths=None):
    return p.status(commit, repo, paths)[0]
assert st(a) == p.STALE, st(a)                         # the controllers changed in d
assert st(a, p.ENGINE_PATHS) == p.FRESH, "a's kernels were restored by c"
assert st(b, p.ENGINE_PATHS) == p.STALE, "b's kernels differ from HEAD's"
assert st(d) == p.FRESH and st(e) == p.FRESH, (st(d), st(e))
assert p.status(b, repo, p.ENGINE_PATHS)[1].startswith(c[:7]), p.status(b, repo, p.ENGINE_PATHS)
assert st("0" * 40) == p.UNKNOWN
print("provenance: ok")
PY
# record(): a `files` entry naming a subfolder holds for the files under it (the longest entry wins), a file's own
# entry over both, and the folder's record elsewhere
mkdir -p "$work/gpu/m/dev/runs"
cat > "$work/gpu/m/provenance.json" <<'JSON'
{"semlb_commit": "aaa", "date": "2026-12-03", "how": "folder",
 "files": {"dev": {"semlb_commit": "bbb"}, "dev/runs": {"semlb_commit": "ccc"}, "dev/x.csv": {"semlb_commit": "ddd"}}}
JSON
"$py" - "$src" "$work/gpu/m" <<'PY'
import sys
sys.path.insert(0, sys.argv[1] + "/analysis")
import provenance as p
m = sys.argv[2]
got = {f: p.record(f"{m}/{f}")["semlb_commit"] for f in ("a.csv", "dev/y.csv", "dev/runs/z.csv", "dev/x.csv", "develop.csv")}
assert got == {"a.csv": "aaa", "dev/y.csv": "bbb", "dev/runs/z.csv": "ccc", "dev/x.csv": "ddd", "develop.csv": "aaa"}, got
print("provenance records: ok")
PY
