#!/usr/bin/env python3
"""Recomputes the numbers of README.md and docs/*.md listed in tests/docs/numbers.json from committed files
and checks that every results/... path the docs cite exists in the checkout (or is one `make experiments`
writes). Python stdlib only.

Usage: check_numbers.py REPO_ROOT [--numbers FILE]   (exit 0: all match; 1: a mismatch, one line each)

numbers.json: {"sources": {ALIAS: PATH, ...}, "checks": [{"doc": FILE, "text": PATTERN,
"values": [EXPR, ...]}, ...]}. PATTERN is literal text with one `{}` per number; whitespace runs (line
breaks included) match any whitespace run, so a sentence may wrap. It must match exactly once in the doc.
Each EXPR is a Python expression over the helpers below (v, mean, min_of, max_of, phase, kernel, kernels_sum, bench,
cells_part, interp);
the printed number must equal it to within half a unit of its last printed digit.
"""
import csv
import fnmatch
import json
import math
import os
import re
import subprocess
import sys

NUMBER = r"([-+]?\d[\d,]*(?:\.\d+)?(?:e[-+]?\d+)?)"


class Sources:
    """Committed CSV and bench files named by alias; row filters are column=value string matches."""

    def __init__(self, root, aliases):
        self.root = root
        self.aliases = aliases
        self.cache = {}

    def path(self, alias):
        if alias not in self.aliases:
            raise KeyError(f"unknown source alias '{alias}'")
        return os.path.join(self.root, self.aliases[alias])

    def rows(self, alias, **filters):
        if alias not in self.cache:
            with open(self.path(alias), newline="") as f:
                self.cache[alias] = list(csv.DictReader(f))
        out = [r for r in self.cache[alias]
               if all(r.get(k.replace("__", ".")) == str(val) for k, val in filters.items())]
        if not out:
            raise ValueError(f"{self.aliases[alias]}: no row with {filters}")
        return out

    def v(self, alias, col, **filters):
        """The value of `col` in the one row matching filters (error if several match)."""
        rows = self.rows(alias, **filters)
        if len(rows) != 1:
            raise ValueError(f"{self.aliases[alias]}: {len(rows)} rows with {filters}, expected 1")
        return float(rows[0][col])

    def mean(self, alias, col, **filters):
        """Mean of `col` over the rows matching filters."""
        rows = self.rows(alias, **filters)
        return sum(float(r[col]) for r in rows) / len(rows)

    def min_of(self, alias, col, **filters):
        """Smallest `col` over the rows matching filters."""
        return min(float(r[col]) for r in self.rows(alias, **filters))

    def max_of(self, alias, col, **filters):
        """Largest `col` over the rows matching filters."""
        return max(float(r[col]) for r in self.rows(alias, **filters))

    def phase(self, alias, name, **filters):
        """Seconds of one phase from the `phases` column (name=seconds;...) of the one matching row."""
        rows = self.rows(alias, **filters)
        if len(rows) != 1:
            raise ValueError(f"{self.aliases[alias]}: {len(rows)} rows with {filters}, expected 1")
        parts = dict(p.split("=") for p in rows[0]["phases"].split(";"))
        return float(parts[name])

    def kernels(self, alias, cells, precision):
        """{kernel: ms/step} of one `semlb bench engine` block (SEMLB_OPENCL_PROFILE=1 output)."""
        found, out = False, {}
        with open(self.path(alias)) as f:
            for line in f:
                fields = line.split()
                if len(fields) > 3 and fields[0].startswith("opencl"):
                    found = fields[1] == precision and fields[2] == str(cells)
                elif found and fields[:1] == ["kernel"]:
                    out[fields[1]] = float(fields[2])
        if not out:
            raise ValueError(f"{self.aliases[alias]}: no kernel times for {cells} cells, {precision}")
        return out

    def bench(self, alias, backend, cells, precision, col):
        """One column (e.g. 'elem-steps/s') of a `semlb bench engine` result line."""
        header = None
        with open(self.path(alias)) as f:
            for line in f:
                fields = line.split()
                if fields[:1] == ["backend"]:
                    header = fields
                elif header and fields[:3] == [backend, precision, str(cells)]:
                    return float(fields[header.index(col)])
        raise ValueError(f"{self.aliases[alias]}: no {backend} {precision} line for {cells} cells")

    def cells_part(self, alias, elements, part):
        """ms per update of one part (download, growth, ..., total) in `semlb bench cells` output."""
        found = False
        with open(self.path(alias)) as f:
            for line in f:
                fields = line.split()
                if line.startswith("opencl") or line.startswith("cpu") or line.startswith("serial"):
                    found = f"{elements} elements" in line
                elif found and fields[:1] == [part]:
                    return float(fields[1])
        raise ValueError(f"{self.aliases[alias]}: no part '{part}' at {elements} elements")

    def kernel(self, alias, cells, precision, name):
        return self.kernels(alias, cells, precision)[name]

    def kernels_sum(self, alias, cells, precision):
        return sum(self.kernels(alias, cells, precision).values())


