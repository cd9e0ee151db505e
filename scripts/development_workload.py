#!/usr/bin/env python3
"""The development scene's moving work, read from the trace.jsonl of a P-rank run of the scene with
`decomposition.policy=static` and `decomposition.timing=modelled`: the engine itself chose the workload-aware
start (controllers' optimal_partition of event 0's W_s) and its modelled rank times are the sums of W_s over
each rank's slices, so nothing is recomputed here. Per event: the static partition's I_global (the trace's
times), max/mean - 1, and the centre of the per-slice work (sum s W_s / sum W_s, in slices and in rank slabs
of slices/P). Usage:
    development_workload.py TRACE.jsonl OUT.csv
prints the summary the issue asks for; exit 1 if a target fails (>= 100 events, mean I_global >= 10%, the work
centre moving >= 1 slab), 2 on a malformed trace (naming file and line)."""
import argparse
import csv
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "analysis"))
from trace_model import TraceError, read_trace  # noqa: E402  (the one trace reader)


def measure(events):
    """Rows per event: I_global and max/mean - 1 of the recorded partition, the work centre."""
    rows = []
    for n, e in events:
        work, times = e["slice_work"], e["times"]
        ranks = len(times)
        mean = sum(times) / ranks
        total = sum(work)
        centre = sum((i + 0.5) * w for i, w in enumerate(work)) / total
        rows.append({"event": e["event"], "total_work": total, "boundaries": " ".join(map(str, e["boundaries"])),
                     "imbalance": (max(times) - min(times)) / mean, "max_over_mean": max(times) / mean - 1,
                     "work_centre_slice": centre, "work_centre_slabs": centre / (len(work) / ranks)})
    return rows


def main(argv):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("trace")
    p.add_argument("out")
    a = p.parse_args(argv)
    try:
        events = read_trace(a.trace)
        if len(events[0][1]["times"]) < 2:
            raise TraceError(f"{a.trace}:{events[0][0]}: field 'times': a trace of at least 2 ranks is needed")
    except (TraceError, OSError) as err:
        print(f"development_workload.py: {err}", file=sys.stderr)
        return 2
    rows = measure(events)
    with open(a.out, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]), lineterminator="\n")
        w.writeheader()
        w.writerows(rows)
    mean = sum(r["imbalance"] for r in rows) / len(rows)
    c = [r["work_centre_slabs"] for r in rows]
    moved = c[-1] - c[0]
    print(f"events {len(rows)}  ranks {len(events[0][1]['times'])}  mean I_global {100 * mean:.1f}%  "
          f"work centre {c[0]:.2f} -> {c[-1]:.2f} slabs (moved {moved:+.2f}; range {min(c):.2f}-{max(c):.2f})  "
          f"work x{rows[-1]['total_work'] / rows[0]['total_work']:.2f}")
    return 0 if len(rows) >= 100 and mean >= 0.10 and abs(moved) >= 1.0 else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
