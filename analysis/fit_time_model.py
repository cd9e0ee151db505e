#!/usr/bin/env python3
"""Fits the replay time model (surrogate/workload_replay.hpp) to measured multi-GPU engine runs, and its error on runs
it was not fitted on.

Model, per event e and rank r (slice_work as the engine's trace holds it: W_s scaled so that it sums to the event's rank
times): T_er = a_e * s_r * (W_er + g * B_er), where W_er is the work of r's slices, B_er the work of the `band` slices on
the far side of each of r's interior boundaries (the ghost elements it receives, in work units; `band` = the ghost reach
in slices), s_r a fixed per-rank speed factor, a_e the event's scale. On two ranks only the ratio s_1/s_0 is seen:
    log(T_e1 / T_e0) = log(s_1 / s_0) + log((W_e1 + g B_e1) / (W_e0 + g B_e0)) + noise.
g is chosen on a grid (0..3, step 0.005) as the value whose leave-one-run-out prediction error is lowest (with one run: the
least-squares value), and likewise whether log(s_1/s_0) is fitted (closed form for each g) or 0; the jitter is the residual std
of the log ratio / sqrt(2) (one independent relative error per rank); speed_spread = |s_1/s_0 - 1| / 2 (a factor
1 -+ spread on the two ranks). The migration cost per slice is the least-squares slope of the slowest rank's migrate_s
against the slices moved at the interval's end (rank_times.csv), over every interval of the fitted runs.

Error on runs it was not fitted on (leave one run out): for each run, the model fitted on the others predicts its rank
times (a_e chosen so that the prediction sums to the measured total, as trace_model.py does); the mean relative error
|P_er - T_er| / T_er is reported beside that of the plain work model (g = 0, s_r = 1).

Usage: fit_time_model.py --runs DIR [DIR ...] --out CSV [--band SLICES]  (each DIR holds trace.jsonl and
rank_times.csv of one measured multi-rank run; exit 2 with FILE:LINE: field 'NAME': reason on bad input).
"""
import argparse
import csv
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from trace_model import TraceError, fmt, rank_sums, read_trace, write_csv  # noqa: E402

COLUMNS = ["run", "fitted_on", "events", "ghost_weight", "speed_ratio", "speed_spread", "jitter",
           "migrate_s_per_slice", "mean_rel_error", "mean_rel_error_work_only"]


def band_work(work, boundaries, band):
    """Per rank: the work of the `band` slices beyond each of its interior boundaries (what it receives as ghosts)."""
    out = [0.0] * (len(boundaries) + 1)
    for k, b in enumerate(boundaries):
        out[k] += math.fsum(work[b:b + band])          # rank k (below the boundary) receives the slices above it
        out[k + 1] += math.fsum(work[max(0, b - band):b])  # rank k + 1 receives those below
    return out


def read_run(folder, band):
    """Events (times, W_r, B_r) of a measured 2-rank run with all times positive, and (moved, migrate_s) per interval."""
    path = os.path.join(folder, "trace.jsonl")
    events = []
    for n, e in read_trace(path):
        if len(e["times"]) != 2:
            raise TraceError(f"{path}:{n}: field 'times': the fit needs 2-rank runs, got {len(e['times'])} ranks")
        if min(e["times"]) <= 0:
            continue
        events.append((e["times"], rank_sums(e["slice_work"], e["boundaries"]),
                       band_work(e["slice_work"], e["boundaries"], band)))
    if not events:
        raise TraceError(f"{path}: no event with measured times")
    rt = os.path.join(folder, "rank_times.csv")
    per_step = {}
    with open(rt) as f:
        for n, row in enumerate(csv.DictReader(f), 2):
            try:
                step, moved, mig = int(row["step"]), int(row["moved_slices"]), float(row["migrate_s"])
            except (KeyError, ValueError) as err:
                raise TraceError(f"{rt}:{n}: field 'migrate_s': {err}")
            m = per_step.setdefault(step, [moved, 0.0])
            m[1] = max(m[1], mig)
    return events, list(per_step.values())


def log_ratio(times, w, b, g):
    return math.log(times[1] / times[0]) - math.log((w[1] + g * b[1]) / (w[0] + g * b[0]))


def fit_speed(events, g):
    """(log speed ratio, residual sum of squares) of the log-ratio model at ghost weight g."""
    r = [log_ratio(t, w, b, g) for t, w, b in events]
    mu = math.fsum(r) / len(r)
    return mu, math.fsum((x - mu) ** 2 for x in r)


