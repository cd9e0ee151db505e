#!/usr/bin/env python3
"""Tables scripts/gpu/before_after.sh's outputs: per kernel (bench engine, SEMLB_OPENCL_PROFILE=1) and per cell-stage
part (bench cells), the old and new ms (mean over rounds, with the rounds' min-max spread) and new / old.
Usage: before_after.py OUT   (reads OUT/{engine,cells}_{old,new}_{round}.txt; prints CSV on stdout)."""
import glob
import os
import re
import sys


def parse(path):
    """{(what, run, name): ms} from one bench output file (run: "float skin 0.50" for bench engine, the precision for
    bench cells)."""
    out, precision = {}, None
    what = "engine" if os.path.basename(path).startswith("engine") else "cells"
    for line in open(path):
        f = line.split()
        if what == "engine" and len(f) > 7 and f[0].startswith("opencl") and f[1] in ("float", "double"):
            precision = f"{f[1]} skin {f[7]}"
            out[(what, precision, "ms/step")] = float(f[6])
        elif what == "engine" and len(f) == 4 and f[0] == "kernel":
            out[(what, precision, f[1])] = float(f[2])
        elif what == "cells" and f and f[0].startswith("opencl"):
            precision = f[1].rstrip(",")
        elif what == "cells" and len(f) >= 2 and f[0] in ("stage", "grid", "total"):
            out[(what, precision, f[0])] = float(f[1])
    return out


def main():
    out = sys.argv[1]
    runs = {"old": [], "new": []}
    for path in sorted(glob.glob(os.path.join(out, "*_*_*.txt"))):
        m = re.match(r"(engine|cells)_(old|new)_(\d+)\.txt$", os.path.basename(path))
        if m:
            runs[m.group(2)].append(parse(path))
    keys = sorted({k for r in runs["old"] + runs["new"] for k in r})
    print("what,run,name,old_ms,old_min,old_max,new_ms,new_min,new_max,new_over_old,rounds")
    for k in keys:
        old = [r[k] for r in runs["old"] if k in r]
        new = [r[k] for r in runs["new"] if k in r]
        if not old or not new:
            continue
        mo, mn = sum(old) / len(old), sum(new) / len(new)
        ratio = mn / mo if mo > 0 else float("nan")
        print(f"{k[0]},{k[1]},{k[2]},{mo:.4f},{min(old):.4f},{max(old):.4f},{mn:.4f},{min(new):.4f},{max(new):.4f},"
              f"{ratio:.4f},{min(len(old), len(new))}")


if __name__ == "__main__":
    main()
