"""Where a committed GPU result comes from (semlb commit and date) and whether the engine has changed since (stale).

A result folder under results/gpu/ holds a `provenance.json`:
    {"semlb_commit": "<40 hex>", "date": "YYYY-MM-DD", "how": "how the commit is known", "note": "optional",
     "files": {"name.csv": {"semlb_commit": ..., "date": ..., "how": ..., "note": ...}}}
`files` overrides the folder's record for single files (results/gpu/provenance.json records the loose files there).
An optional `"depends": "kernels"` says the result times the engine only (no controller decides anything in it).
A result is stale when the engine's kernels or the controllers (KERNEL_PATHS; only ENGINE_PATHS for a result that
depends on the kernels alone) differ at HEAD from its own commit; unknown when git cannot say (a tarball without
history, or a commit this clone does not hold). A C, C++ or OpenCL file whose tokens are the same at both commits
(a change of comments, blank lines or layout only, as a formatter makes) is not a difference (code_tokens: Pygments'
C++ lexer, comments and the whitespace between tokens dropped; a template that is not C compared by its text).
Usage: provenance.py [--results DIR] [--check]   (prints one line per record: path, commit, date, status)
"""
import argparse
import atexit
import functools
import hashlib
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
# (engine/simulation), W_s (model/slices), the decomposition (exchange, migration) and the controllers, and the
# interface the backends implement (engine/device: its device-timer parts split the measured seconds).
ENGINE_PATHS = ["engine/physics", "engine/device", "engine/backends", "engine/pairs", "engine/terms", "engine/effects",
                "engine/growth", "engine/division", "engine/fates", "engine/removal", "engine/simulation",
                "engine/model/slices.hpp", "engine/model/slices.cpp", "engine/decomposition"]
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


# code_tokens' digest per git blob, kept in the clone's git folder between runs (a blob never changes; the version
# in the name stands for code_tokens' rules: raise it when they change): lexing every version of every engine file
# takes half a minute, reading the digests a moment.
TOKEN_CACHE = "semlb-token-digests-v2.json"
_digests = {}


def _digest_cache(repo):
    """{blob sha: digest or ''} of REPO, read from its git folder once (empty when absent or unreadable)."""
    if repo not in _digests:
        gitdir = _git("rev-parse", "--absolute-git-dir", repo=repo)
        path = os.path.join(gitdir, TOKEN_CACHE) if gitdir else None
        try:
            with open(path) as f:
                cache = json.load(f)
        except (OSError, TypeError, ValueError):
            cache = {}
        _digests[repo] = (path, cache if isinstance(cache, dict) else {}, [False])
        atexit.register(_save_digests, repo)
    return _digests[repo]


def _save_digests(repo):
    """Writes REPO's digest cache back when it grew (atomically: a concurrent run loses at most its own additions)."""
    path, cache, dirty = _digests[repo]
    if path and dirty[0]:
        try:
            with open(path + f".{os.getpid()}", "w") as f:
                json.dump(cache, f)
            os.replace(path + f".{os.getpid()}", path)
        except OSError:
            pass


def _blob_digest(sha, repo=REPO):
    """sha256 of code_tokens of the git blob SHA, '' for a blob git cannot give; cached (_digest_cache)."""
    _, cache, dirty = _digest_cache(repo)
    if sha not in cache:
        out = subprocess.run(["git", "-C", repo, "cat-file", "blob", sha], capture_output=True, timeout=30)
        text = out.stdout.decode("utf-8", "surrogateescape")
        cache[sha] = hashlib.sha256(repr(code_tokens(text)).encode("utf-8", "surrogateescape")).hexdigest() \
            if out.returncode == 0 else ""
        dirty[0] = True
    return cache[sha]


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


# Words that stand for what the C++ lexer would lose or misread in a directive (the lexer's own preprocessor states
# read `#if 0` blocks and `//` inside a directive's strings as comments): each directive line becomes code between
# DIRECTIVE and END, a function-like macro's name is followed by FUNCTION_MACRO, `#` and `##` become words.
DIRECTIVE, END, FUNCTION_MACRO = "__semlb_directive__", "__semlb_directive_end__", "__semlb_function_macro__"
STRINGIZE, PASTE = "__semlb_stringize__", "__semlb_paste__"