def migration_slope(runs):
    """Least-squares seconds per slice moved (slowest rank's migrate_s against moved slices), >= 0."""
    pts = np.asarray([p for _, mig in runs for p in mig], dtype=float)
    if len(pts) < 2 or np.ptp(pts[:, 0]) == 0:
        return 0.0
    return max(0.0, float(np.polyfit(pts[:, 0], pts[:, 1], 1)[0]))


GRID = [0.005 * i for i in range(601)]


def fit(runs):
    """(g, log speed ratio, jitter, migration s per slice) over the events and intervals of `runs`. With several runs, g is
    the grid value with the lowest leave-one-run-out error (the ghost term must predict runs it was not fitted on);
    with one, the least-squares value."""
    events = [e for ev, _ in runs for e in ev]
    if len(runs) > 1:
        def loo(choice):
            g, speed = choice
            errs = []
            for i, (held, _) in enumerate(runs):
                mu = fit_speed([e for j, (ev, _) in enumerate(runs) if j != i for e in ev], g)[0] if speed else 0.0
                errs.append(rel_error(held, g, mu))
            return math.fsum(errs) / len(errs)
        g, speed = min([(x, sp) for x in GRID for sp in (False, True)], key=loo)
    else:
        g, speed = min(GRID, key=lambda x: fit_speed(events, x)[1]), True
    mu, ss = fit_speed(events, g)
    if not speed:  # equal speeds predict held-out runs better than a fitted ratio
        mu = 0.0
        ss = math.fsum(log_ratio(t, w, b, g) ** 2 for t, w, b in events)
    jitter = math.sqrt(ss / max(1, len(events) - 2)) / math.sqrt(2)
    return g, mu, jitter, migration_slope(runs)


def rel_error(events, g, mu):
    """Mean |P - T| / T with P = a_e s_r (W + g B), a_e making sum P = sum T."""
    s = [1.0, math.exp(mu)]
    errs = []
    for t, w, b in events:
        raw = [s[r] * (w[r] + g * b[r]) for r in range(2)]
        a = math.fsum(t) / math.fsum(raw)
        errs += [abs(a * raw[r] - t[r]) / t[r] for r in range(2)]
    return math.fsum(errs) / len(errs)


def main():
    ap = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    ap.add_argument("--runs", nargs="+", required=True, help="folders of measured 2-rank runs")
    ap.add_argument("--out", required=True, help="CSV to write (atomically)")
    ap.add_argument("--band", type=int, default=4, help="ghost reach in slices (cutoff * 1.01 / slice width; default 4)")
    a = ap.parse_args()
    if a.band < 0:
        print(f"--band: must be >= 0, got {a.band}", file=sys.stderr)
        return 2
    try:
        runs = {os.path.normpath(d): read_run(d, a.band) for d in a.runs}
    except (TraceError, OSError) as err:
        print(err, file=sys.stderr)
        return 2
    rows = []
    names = sorted(runs)
    g, mu, jitter, mig = fit([runs[n] for n in names])
    rows.append({"run": "all", "fitted_on": len(names), "events": sum(len(runs[n][0]) for n in names),
                 "ghost_weight": g, "speed_ratio": math.exp(mu), "speed_spread": abs(math.exp(mu) - 1) / 2, "jitter": jitter,
                 "migrate_s_per_slice": mig,
                 "mean_rel_error": float("nan"), "mean_rel_error_work_only": float("nan")})
    if len(names) > 1:
        for held in names:
            others = [runs[n] for n in names if n != held]
            g_o, mu_o, jit_o, mig_o = fit(others)
            ev = runs[held][0]
            rows.append({"run": held, "fitted_on": len(others), "events": len(ev), "ghost_weight": g_o,
                         "speed_ratio": math.exp(mu_o), "speed_spread": abs(math.exp(mu_o) - 1) / 2, "jitter": jit_o,
                         "migrate_s_per_slice": mig_o, "mean_rel_error": rel_error(ev, g_o, mu_o),
                         "mean_rel_error_work_only": rel_error(ev, 0.0, 0.0)})
    for r in rows:
        print(" ".join(f"{k}={fmt(r[k])}" for k in COLUMNS))
    write_csv(a.out, COLUMNS, rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
