"""Where a committed GPU result comes from (semlb commit and date) and whether the engine has changed since (stale).

A result folder under results/gpu/ holds a `provenance.json`:
    {"semlb_commit": "<40 hex>", "date": "YYYY-MM-DD", "how": "how the commit is known", "note": "optional",
     "files": {"name.csv": {"semlb_commit": ..., "date": ..., "how": ..., "note": ...}}}
`files` overrides the folder's record for single files (results/gpu/provenance.json records the loose files there).
An optional `"depends": "kernels"` says the result times the engine only (no controller decides anything in it).
A result is stale when the engine's kernels or the controllers (KERNEL_PATHS; only ENGINE_PATHS for a result that
depends on the kernels alone) differ at HEAD from its own commit; unknown when git cannot say (a tarball without
history, or a commit this clone does not hold). A C, C++ or OpenCL file whose tokens are the same at both commits
(a change of comments, blank lines or layout only, as a formatter makes) is not a difference: the tokens are Pygments'
C++ lexer's, comments and whitespace between tokens dropped; a preprocessor directive is compared with its spacing.
Usage: provenance.py [--results DIR] [--check]   (prints one line per record: path, commit, date, status)
"""
import argparse
import functools
import json
import os
import re
import subprocess
import sys

from pygments.lexers import CppLexer
from pygments.token import Comment, Error, Number, Operator, Punctuation, Text

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# The paths whose changes make a committed timing or controller result stale: the kernels and their host code, the
# shared C99 physics they compile (engine/physics), the per-pair and per-cell plug-ins, the step loop
# (engine/simulation), W_s (model/slices), the decomposition (exchange, migration) and the controllers.
ENGINE_PATHS = ["engine/physics", "engine/backends", "engine/pairs", "engine/terms", "engine/effects", "engine/growth",
                "engine/division", "engine/fates", "engine/removal", "engine/simulation", "engine/model/slices.hpp",
                "engine/model/slices.cpp", "engine/decomposition"]
KERNEL_PATHS = ENGINE_PATHS + ["controllers"]

# Changes a reader knows the engine by: a result made before one of them is labelled "before <name>".
MILESTONES = [("the GPU-resident engine", "52e041256476e6d0e0f70823a8511537cca1cdd0"),
              ("the neighbour list", "aaa44ac")]

FRESH, STALE, UNKNOWN = "fresh", "stale", "unknown"
_cache = {}


def _git(*args, repo=REPO):
    """stdout of `git -C repo ARGS`, or None when git fails (no git, no history, unknown commit)."""
    key = (repo,) + args
    if key not in _cache:
        try:
            out = subprocess.run(["git", "-C", repo, *args], capture_output=True, text=True, timeout=30)
            _cache[key] = out.stdout.strip() if out.returncode == 0 else None
        except (OSError, subprocess.SubprocessError):
            _cache[key] = None
    return _cache[key]


# Files compared by their tokens (code_tokens) rather than their bytes.
CODE_SUFFIXES = (".c", ".h", ".cc", ".cpp", ".hpp", ".cl")


@functools.lru_cache(maxsize=None)
def _blob_tokens(sha, repo=REPO):
    """code_tokens of the git blob SHA (computed once per blob)."""
    out = subprocess.run(["git", "-C", repo, "cat-file", "blob", sha], capture_output=True, timeout=30)
    return code_tokens(out.stdout.decode("utf-8", "replace")) if out.returncode == 0 else None


# C and C++ punctuators of more than one character, longest first (maximal munch, C++20 [lex.pptoken] 3.3)
PUNCTUATORS = sorted(["<<=", ">>=", "->*", "...", "<=>", "++", "--", "<<", ">>", "&&", "||", "->", "==", "!=", "<=", ">=",
                      "+=", "-=", "*=", "/=", "%=", "&=", "|=", "^=", "::", "##", ".*"], key=len, reverse=True)


def _munch(run):
    """A run of adjacent operator and punctuation characters split as a C++ lexer splits it (maximal munch)."""
    out, i = [], 0
    while i < len(run):
        p = next((p for p in PUNCTUATORS if run.startswith(p, i)), run[i])
        out.append(p)
        i += len(p)
    return out