def _directive_line(m):
    """A directive line (re.Match of `^(indent)#(body)$`) as code the C++ lexer reads in its root state."""
    indent, body = m.group(1), m.group(2)
    d = re.match(r"(\s*define\s+\w+)(\(?)(.*)", body, re.S)
    if d:  # `#define F(x)` is function-like, `#define F (x)` object-like
        body = d.group(1) + (f" {FUNCTION_MACRO} (" if d.group(2) else " ") + d.group(3)
    inc = re.match(r"(\s*include\s*)<([^>]*)>(.*)", body, re.S)
    if inc:  # a header name is one token, spaces and all
        body = f'{inc.group(1)}"<{inc.group(2)}>"{inc.group(3)}'
    body = body.replace("##", f" {PASTE} ").replace("#", f" {STRINGIZE} ")
    return f"{indent}{DIRECTIVE} {body}\n{END}"


def _lex(text):
    return list(CppLexer(stripnl=False).get_tokens(text))


def code_tokens(text):
    """The tokens of C, C++ or OpenCL source TEXT (str) as [(token type, value)], without comments and without the
    whitespace between tokens: two texts that differ in comments and layout only give the same list. Line splices
    are removed first (C's translation phase 2). Operators and punctuation written together are split as a C++ lexer
    splits them (`a + +b` is not `a ++b`, `x - 1` is `x -1`). A preprocessor directive is read as code between two
    markers (_directive_line), so that `#if 0` blocks and strings in directives count, and `#define F (x)` is not
    `#define F(x)`. A text that is not C to the lexer (a template of embed_kernels.cmake, `semlb_growth_@NAME@(`)
    gives one token: its text without comments and blank lines, every other space kept."""
    toks = _lex(text)
    if not any(ttype in Error for ttype, _ in toks):
        toks = _lex(re.sub(r"(?m)^([ \t]*)#(.*)$", _directive_line, re.sub(r"\\\r?\n", "", text)))
    if any(ttype in Error for ttype, _ in toks):  # not C: a template (`f_@NAME@(`), whose spacing and lines are syntax
        kept = "".join(("\n" if value.endswith("\n") else " ") if ttype in Comment else value for ttype, value in _lex(text))
        return [("template", "\n".join(line.rstrip() for line in kept.splitlines() if line.strip()))]
    out, run, gap = [], "", True

    def flush():
        nonlocal run
        out.extend(("symbol", p) for p in _munch(run))
        run = ""

    for ttype, value in toks:
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


def same_code(commit, path, repo=REPO):
    """True when PATH holds the same at COMMIT and at HEAD as far as staleness goes (_state: the tokens of a C, C++ or
    OpenCL file, the bytes of any other); False where it is missing at either."""
    old = _state(commit, path, repo)
    return old is not None and old == _state("HEAD", path, repo)


