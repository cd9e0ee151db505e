#!/usr/bin/env python3
"""The development scene's moving work, measured offline from the engine's own W_s: per rebalancing event of a
run's trace.jsonl (any rank count; a one-rank run with decomposition.timing=modelled writes the raw W_s, the
engine's slice_workload), the I_global of a static P-rank partition fixed at the optimal partition of event 0's
W_s (the workload-aware start; of the uniform start with --initial uniform), its max/mean - 1, and the centre of
the per-slice work (sum s W_s / sum W_s, in slices and in rank slabs of slices/P). Usage:
    development_workload.py TRACE.jsonl OUT.csv [--ranks 4] [--initial workload|uniform]
prints the summary the issue asks for; exit 1 if a target fails (>= 100 events, mean I_global >= 10%, the work
centre moving >= 1 slab)."""
import argparse
import csv
import json
import sys


def shares(work, boundaries, ranks):
    """Work per rank for interior boundaries (slice indices, len ranks-1) over len(work) slices."""
    cuts = [0] + list(boundaries) + [len(work)]
    return [sum(work[cuts[r]:cuts[r + 1]]) for r in range(ranks)]


def optimal_partition(work, ranks, min_width):
    """Interior boundaries (slice indices) minimising the largest part over contiguous parts of >= min_width
    slices, as controllers/chains.cpp; among optimal ones, each boundary where the prefix is closest to its
    equal share k*total/P while the rest stays feasible (its tie rule). Exact: binary search over candidate
    sums. ValueError if ranks * min_width > len(work)."""
    S = len(work)
    if ranks * min_width > S:
        raise ValueError(f"{ranks} ranks of >= {min_width} slices do not fit {S} slices")
    prefix = [0.0]
    for w in work:
        prefix.append(prefix[-1] + w)

    def feasible_from(start, parts, bound):  # can [start, S) be split into `parts` parts of sum <= bound?
        if parts == 1:
            return S - start >= min_width and prefix[S] - prefix[start] <= bound
        for e in range(start + min_width, S - (parts - 1) * min_width + 1):
            if prefix[e] - prefix[start] > bound:
                break
            if feasible_from(e, parts - 1, bound):
                return True
        return False

    sums = sorted({prefix[j] - prefix[i] for i in range(S) for j in range(i + 1, S + 1)})
    lo, hi = 0, len(sums) - 1
    while lo < hi:
        mid = (lo + hi) // 2
        if feasible_from(0, ranks, sums[mid]):
            hi = mid
        else:
            lo = mid + 1
    bound, total, cuts, start = sums[lo], prefix[S], [], 0
    for k in range(1, ranks):
        best = None
        for e in range(start + min_width, S - (ranks - k) * min_width + 1):
            if prefix[e] - prefix[start] > bound:
                break
            if feasible_from(e, ranks - k, bound):
                d = abs(prefix[e] - k * total / ranks)
                if best is None or d < best[0]:
                    best = (d, e)
        cuts.append(best[1])
        start = best[1]
    return cuts


def uniform_partition(slices, ranks):
    return [round(k * slices / ranks) for k in range(1, ranks)]


def measure(events, ranks, initial):
    """Rows per event: I_global and max/mean - 1 of the static partition, the work centre."""
    first = events[0]
    S, min_width = first["slices"], first["min_width"]
    b = optimal_partition(first["slice_work"], ranks, min_width) if initial == "workload" else uniform_partition(S, ranks)
    rows = []
    for e in events:
        work = e["slice_work"]
        if len(work) != S:
            raise ValueError(f"event {e['event']}: {len(work)} slices, the first had {S}")
        s = shares(work, b, ranks)
        total = sum(work)
        mean = total / ranks
        centre = sum((i + 0.5) * w for i, w in enumerate(work)) / total
        rows.append({"event": e["event"], "total_work": total, "boundaries": " ".join(map(str, b)),
                     "imbalance": (max(s) - min(s)) / mean, "max_over_mean": max(s) / mean - 1,
                     "work_centre_slice": centre, "work_centre_slabs": centre / (S / ranks)})
    return rows


def main(argv):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("trace")
    p.add_argument("out")
    p.add_argument("--ranks", type=int, default=4)
    p.add_argument("--initial", choices=["workload", "uniform"], default="workload")
    a = p.parse_args(argv)
    with open(a.trace) as f:
        events = [json.loads(line) for line in f if line.strip()]
    if not events:
        print(f"{a.trace}: no events", file=sys.stderr)
        return 2
    rows = measure(events, a.ranks, a.initial)
    with open(a.out, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    mean = sum(r["imbalance"] for r in rows) / len(rows)
    c = [r["work_centre_slabs"] for r in rows]
    moved = c[-1] - c[0]
    print(f"events {len(rows)}  static ({a.initial} start, {a.ranks} ranks) mean I_global {100 * mean:.1f}%  "
          f"work centre {c[0]:.2f} -> {c[-1]:.2f} slabs (moved {moved:+.2f}; range {min(c):.2f}-{max(c):.2f})  "
          f"work x{rows[-1]['total_work'] / rows[0]['total_work']:.2f}")
    return 0 if len(rows) >= 100 and mean >= 0.10 and abs(moved) >= 1.0 else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