def _directive(toks, i):
    """(tokens, next index) of the preprocessor directive whose '#' is toks[i]: its keyword, for a #define whether the
    macro is function-like (`F(x)`) or object-like (`F (x)`), then the code tokens of the rest, the line splices
    (backslash-newline) and comments read as spaces."""
    parts, i = [], i + 1
    while i < len(toks):
        ttype, value = toks[i]
        spliced = "".join(parts).rstrip(" \t").endswith("\\")
        if not spliced and ((ttype in Comment.Preproc and value == "\n") or
                            (ttype in Comment.Single and value.endswith("\n"))):
            break
        parts.append(value if ttype in Comment.Preproc or ttype in Comment.PreprocFile else " ")
        i += 1
    body = re.sub(r"\\[ \t]*\n", " ", "".join(parts)).strip()
    word, rest = re.match(r"(\w*)(.*)", body, re.S).groups()
    out = [("directive", word)]
    if word == "define":
        out.append(("macro", "function" if re.match(r"\w+\(", rest.lstrip()) else "object"))
    return out + code_tokens(rest) + [("directive", "end")], i + 1


def code_tokens(text):
    """The tokens of C, C++ or OpenCL source TEXT (str) as [(token type, value)], without comments and without the
    whitespace between tokens: two texts that differ in comments and layout only give the same list. Operators and
    punctuation written together are split as a C++ lexer splits them (`a + +b` is not `a ++b`, `x - 1` is `x -1`);
    a preprocessor directive gives its keyword, whether a macro is function-like (`#define F (x)` is not
    `#define F(x)`) and its tokens as code. A text that is not C to the lexer (a template of embed_kernels.cmake,
    `semlb_growth_@NAME@(`) gives one token: its text without comments and blank lines, every other space kept."""
    toks = list(CppLexer(stripnl=False).get_tokens(text))
    if any(ttype in Error for ttype, _ in toks):  # not C: a template (`f_@NAME@(`), whose spacing and lines are syntax
        kept = "".join(("\n" if value.endswith("\n") else "") if ttype in Comment and ttype not in Comment.Preproc and
                       ttype not in Comment.PreprocFile else value for ttype, value in toks)
        return [("template", "\n".join(line.rstrip() for line in kept.splitlines() if line.strip()))]
    out, run, gap, i = [], "", True, 0

    def flush():
        nonlocal run
        out.extend(("symbol", p) for p in _munch(run))
        run = ""

    while i < len(toks):
        ttype, value = toks[i]
        if ttype in Comment.Preproc and value == "#":
            flush()
            tokens, i = _directive(toks, i)
            out += tokens
            gap = True
            continue
        i += 1
        dropped = (ttype in Text and not value.strip()) or ttype in Comment
        if ttype in Number and value[:1] in "+-":  # a sign the lexer read into the number: an operator
            if gap:
                flush()
            run, gap, value = run + value[0], False, value[1:]
        symbol = ttype in Operator or ttype in Punctuation
        if run and (dropped or not symbol or gap):
            flush()
        gap = dropped
        if dropped:
            continue
        if symbol:
            run += value
        else:
            out.append((str(ttype), value))
    flush()
    return out


def same_code(commit, path, repo=REPO, head="HEAD"):
    """True when PATH (a C, C++ or OpenCL file) holds the same tokens (code_tokens) at COMMIT and at HEAD (another
    revision with head=); False for any other file, or one missing at either."""
    if not path.endswith(CODE_SUFFIXES):
        return False
    old, new = _git("rev-parse", "-q", "--verify", f"{commit}:{path}", repo=repo), \
        _git("rev-parse", "-q", "--verify", f"{head}:{path}", repo=repo)
    if not old or not new:
        return False
    return old == new or (_blob_tokens(old, repo) is not None and _blob_tokens(old, repo) == _blob_tokens(new, repo))


def record(path, root=None):
    """The provenance record of a committed result file or folder: the nearest provenance.json at or above it (up to
    ROOT, default the `gpu` folder holding it), with the fields of its `files` entry for the file over the folder's
    (a note on the folder holds for its files; an entry naming a subfolder holds for what is under it, the longest
    such entry winning). None without one."""
    path = os.path.abspath(path)
    folder = path if os.path.isdir(path) else os.path.dirname(path)
    root = os.path.abspath(root) if root else None
    while True:
        p = os.path.join(folder, "provenance.json")
        if os.path.exists(p):
            with open(p) as f:
                doc = json.load(f)
            rel = os.path.relpath(path, folder)
            rec = {k: v for k, v in doc.items() if k != "files"}  # the folder's record, a file's own fields over it
            entries = doc.get("files", {})
            under = [k for k in entries if rel == k or rel.startswith(k.rstrip("/") + "/")]
            if under:
                rec.update(entries[max(under, key=len)])
            rec["file"] = p
            return rec
        if folder == root or os.path.basename(folder) == "gpu" or os.path.dirname(folder) == folder:
            return None
        folder = os.path.dirname(folder)