def _state(rev, path, repo=REPO):
    """What PATH holds at REV as far as staleness goes: the digest of its tokens (a C, C++ or OpenCL file,
    code_tokens) or its blob; None where it is absent."""
    sha = _git("rev-parse", "-q", "--verify", f"{rev}:{path}", repo=repo)
    if not sha:
        return None
    digest = _blob_digest(sha, repo) if path.endswith(CODE_SUFFIXES) else ""
    return ("tokens", digest) if digest else ("blob", sha)


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
    COMMIT, comments and layout of source files aside (same_code; detail: the newest commit since that brought a
    differing file to its state at HEAD, changes undone later and layout aside, 'abc1234 YYYY-MM-DD'); UNKNOWN when
    git cannot tell (detail: why)."""
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
    # and layout only (each file checked when first needed). The detail: the newest commit since that brought a
    # differing file to what it holds at HEAD, a change undone later (a detour: a format commit and its repair) not
    # counted, along the first parents (a merge stands for its branch, so each commit's parent holds what the one
    # before it left).
    changed = {f for f in changed.splitlines() if f}
    differs = functools.lru_cache(maxsize=None)(lambda f: not same_code(commit, f, repo))
    log = _git("log", "--first-parent", "-m", "--format=%x01%H %h %cs", "--name-only", f"{commit}..HEAD", "--", *paths,
               repo=repo) or ""
    entries = [(e.splitlines()[0].split(" ", 1), set(e.splitlines()[1:])) for e in log.split("\x01")[1:]]
    owners = {}
    for (full, short), files in entries:
        for f in sorted(files & changed):
            if not differs(f):
                continue  # the file holds what it held at COMMIT (a layout-only commit is no owner: _owner)
            if f not in owners:
                owners[f] = _owner(f, commit, [e[0][0] for e in entries if f in e[1]], repo)
            if owners[f] == full:
                return STALE, short
    differ = sorted(f for f in changed if differs(f))
    return (STALE, differ[0]) if differ else (FRESH, "")


def _owner(path, commit, touching, repo):
    """The commit (of TOUCHING, the commits since COMMIT that touched PATH, newest first) that brought PATH to what it
    holds at HEAD: walked oldest first from COMMIT's state, a commit that returns the file to an earlier state undoes
    the ones between (and itself); None when nothing remains."""
    states, owners = [_state(commit, path, repo)], [None]
    for full in reversed(touching):
        k = _state(full, path, repo)
        if k in states:
            j = states.index(k)
            del states[j + 1:], owners[j + 1:]
        else:
            states.append(k)
            owners.append(full)
    return owners[-1]


def before(commit, repo=REPO):
    """The MILESTONES names the COMMIT predates (it does not contain them); [] when git cannot tell."""
    out = []
    for name, m in MILESTONES:
        full = _git("rev-parse", "--verify", "-q", f"{m}^{{commit}}", repo=repo)
        if full and _git("merge-base", "--is-ancestor", full, commit, repo=repo) is None and \
                _git("cat-file", "-e", f"{commit}^{{commit}}", repo=repo) is not None:
            out.append(name)
    return out


def commit_time(commit, repo=REPO):
    """COMMIT's committer time (seconds since the epoch), to order results made on the same day; 0 when git cannot
    tell (no history, a commit this clone does not hold)."""
    out = _git("log", "-1", "--format=%ct", f"{commit}^{{commit}}", repo=repo) if commit else None
    return int(out.strip()) if out and out.strip().isdigit() else 0


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


def under(folder, rel, commit, show):
    """Calls show(REL/SUB, describe(...)) for what under FOLDER, at any depth, was made with another commit than the
    folder above it (its own provenance.json or a `files` entry): a subfolder's results kept beside the folder's."""
    for sub in sorted(os.listdir(folder)):
        if sub == "provenance.json":
            continue
        q = os.path.join(folder, sub)
        s = describe(q)
        if s["commit"][:7] != commit[:7]:
            show(f"{rel}/{sub}", s)
        if os.path.isdir(q):
            under(q, f"{rel}/{sub}", s["commit"], show)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--results", default=os.path.join(REPO, "results"), help="results folder (default: the repo's)")
    ap.add_argument("--check", action="store_true", help="exit 1 when a result folder under gpu/ has no record")
    args = ap.parse_args()
    gpu = os.path.join(args.results, "gpu")
    missing = 0

    def show(rel, d):
        print(f"{rel}: {d['commit'][:7] or '-'} {d['date'] or '-'} {d['status']} {d['detail']}"
              + (" · before " + ", ".join(d["before"]) if d["before"] else ""))

    for name in sorted(os.listdir(gpu)):
        p = os.path.join(gpu, name)
        if name == "provenance.json":
            continue
        d = describe(p)
        missing += not d["commit"]
        show(f"gpu/{name}", d)
        if os.path.isdir(p):
            under(p, f"gpu/{name}", d["commit"], show)
    return 1 if args.check and missing else 0


if __name__ == "__main__":
    sys.exit(main())