def interp(x, xs, ys):
    """Linear interpolation of y at x between the two neighbouring points of (xs, ys), xs monotone."""
    pts = list(zip(xs, ys))
    for (x0, y0), (x1, y1) in zip(pts, pts[1:]):
        if min(x0, x1) <= x <= max(x0, x1):
            return y0 + (y1 - y0) * (x - x0) / (x1 - x0)
    raise ValueError(f"interp: {x} outside {xs}")


def tolerance(printed):
    """Half a unit of the last printed digit of a number like 59.9, 6,533,913 or 1.07e9."""
    mant, _, exp = printed.lower().partition("e")
    decimals = len(mant.split(".")[1]) if "." in mant else 0
    return 0.5 * 10 ** (-decimals + (int(exp) if exp else 0))


def collapse(text):
    """Text with whitespace runs collapsed to one space, and the original offset of each kept char."""
    out, where, prev_space = [], [], False
    for i, c in enumerate(text):
        if c.isspace():
            if not prev_space:
                out.append(" ")
                where.append(i)
            prev_space = True
        else:
            out.append(c)
            where.append(i)
            prev_space = False
    return "".join(out), where


def check_numbers(root, spec):
    src = Sources(root, spec["sources"])
    env = {"__builtins__": {}, "v": src.v, "mean": src.mean, "min_of": src.min_of, "max_of": src.max_of, "phase": src.phase, "kernel": src.kernel,
           "kernels_sum": src.kernels_sum,
           "bench": src.bench, "cells_part": src.cells_part, "interp": interp, "abs": abs, "min": min, "max": max}
    errors, checked, docs = [], 0, {}
    for entry in spec["checks"]:
        doc = entry["doc"]
        if doc not in docs:
            with open(os.path.join(root, doc)) as f:
                raw = f.read()
            docs[doc] = (raw,) + collapse(raw)
        raw, flat, where = docs[doc]
        pattern = " ".join(entry["text"].split())
        parts = pattern.split("{}")
        if len(parts) - 1 != len(entry["values"]):
            errors.append(f"{doc}: '{entry['text']}': {len(parts) - 1} {{}} but {len(entry['values'])} values")
            continue
        regex = NUMBER.join(re.escape(p) for p in parts)
        matches = list(re.finditer(regex, flat))
        if len(matches) != 1:
            errors.append(f"{doc}: text '{pattern}' found {len(matches)} times, expected once "
                          "(edited text or number format? update tests/docs/numbers.json)")
            continue
        m = matches[0]
        line = raw.count("\n", 0, where[m.start()]) + 1
        for k, expr in enumerate(entry["values"]):
            printed = m.group(k + 1)
            if re.fullmatch(r"\s*[-+\d.e]+\s*", expr):
                errors.append(f"{doc}:{line}: {printed}: '{expr}' is a constant, not a computation from a "
                              "source; write the number into the text instead")
                continue
            try:
                value = eval(expr, env)  # noqa: S307 (expressions from our own committed numbers.json)
            except Exception as e:  # report every failing expression, not just the first
                errors.append(f"{doc}:{line}: {printed}: cannot compute '{expr}': {e}")
                continue
            shown = float(printed.replace(",", ""))
            tol = tolerance(printed.replace(",", ""))
            checked += 1
            if not math.isfinite(value) or abs(value - shown) > tol * (1 + 1e-9):
                errors.append(f"{doc}:{line}: '{printed}' in '{m.group(0)}' but {expr} = {value:.6g}")
    return errors, checked


