#!/usr/bin/env python3
"""How well the per-slice work model predicts measured rank times, on every engine trace.jsonl under a folder.

For each event of a trace, on its recorded partition (`boundaries`, in force during the interval the `times`
measure), the predicted time of rank r is the sum of `slice_work` over r's slices. The engine scales the integer
work score W_s by one global factor per event (sum of slice_work == sum of times), so the model predicts how the
time is split between ranks, not the total: R^2 is taken around each event's mean rank time,
    R^2 = 1 - sum_(e,r) (T_er - P_er)^2 / sum_(e,r) (T_er - mean_r T_er)^2
(0: no better than "every rank takes the mean"), and the mean relative error is mean |P_er - T_er| / T_er.
Events whose times are all zero (a run's first event at step 0) are left out.
The run's `decomposition.timing` comes from the scene.yaml beside the trace: with `modelled`, times ARE the work
sums (R^2 = 1 by construction); such traces are listed but left out of the pooled rows. Committed traces (under
DIR/cpu, DIR/gpu) and the ones a fresh `make experiments` made are pooled apart: pooled_measured_committed and
pooled_measured.

Usage: trace_model.py --results DIR [--out CSV]   (every DIR/**/trace.jsonl; prints the table; CSV: one row per
trace and a pooled row per origin, trace=pooled_measured (fresh) / pooled_measured_committed). Exit 2 with FILE:LINE: field 'NAME': reason on a bad trace.
Python stdlib only (PyYAML is not needed: the timing key is read line by line).
"""
import argparse
import csv
import json
import math
import os
import re
import sys

COLUMNS = ["trace", "timing", "ranks", "slices", "events", "points", "r2", "mean_rel_error", "max_rel_error"]


class TraceError(Exception):
    pass


# Folders under a results folder that hold committed traces (results/cpu: the 2-core VM, results/gpu: H200s); every
# other trace there was made by this checkout's own `make experiments`. Pooled rows never mix the two.
COMMITTED = ("cpu", "gpu", "surrogate")


def origin(rel):
    """'committed' for a trace folder (relative to the results folder) under one of COMMITTED, else 'fresh'."""
    return "committed" if rel.replace(os.sep, "/").split("/", 1)[0] in COMMITTED else "fresh"


def find_traces(root):
    """Every file named trace.jsonl below root, sorted by path (as the replay_score runner does)."""
    found = []
    for d, _, files in os.walk(root, followlinks=True):
        if "trace.jsonl" in files:
            found.append(os.path.join(d, "trace.jsonl"))
    return sorted(found)


def scene_timing(folder):
    """decomposition.timing of the scene.yaml in folder ('measured' is the engine's default), or 'unknown'."""
    path = os.path.join(folder, "scene.yaml")
    if not os.path.exists(path):
        return "unknown"
    section = None
    with open(path) as f:
        for line in f:
            text = line.split("#", 1)[0].rstrip()
            if not text.strip():
                continue
            if not text[0].isspace():
                section = text.split(":", 1)[0].strip()
                flow = re.search(r"[{,]\s*timing:\s*([A-Za-z]+)", text)  # decomposition: {timing: modelled}
                if section == "decomposition" and flow:
                    return flow.group(1)
            elif section == "decomposition" and text.strip().startswith("timing:"):
                return text.split(":", 1)[1].strip().strip("'\"")
    return "measured"


def rank_sums(work, boundaries):
    """Sum of work over each rank's slices [b_{r-1}, b_r)."""
    cuts = [0] + list(boundaries) + [len(work)]
    return [math.fsum(work[a:b]) for a, b in zip(cuts, cuts[1:])]