def status(commit, repo=REPO, paths=None):
    """(FRESH | STALE | UNKNOWN, detail): STALE when PATHS (default KERNEL_PATHS) hold something else at HEAD than at
    COMMIT, comments and layout of source files aside (same_code; detail: the latest commit since that changed a file
    that differs, other than in its layout, 'abc1234 YYYY-MM-DD'); UNKNOWN when git cannot tell (detail: why)."""
    if not commit:
        return UNKNOWN, "no commit recorded"
    if _git("rev-parse", "--git-dir", repo=repo) is None:
        return UNKNOWN, "no git history here"
    if _git("cat-file", "-e", f"{commit}^{{commit}}", repo=repo) is None:
        return UNKNOWN, f"commit {commit[:7]} is not in this clone"
    paths = paths or KERNEL_PATHS
    changed = _git("diff", "--name-only", commit, "HEAD", "--", *paths, repo=repo)
    if changed is None:
        return UNKNOWN, "git diff failed"
    # the paths hold what they held then (a change undone since leaves the result current), or differ in comments
    # and layout only. The detail: the newest commit since that changed the tokens of a file that differs.
    changed = set(changed.splitlines())
    if not changed:
        return FRESH, ""
    log = _git("log", "--format=%x01%H %h %cs", "--name-only", f"{commit}..HEAD", "--", *paths, repo=repo) or ""
    for entry in log.split("\x01")[1:]:
        head, *files = entry.splitlines()
        full, short = head.split(" ", 1)
        if any(f in changed and not same_code(commit, f, repo) and not same_code(f"{full}^", f, repo, full)
               for f in files):
            return STALE, short
    differ = sorted(f for f in changed if not same_code(commit, f, repo))
    return (STALE, differ[0]) if differ else (FRESH, "")


def before(commit, repo=REPO):
    """The MILESTONES names the COMMIT predates (it does not contain them); [] when git cannot tell."""
    out = []
    for name, m in MILESTONES:
        full = _git("rev-parse", "--verify", "-q", f"{m}^{{commit}}", repo=repo)
        if full and _git("merge-base", "--is-ancestor", full, commit, repo=repo) is None and \
                _git("cat-file", "-e", f"{commit}^{{commit}}", repo=repo) is not None:
            out.append(name)
    return out


def describe(path, repo=REPO):
    """{'commit', 'date', 'status', 'detail', 'before', 'note'} for a committed result (status UNKNOWN and commit ''
    without a record)."""
    rec = record(path)
    if rec is None:
        return {"commit": "", "date": "", "status": UNKNOWN, "detail": "no provenance.json", "before": [], "note": ""}
    commit = rec.get("semlb_commit", "")
    st, detail = status(commit, repo, ENGINE_PATHS if rec.get("depends") == "kernels" else KERNEL_PATHS)
    return {"commit": commit, "date": rec.get("date", ""), "status": st, "detail": detail,
            "before": before(commit, repo) if commit else [], "note": rec.get("note", "")}


def label(path, repo=REPO):
    """One markdown phrase for a result's provenance: 'semlb abc1234, 2026-11-22 · **stale**: the kernels or
    controllers changed after it (last: def5678 2026-12-03) · before the GPU-resident engine'."""
    d = describe(path, repo)
    if not d["commit"]:
        return "provenance **unknown** (no provenance.json)"
    text = f"semlb `{d['commit'][:7]}`, {d['date']}"
    if d["status"] == STALE:
        text += f" · **stale**: the kernels or controllers changed after it (last: `{d['detail']}`)"
    elif d["status"] == UNKNOWN:
        text += f" · staleness **unknown** ({d['detail']})"
    else:
        text += " · current: no kernel or controller change since"
    if d["before"]:
        text += " · before " + " and ".join(d["before"])
    if d["note"]:
        text += " · " + d["note"]
    return text


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--results", default=os.path.join(REPO, "results"), help="results folder (default: the repo's)")
    ap.add_argument("--check", action="store_true", help="exit 1 when a result folder under gpu/ has no record")
    args = ap.parse_args()
    gpu = os.path.join(args.results, "gpu")
    missing = 0
    for name in sorted(os.listdir(gpu)):
        p = os.path.join(gpu, name)
        if name == "provenance.json":
            continue
        d = describe(p)
        missing += not d["commit"]
        print(f"gpu/{name}: {d['commit'][:7] or '-'} {d['date'] or '-'} {d['status']} {d['detail']}"
              + (" · before " + ", ".join(d["before"]) if d["before"] else ""))
    return 1 if args.check and missing else 0


if __name__ == "__main__":
    sys.exit(main())
