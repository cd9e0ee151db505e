#!/usr/bin/env python3
"""The development scene's moving work, from a decomposed run's trace.jsonl: per rebalancing event the modelled
imbalance of the run's boundaries (max rank share of slice_work / mean - 1), the measured imbalance (times) and
the centre of the per-slice work (in slices and in rank slabs). Usage:
    development_workload.py TRACE.jsonl OUT.csv   (prints the summary the issue asks for; exit 1 if it fails)"""
import csv
import json
import sys


def shares(work, boundaries, ranks):
    """Work per rank for interior boundaries (slice indices, len ranks-1) over len(work) slices."""
    cuts = [0] + list(boundaries) + [len(work)]
    return [sum(work[cuts[r]:cuts[r + 1]]) for r in range(ranks)]


def main(trace, out):
    rows = []
    with open(trace) as f:
        for line in f:
            if not line.strip():
                continue
            e = json.loads(line)
            work, times, b = e["slice_work"], e["times"], e["boundaries"]
            P = len(times)
            s = shares(work, b, P)
            total = sum(work)
            centre = sum((i + 0.5) * w for i, w in enumerate(work)) / total
            rows.append({"event": e["event"], "total_work": total,
                         "modelled_imbalance": max(s) / (total / P) - 1,
                         "measured_imbalance": max(times) / (sum(times) / P) - 1 if sum(times) > 0 else 0.0,
                         "work_centre_slice": centre, "work_centre_slabs": centre / (len(work) / P)})
    with open(out, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    mean_mod = sum(r["modelled_imbalance"] for r in rows) / len(rows)
    mean_meas = sum(r["measured_imbalance"] for r in rows) / len(rows)
    c = [r["work_centre_slabs"] for r in rows]
    moved = max(c) - min(c)
    print(f"events {len(rows)}  mean modelled imbalance {100 * mean_mod:.1f}%  mean measured imbalance "
          f"{100 * mean_meas:.1f}%  work centre range {min(c):.2f}-{max(c):.2f} slabs (moved {moved:.2f} slabs)")
    return 0 if len(rows) >= 100 and mean_mod >= 0.10 and moved >= 1.0 else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