def read_trace(path):
    """(line, event) per event of a trace.jsonl, each with boundaries, times, slice_work and slices consistent;
    TraceError naming FILE:LINE: field on bad input or an empty trace. Shared with scripts/development_workload.py."""
    out = []
    with open(path) as f:
        for n, text in enumerate(f, 1):
            if not text.strip():
                continue
            try:
                e = json.loads(text)
            except json.JSONDecodeError as err:
                raise TraceError(f"{path}:{n}: not JSON: {err}")
            for key in ("boundaries", "times", "slice_work", "slices"):
                if key not in e:
                    raise TraceError(f"{path}:{n}: field '{key}': missing")
            times, work, b = e["times"], e["slice_work"], e["boundaries"]
            if len(work) != e["slices"]:
                raise TraceError(f"{path}:{n}: field 'slice_work': {len(work)} entries but slices is {e['slices']}")
            if len(b) != len(times) - 1 or list(b) != sorted(b) or (b and (b[0] < 0 or b[-1] > len(work))):
                raise TraceError(f"{path}:{n}: field 'boundaries': not {len(times) - 1} sorted cuts in [0, {len(work)}]")
            out.append((n, e))
    if not out:
        raise TraceError(f"{path}: the trace has no events")
    return out


def read_events(path):
    """(line, slices, times, predicted) per event (read_trace's checks)."""
    return [(n, e["slices"], e["times"], rank_sums(e["slice_work"], e["boundaries"])) for n, e in read_trace(path)]


def score(events):
    """(points, R^2 around each event's mean, mean and max relative error); events with all-zero times skipped."""
    ss_res = ss_tot = 0.0
    rel = []
    for _, _, times, pred in events:
        if not any(times):
            continue
        mean = math.fsum(times) / len(times)
        for t, p in zip(times, pred):
            ss_res += (t - p) ** 2
            ss_tot += (t - mean) ** 2
            if t > 0:
                rel.append(abs(p - t) / t)
    r2 = 1 - ss_res / ss_tot if ss_tot > 0 else float("nan")
    return len(rel), r2, (sum(rel) / len(rel) if rel else float("nan")), (max(rel) if rel else float("nan"))


def fmt(x):
    """A CSV cell: floats to 6 significant digits (nan as "nan"), anything else as str."""
    return f"{x:.6g}" if isinstance(x, float) else str(x)


def write_csv(path, columns, rows):
    """Writes rows (dicts) under `columns` to path atomically (path.tmp, then renamed), LF line ends."""
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    with open(path + ".tmp", "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(columns)
        for r in rows:
            w.writerow([fmt(r[c]) for c in columns])
    os.replace(path + ".tmp", path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    ap.add_argument("--results", required=True, help="folder searched for trace.jsonl files")
    ap.add_argument("--out", help="CSV to write (atomically)")
    a = ap.parse_args()
    if not os.path.isdir(a.results):
        print(f"--results: '{a.results}' is not a folder", file=sys.stderr)
        return 2
    rows, pooled = [], {"fresh": [], "committed": []}
    try:
        for path in find_traces(a.results):
            events = read_events(path)
            folder = os.path.dirname(path)
            timing = scene_timing(folder)
            points, r2, mre, mx = score(events)
            rows.append({"trace": os.path.relpath(folder, a.results), "timing": timing, "ranks": len(events[0][2]),
                         "slices": events[0][1], "events": len(events), "points": points, "r2": r2,
                         "mean_rel_error": mre, "max_rel_error": mx})
            if timing == "measured":
                pooled[origin(rows[-1]["trace"])] += events
    except TraceError as err:
        print(err, file=sys.stderr)
        return 2
    if not rows:
        print(f"--results: no trace.jsonl under '{a.results}'", file=sys.stderr)
        return 2
    for kind, name in (("fresh", "pooled_measured"), ("committed", "pooled_measured_committed")):
        if pooled[kind]:
            points, r2, mre, mx = score(pooled[kind])
            rows.append({"trace": name, "timing": "measured", "ranks": "", "slices": "", "events": len(pooled[kind]),
                         "points": points, "r2": r2, "mean_rel_error": mre, "max_rel_error": mx})
    for r in rows:
        print(" ".join(f"{k}={fmt(r[k])}" for k in COLUMNS))
    if a.out:
        write_csv(a.out, COLUMNS, rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