RESULTS_PATH = re.compile(r"results/[A-Za-z0-9_./*<>-]*[A-Za-z0-9_*>/]")
# What `make experiments` writes: results/tables, results/figures, results/epidermis, results/development,
# results/trace_model, results/REPORT.md, results/report (its detail pages) and one folder per
# manifest (experiments/*.yaml 'output:' folder).
MAKE_EXPERIMENTS = re.compile(r"`?make (experiments|epidermis|train)`?|PROFILE=paper make experiments")


def check_paths(root, docs):
    """results/... paths in the docs: tracked by git (a file, a folder of tracked files or a glob), or
    written by `make experiments` and said so in the same paragraph."""
    tracked = subprocess.run(["git", "-C", root, "ls-files", "results"], check=True, capture_output=True,
                             text=True).stdout.split()
    manifests = sorted(os.path.splitext(n)[0] for n in os.listdir(os.path.join(root, "experiments"))
                       if n.endswith(".yaml"))
    made = ["results/tables/", "results/figures/", "results/epidermis/", "results/development/", "results/trace_model/",
            "results/REPORT.md", "results/report/", "results/<experiment>/"] + \
        [f"results/{m}/" for m in manifests]
    errors, seen = [], 0
    for doc in docs:
        with open(os.path.join(root, doc)) as f:
            raw = f.read()
        offset = 0
        for para in re.split(r"\n\s*\n", raw):
            start = raw.index(para, offset)
            offset = start + len(para)
            for m in RESULTS_PATH.finditer(para):
                path = m.group(0).rstrip(".")
                seen += 1
                line = raw.count("\n", 0, start + m.start()) + 1
                if path.rstrip("/") == "results":
                    continue
                if any(t == path or t.startswith(path.rstrip("/") + "/") or fnmatch.fnmatch(t, path)
                       for t in tracked):
                    continue
                if any(path.startswith(p) for p in made) or path in ("results/tables", "results/figures"):
                    if MAKE_EXPERIMENTS.search(para):
                        continue
                    errors.append(f"{doc}:{line}: '{path}' is not in the checkout; say in the same paragraph "
                                  "that `make experiments` writes it")
                    continue
                errors.append(f"{doc}:{line}: '{path}' is neither tracked (git ls-files) nor written by "
                              "`make experiments`")
    return errors, seen


def main():
    args = sys.argv[1:]
    if not args or args[0].startswith("-"):
        print(__doc__.strip().splitlines()[2], file=sys.stderr)
        return 2
    root = args[0]
    numbers = os.path.join(root, "tests", "docs", "numbers.json")
    if "--numbers" in args:
        numbers = args[args.index("--numbers") + 1]
    with open(numbers) as f:
        spec = json.load(f)
    docs = ["README.md"] + sorted(os.path.join("docs", n) for n in os.listdir(os.path.join(root, "docs"))
                                  if n.endswith(".md"))
    errors, checked = check_numbers(root, spec)
    path_errors, paths = check_paths(root, docs)
    for e in errors + path_errors:
        print(e)
    print(f"check_numbers: {checked} numbers in {len(spec['checks'])} places, {paths} results/ paths; "
          f"{len(errors) + len(path_errors)} problems")
    return 1 if errors or path_errors else 0


if __name__ == "__main__":
    sys.exit(main())
