"""Summarises an Nsight Compute source page (`ncu --page source --csv --print-source sass`) by basic block.

Usage: /usr/bin/python3 analysis/ncu_blocks.py SOURCE.csv [TOP]
Instructions of one basic block run equally often, so they are grouped by their "Instructions Executed" count;
each line gives a block's executions (warp-level), its SASS instructions, its share of the kernel's executed
instructions and of the warp-stall samples, and its average active threads per warp (of 32). Used for
results/gpu/ncu_forces_binned (docs/performance.md "Profiling the force kernel"). Exit code 2 on a file that is
not such a page.
"""
import collections
import csv
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sections.common import md_table  # noqa: E402


def blocks(path):
    """[(executions, instructions, instr_share, sample_share, threads)] by decreasing instruction share."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if len(rows) < 3 or "Instructions Executed" not in rows[1]:
        raise ValueError(f"{path}: line 2: no 'Instructions Executed' column (not an ncu source page)")
    head, data = rows[1], rows[2:]
    ix, th = head.index("Instructions Executed"), head.index("Avg. Threads Executed")
    sa = head.index("Warp Stall Sampling (All Samples)")
    total = sum(int(r[ix]) for r in data)
    samples = sum(int(r[sa]) for r in data)
    groups = collections.defaultdict(lambda: [0, 0, 0, set()])
    for r in data:
        e = int(r[ix])
        if e:
            g = groups[e]
            g[0] += e
            g[1] += int(r[sa])
            g[2] += 1
            g[3].add(r[th])
    out = [(e, n, s / total, a / max(samples, 1), "/".join(sorted(t))) for e, (s, a, n, t) in groups.items()]
    return total, sorted(out, key=lambda b: -b[2])


def main():
    if len(sys.argv) not in (2, 3):
        print(__doc__.strip().splitlines()[2], file=sys.stderr)
        return 2
    try:
        total, rows = blocks(sys.argv[1])
    except (OSError, ValueError) as e:
        print(f"ncu_blocks: {e}", file=sys.stderr)
        return 2
    top = int(sys.argv[2]) if len(sys.argv) == 3 else 6
    print(f"{sys.argv[1]}: {total:,} warp-level instructions executed")
    print(md_table(["executions", "SASS instructions", "share of instructions", "share of stall samples", "active threads"],
                   [(f"{e / 1e6:.1f}M", n, f"{100 * si:.1f}%", f"{100 * ss:.1f}%", t) for e, n, si, ss, t in rows[:top]],
                   align="rrrrr"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
