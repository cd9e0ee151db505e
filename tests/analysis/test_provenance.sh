#!/usr/bin/env bash
# analysis/provenance.py status(): a result is stale when the kernel or controller paths differ at HEAD from its own
# commit, current when they hold the same (a change undone since) or differ in comments and layout only, and a
# kernels-only result ignores the controllers.
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
# comments and layout: a C, C++ or OpenCL file whose tokens are unchanged is no difference (a formatter's commit
# leaves results current); a token changed, or any change to another kind of file, is one; the detail skips a newer
# layout-only commit
mkdir -p "$work/fmt/engine/backends" && cd "$work/fmt"
git init -q && git config user.email t@t && git config user.name t
printf '#define F(x) ((x)+1)\nint f(int a,int b){return a+ +b;} // sum\n' > engine/backends/k.cpp
printf '__kernel void k(__global float* x){x[0]=-1.0f;}\n' > engine/backends/k.cl
echo 'set(A 1)' > engine/backends/CMakeLists.txt
f1=$(commit f1)
printf '// The sum.\n#define F(x) ((x)+1)\n\nint f(int a, int b) {\n  return a + +b;  // sum\n}\n' > engine/backends/k.cpp
printf '/* one kernel */\n__kernel void k(__global float* x) {\n  x[0] = -1.0f;\n}\n' > engine/backends/k.cl
f2=$(commit "layout and comments")
sed -i 's/a + +b/a ++b/' engine/backends/k.cpp; f3=$(commit "a token")
sed -i 's/a ++b/a + +b/' engine/backends/k.cpp; echo 'set(A 2)' > engine/backends/CMakeLists.txt; f4=$(commit cmake)
echo 'set(A 1)' > engine/backends/CMakeLists.txt; sed -i 's/#define F(x)/#define F (x)/' engine/backends/k.cpp
f5=$(commit "directive spacing")
sed -i 's/#define F (x)/#define F(x)/' engine/backends/k.cpp; sed -i 's|x\[0\] = -1.0f;|x[0]=-1.0f; // layout|' engine/backends/k.cl
f6=$(commit "undone, and layout")
"$py" - "$src" "$work/fmt" "$f1" "$f2" "$f3" "$f4" "$f5" "$f6" <<'PY'
import subprocess, sys
sys.path.insert(0, sys.argv[1] + "/analysis")
import provenance as p
repo, f1, f2, f3, f4, f5, f6 = sys.argv[2:]
st = lambda c: p.status(c, repo, p.ENGINE_PATHS)
assert st(f1) == (p.FRESH, ""), st(f1)                 # f2..f6 leave only layout and comments against f1
assert st(f2)[0] == p.FRESH and st(f6)[0] == p.FRESH
assert st(f3)[0] == p.STALE and st(f3)[1].startswith(f4[:7]), st(f3)    # a ++b: f4 made it a + +b (f5-f6 a detour)
assert st(f4)[0] == p.STALE and st(f4)[1].startswith(f5[:7]), st(f4)    # the CMake line undone in f5
assert st(f5)[0] == p.STALE and st(f5)[1].startswith(f6[:7]), st(f5)    # F (x) -> F(x): a directive's spacing
# the detail names the newest commit that touched a file that differs, not a newer one that touched only files that
# differ in layout (k.cl)
open(f"{repo}/engine/backends/k.cl", "a").write("\n// trailing comment\n")
subprocess.run(["git", "-C", repo, "commit", "-qam", "comment"], check=True)
p._cache.clear()
assert st(f3)[1].startswith(f4[:7]), st(f3)
# nor a newer commit that changed the differing file's layout only (k.cpp reformatted)
text = open(f"{repo}/engine/backends/k.cpp").read()
open(f"{repo}/engine/backends/k.cpp", "w").write(text.replace("int f(int a, int b) {", "int f(int a,\n      int b) {"))
subprocess.run(["git", "-C", repo, "commit", "-qam", "layout"], check=True)
p._cache.clear()
assert st(f3)[1].startswith(f4[:7]) and st(f1) == (p.FRESH, ""), (st(f3), st(f1))
print("provenance, layout and comments: ok")
PY
# code_tokens: what a formatter changes gives the same tokens, what changes the program does not
"$py" - "$src" <<'PY'
import sys
sys.path.insert(0, sys.argv[1] + "/analysis")
from provenance import code_tokens as t
same = [("#define M(a) \\\n  ((a)-1)  \\\n", "#define M(a) \\\n  ((a) - 1)            \\\n"),
        ("#if defined(X)\nint y;\n#endif\n", "#if defined( \\\n    X)\nint y;  // why\n#endif\n"),
        ('f("a" "b");', 'f("a"\n  "b");'), ("x=-1.0f;", "x = -1.0f;"), ("int *p;", "int* p;")]
same += [("/* a template */\ncase @I@: return f_@NAME@(x);\n", "case @I@: return f_@NAME@(x);  // why\n\n")]
differ = [("case @I@: return f_@NAME@(x);", "case @I @: return f_ @NAME @(x);"),
          ("case @I@: return f_@NAME@(x);", "case @I@:\n  return f_@NAME@(x);"),
          ("#define A 1\nint x;\n", "#define A 1 int x;\n"), ("#define F(x) x\n", "#define F (x) x\n"),
          ("y = x - -1;", "y = x--1;"), ('f("a b");', 'f("a  b");'), ('f("ab");', 'f("a" "b");'), ("a+++b;", "a + ++b;")]
# what the lexer's own preprocessor states or the line splices would hide (a fresh reviewer's cases)
differ += [("#if 0\nint a;\n#elif defined(A)\nint b;\n#endif\n", "#if 0\nint a;\n#elif defined(B)\nint b;\n#endif\n"),
           ('#define URL "http://a.org"\n', '#define URL "http://b.net"\n'),
           ('#define S "/*"\nint x = 1;\n/* */\n', '#define S "/*"\nint x = 2;\n/* */\n'),
           ("x = -\\\n-y;", "x = - \\\n-y;"), ("#define F\\\n(x) x\n", "#define F (x) x\n"),
           ("#include <a/ b.h>\n", "#include <a/b.h>\n"), ("#define S(x) #x\n", "#define S(x) x\n"),
           ("int/**/y;", "inty;")]
same += [("#define F(x)   ((x) - 1)  \\\n  + 2\n", "#define F(x) ((x)-1) + 2\n"),
         ("#define P(a,b) a##b\n", "#define P(a, b) a ## b\n")]
for a, b in same:
    assert t(a) == t(b), (a, b)
for a, b in differ:
    assert t(a) != t(b), (a, b)
print("code_tokens: ok")
PY
