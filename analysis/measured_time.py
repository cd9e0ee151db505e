#!/usr/bin/env python3
"""Measured GPU time (docs/measured_time.md): the tables of scripts/gpu/measured_time.sh's runs.

Usage: measured_time.py RUNS OUT [--semlb SEMLB] [--scene NAME] [--nvlink-gbs 450] [--seeds 0-2] [--no-replay]
       measured_time.py --combine ROOT   (ROOT/SCENE/*.csv of several scenes into ROOT/*.csv)
       measured_time.py --check-regions FILE... [--limit 3]   (exit 1 naming the file, event and region when a region's
                        timed pair forces are more than LIMIT times the median region's, per unit of W_s: another
                        job's device work overlapped the timed launch; scripts/gpu/workload_library.sh runs it)

RUNS is the script's OUT folder (tissue/, cost/, turns/, record/, e2e/); OUT receives:
- timer_cost.csv: the loop's wall seconds with decomposition.timing measured and device, per round;
- turns_validation.csv: per interval, the sum of the P ranks' device seconds against one rank's (the difference is
  the ghost work and the per-rank launches), and each slab of the 2-rank run against the same slab alone;
- time_model_validation.csv: per end-to-end run, the mean absolute relative error of the per-rank interval times that
  the time model predicts from the recorded workload (record/workload.h5: measured seconds per slice) under the
  run's own boundaries, against its device timers; ghost_weight, element_s, list_weight, list_element_weight and
  rank_overhead_s (surrogate/workload_replay.hpp, list_by=work) are fitted (non-negative least squares) on
  the runs marked fitted (launch 1 of static at every P) and the error of the others is out of sample;
- policy_order.csv: per P, each policy's mean measured loop seconds and its replayed loop seconds (`semlb replay
  --workload record/workload.h5` with the fitted model, seeds averaged), with both ranks;
- end_to_end.csv: one row per launch (scene, policy, ranks, launch, mean_imbalance, migration, loop_s, compute_s,
  exchange_s, migrate_s, migrate_measured_s, ideal_s): the device-timed imbalance, the slices moved, and the projected
  loop time (sum over intervals of the slowest rank's device seconds, plus the ghost bands' and migrating cells' bytes
  over the stated NVLink bandwidth);
- end_to_end_summary.csv: per (policy, ranks) the mean over launches and the 95% Student-t interval, and static minus
  the policy's loop time with its interval;
- parts_additivity.csv (runs with rank_times.csv's device_PART_s): per run and part of the device time (pair
  forces, list builds, cell stage, other), the ranks' sum against the one-rank recording's, and the error of each
  rank's part predicted from its share of the elements (which part the time model's spreading by elements misses);
- migration_cost.csv: the measured migration seconds (wall, the slowest rank) of each interval that moved slices;
  migration_fit.csv: the least-squares line through them (seconds per slice moved, per interval, over how many).
Needs numpy, scipy and h5py (Debian's python3-numpy, python3-scipy, python3-h5py).
"""
import argparse
import csv
import json
import os
import subprocess
import sys

import h5py
import numpy as np
from scipy import optimize, stats


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def write_csv(path, header, rows):
    """Rows (sequences in header order) to PATH, written to PATH.tmp then renamed."""
    with open(path + ".tmp", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        for r in rows:
            w.writerow([f"{v:.6g}" if isinstance(v, float) else v for v in r])
    os.replace(path + ".tmp", path)


def rank_times(run):
    """{step: [row of rank 0, row of rank 1, ...]} of RUN/rank_times.csv, numbers as floats."""
    out = {}
    for r in read_csv(os.path.join(run, "rank_times.csv")):
        out.setdefault(int(r["step"]), {})[int(r["rank"])] = {k: float(v) for k, v in r.items()}
    return {s: [v[q] for q in sorted(v)] for s, v in sorted(out.items())}


def trace_boundaries(run):
    """{step: boundaries in force during the interval ending there}: RUN/trace.jsonl's events in order (or
    boundaries.jsonl's, the committed runs' traces reduced to event, boundaries, decision, times), matched to
    RUN/rank_times.csv's steps in order (a run from a restarted state numbers its events from 0)."""
    path = os.path.join(run, "trace.jsonl")
    if not os.path.exists(path):
        path = os.path.join(run, "boundaries.jsonl")
    with open(path) as f:
        events = sorted((json.loads(line) for line in f if line.strip()), key=lambda e: e["event"])
    return {step: e["boundaries"] for step, e in zip(rank_times(run), events)}


def loop_seconds(run, nvlink_gbs):
    """The projected loop of one run: per interval the slowest rank's device seconds, the ghost bytes and migration
    bytes of the busiest sender over NVLink, and the measured migration wall seconds (the slowest rank)."""
    rt = rank_times(run)
    bw = nvlink_gbs * 1e9
    compute = exchange = migrate = measured = ideal = 0.0
    imbalance, moved = [], 0
    for step, rows in rt.items():
        d = np.array([r["device_s"] for r in rows])
        compute += d.max()
        ideal += d.mean()
        imbalance.append((d.max() - d.min()) / d.mean() if d.mean() > 0 else 0.0)
        exchange += max(r["exchange_bytes"] for r in rows) / bw
        migrate += max(r["migrate_bytes"] for r in rows) / bw
        measured += max(r["migrate_s"] for r in rows)
        moved += int(rows[0]["moved_slices"])
    return {"mean_imbalance": float(np.mean(imbalance)), "migration": moved, "compute_s": compute, "exchange_s": exchange,
            "migrate_s": migrate, "migrate_measured_s": measured, "ideal_s": ideal,
            "loop_s": compute + exchange + migrate}


def bits(mask):
    """The set bits of a non-negative integer mask (a slice's cell-stage or list-trigger bits)."""
    return bin(int(mask)).count("1")


class Workload:
    """The measured workload's per-event arrays (controllers/workload.hpp), by step."""

    def __init__(self, path):
        with h5py.File(path, "r") as f:
            if "events/slice_seconds" not in f:
                sys.exit(f"measured_time.py: {path}: field 'slice_seconds': missing (record with decomposition.timing: device)")
            e = f["events"]
            self.steps = [int(s) for s in e["step"][:]]
            self.seconds = e["slice_seconds"][:]
            self.below = e["band_below"][:].astype(float)
            self.above = e["band_above"][:].astype(float)
            self.elements = e["elements"][:].astype(float)
            self.slice_elements = e["slice_elements"][:].astype(float) if "slice_elements" in e else None
            self.work = e["slice_work"][:].astype(float) if "slice_work" in e else None
            # version 3: the list builds leave the slices and go to the ranks whose slices changed (the replay's
            # model_times, surrogate/workload_replay.hpp)
            self.list_s = e["part_seconds"][:, 1] if "part_seconds" in e else None
            self.changes = e["cell_stage_changes"][:] if "cell_stage_changes" in e else None
            # version 4: the one rank's list builds and, per slice, the builds its elements triggered (list_by=triggers)
            self.builds = e["list_builds"][:] if "list_triggers" in e else None
            self.triggers = e["list_triggers"][:] if "list_triggers" in e else None
        self.at = {s: i for i, s in enumerate(self.steps)}

    def terms(self, step, boundaries):
        """Per rank the columns of the time model (surrogate/workload_replay.hpp, list_by=work): S_r (its slices'
        measured seconds, less the one-rank list builds spread by elements in version 3), sigma G_r (seconds per
        element x ghost elements received), n_r (its elements, version 3) and L Wch_r / W (the list seconds placed by
        the W_s of its slices that changed at a cell stage, version 3; in version 4, list_by=triggers: L b_r / k W_r / W,
        b_r the builds its slices' triggers and cell stages claim, capped at the one rank's k), and L n_r / N (the list
        seconds by its elements: every slab rank rebuilds at about the one rank's rate); the last three are 0 for a
        version 2 file."""
        i = self.at[step]
        cuts = [0] + list(boundaries) + [self.seconds.shape[1]]
        sigma = self.seconds[i].sum() / self.elements[i] if self.elements[i] > 0 else 0.0
        seconds = self.seconds[i]
        n = self.slice_elements[i] if self.list_s is not None else np.zeros(len(seconds))
        spread = self.list_s[i] * n / n.sum() if n.sum() > 0 else np.zeros(len(seconds))  # the list seconds by elements
        seconds = np.maximum(0.0, seconds - spread)
        v3 = self.list_s is not None
        changed = self.work[i] * (self.changes[i] != 0) if v3 else np.zeros(len(seconds))
        total_work = self.work[i].sum() if v3 else 0.0
        rows = []
        for q in range(len(cuts) - 1):
            lo, hi = cuts[q], cuts[q + 1]
            g = (self.below[i][lo - 1] if q > 0 else 0.0) + (self.above[i][hi - 1] if q + 2 < len(cuts) else 0.0)
            if self.triggers is not None:
                k = int(self.builds[i])
                own = min(k, bits(np.bitwise_or.reduce(self.triggers[i][lo:hi])) +
                          bits(np.bitwise_or.reduce(self.changes[i][lo:hi])))
                placed = (self.list_s[i] * own / k * self.work[i][lo:hi].sum() / total_work
                          if k > 0 and total_work > 0 else 0.0)
            else:
                placed = self.list_s[i] * changed[lo:hi].sum() / total_work if total_work > 0 else 0.0
            rows.append((seconds[lo:hi].sum(), sigma * g, n[lo:hi].sum(), placed, spread[lo:hi].sum()))
        return np.array(rows)


# The fitted parameters of the time model, in the order of Workload.terms' columns after the first (the constant
# rank_overhead_s last): surrogate/workload_replay.hpp's keys.
MODEL_KEYS = ("ghost_weight", "element_s", "list_weight", "list_element_weight", "rank_overhead_s")
TERMS = len(MODEL_KEYS) - 1  # the columns of Workload.terms after S_r; model_rows appends the measured seconds


PARTS = ("pair", "list", "cells")


def parts_rows(workload, record, runs, scene):
    """Per run and part of the device time (rank_times.csv's device_PART_s, and other = the rest): the P ranks' sum
    against the one-rank recording's over the intervals both have (additivity), and the mean absolute relative error
    of each rank's part predicted as the recording's part times the rank's share of the elements."""
    if workload.slice_elements is None or not os.path.exists(os.path.join(record, "rank_times.csv")):
        return []
    one = rank_times(record)
    if not one or "device_pair_s" not in next(iter(one.values()))[0]:
        return []
    def part(r, name):
        return r["device_s"] - sum(r[f"device_{p}_s"] for p in PARTS) if name == "other" else r[f"device_{name}_s"]
    out = []
    for policy, ranks, launch, d in runs:
        rt, bounds = rank_times(d), trace_boundaries(d)
        if "device_pair_s" not in next(iter(rt.values()))[0]:
            continue
        for name in PARTS + ("other",):
            total = single = 0.0
            errors = []
            for step, rs in rt.items():
                if step not in one or step not in workload.at or step not in bounds:
                    continue
                i = workload.at[step]
                n = workload.slice_elements[i]
                cuts = [0] + list(bounds[step]) + [len(n)]
                ref = part(one[step][0], name)
                total += sum(part(r, name) for r in rs)
                single += ref
                for q, r in enumerate(rs):
                    m = part(r, name)
                    if m > 0:
                        errors.append(abs(ref * n[cuts[q]:cuts[q + 1]].sum() / n.sum() - m) / m)
            if single > 0:
                out.append((scene, policy, ranks, launch, name, total, single, total / single - 1,
                            float(np.mean(errors)) if errors else float("nan")))
    return out


def model_rows(workload, run):
    """Workload.terms' columns and the measured device seconds, per interval and rank of RUN whose step the workload has."""
    rt, bounds = rank_times(run), trace_boundaries(run)
    rows = []
    for step, rs in rt.items():
        if step not in workload.at or step not in bounds:
            continue
        terms = workload.terms(step, bounds[step])
        for q, r in enumerate(rs):
            rows.append(tuple(terms[q]) + (r["device_s"],))
    return np.array(rows)


def fit_time_model(rows):
    """Non-negative least squares (scipy.optimize.nnls) of T - S_r = ghost_weight sigma G_r + element_s n_r +
    list_weight L Wch_r / W + list_element_weight L n_r / N + rank_overhead_s: {MODEL_KEYS: value}. A column that is 0
    throughout (a version 2 file has no elements per slice and no list seconds) is left out and its key set to 0."""
    columns = np.column_stack([rows[:, 1:1 + TERMS], np.ones(len(rows))])
    used = [k for k in range(columns.shape[1]) if np.any(columns[:, k] != 0)]
    coef, _ = optimize.nnls(columns[:, used], rows[:, -1] - rows[:, 0])
    out = dict.fromkeys(MODEL_KEYS, 0.0)
    for k, c in zip(used, coef):
        out[MODEL_KEYS[k]] = float(c)
    return out


def predict(rows, model):
    """The time model's seconds of model_rows' rows."""
    return rows[:, 0] + sum(model[k] * rows[:, j + 1] for j, k in enumerate(MODEL_KEYS[:TERMS])) + model["rank_overhead_s"]


def interval95(values):
    """Mean and the half-width of its 95% Student-t interval (0 for one value)."""
    v = np.asarray(values, dtype=float)
    if len(v) < 2:
        return float(v.mean()), 0.0
    return float(v.mean()), float(stats.t.ppf(0.975, len(v) - 1) * v.std(ddof=1) / np.sqrt(len(v)))


def e2e_runs(runs_dir):
    """(policy, ranks, launch, folder) of every finished e2e run, named POLICY_npP_lL by measured_time.sh."""
    out = []
    d = os.path.join(runs_dir, "e2e")
    for name in sorted(os.listdir(d)) if os.path.isdir(d) else []:
        if not os.path.exists(os.path.join(d, name, "rank_times.csv")):
            continue
        policy, np_, launch = name.rsplit("_", 2)
        out.append((policy, int(np_[2:]), int(launch[1:]), os.path.join(d, name)))
    return out


def combine(root):
    """ROOT/end_to_end.csv, end_to_end_summary.csv and time_model_validation.csv: the rows of every scene's folder
    (ROOT/SCENE/NAME.csv, written by a run of this script each) in one file, scenes in name order."""
    scenes = sorted(d for d in os.listdir(root) if os.path.isdir(os.path.join(root, d)) and d != "runs")
    for name in ("end_to_end.csv", "end_to_end_summary.csv", "time_model_validation.csv"):
        header, rows = None, []
        for sc in scenes:
            path = os.path.join(root, sc, name)
            if os.path.exists(path):
                with open(path, newline="") as f:
                    r = list(csv.reader(f))
                header = header or r[0]
                rows += r[1:]
        if header:
            write_csv(os.path.join(root, name), header, rows)


def region_outliers(path, limit):
    """(event, region, ratio to the median region) of every timed region of a measured workload whose pair-force
    seconds per unit of W_s exceed `limit` times the event's median region (the regions as the engine cuts them:
    contiguous slices of about equal elements, distributed.cpp measured_slice_seconds)."""
    with h5py.File(path, "r") as f:
        if "events/slice_seconds" not in f:
            return []
        K = int(f.attrs["cost_regions"])
        e = f["events"]
        seconds, work = e["slice_seconds"][:], e["slice_work"][:].astype(float)
        n, interval = e["slice_elements"][:].astype(float), e["interval_s"][:]
        pair = e["part_seconds"][:, 0] if "part_seconds" in e else None
    out = []
    for i in range(len(seconds)):
        total = n[i].sum()
        if total <= 0:
            continue
        mid = np.cumsum(n[i]) - n[i] / 2
        region = np.minimum(K - 1, (mid * K / total).astype(int))
        # the pair forces alone where the file has the parts (the rest was spread by elements)
        s = seconds[i] - (interval[i] - pair[i]) * n[i] / total if pair is not None else seconds[i]
        per = [(s[region == k].sum(), work[i][region == k].sum()) for k in range(K)]
        ratio = np.array([a / w if w > 0 else np.nan for a, w in per])
        med = np.nanmedian(ratio)
        for k, r in enumerate(ratio):
            if med > 0 and np.isfinite(r) and r > limit * med:
                out.append((i, k, float(r / med)))
    return out


def limit_value(text):
    """--limit: a finite number above 1 (argparse type)."""
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a number")
    if not (np.isfinite(v) and v > 1):
        raise argparse.ArgumentTypeError(f"{text} must be a finite number above 1")
    return v


def check_regions(args):
    """Exit status of --check-regions: 0 when every file passes, 1 when one has an outlier region (one line each on
    stderr), 2 for a file that cannot be read as a measured workload (one line naming it)."""
    ap = argparse.ArgumentParser(prog="measured_time.py --check-regions")
    ap.add_argument("files", nargs="+")
    ap.add_argument("--limit", type=limit_value, default=3.0)
    a = ap.parse_args(args)
    bad = 0
    for path in a.files:
        try:
            found = region_outliers(path, a.limit)
        except (OSError, KeyError, TypeError, ValueError) as err:
            print(f"{path}: not a measured workload file ({type(err).__name__}: {err})", file=sys.stderr)
            return 2
        if found:
            event, region, r = found[0]
            print(f"{path}: field 'slice_seconds': event {event}: region {region} timed {r:.1f}x the median region per "
                  f"unit of W_s ({len(found)} such regions): another job's device work overlapped the timed launches",
                  file=sys.stderr)
            bad = 1
    return bad


def main():
    if len(sys.argv) == 3 and sys.argv[1] == "--combine":
        if not os.path.isdir(sys.argv[2]):
            print(f"measured_time.py: --combine {sys.argv[2]}: not a folder", file=sys.stderr)
            sys.exit(2)
        return combine(sys.argv[2])
    if len(sys.argv) > 1 and sys.argv[1] == "--check-regions":
        sys.exit(check_regions(sys.argv[2:]))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("runs")
    ap.add_argument("out")
    ap.add_argument("--semlb", default="build/cli/semlb")
    ap.add_argument("--scene", default="epidermis_half")
    ap.add_argument("--nvlink-gbs", type=float, default=450.0, help="GB/s per direction (H200 NVLink 4: 450)")
    ap.add_argument("--seeds", default="0-2", help="replay seeds A-B for policy_order.csv")
    ap.add_argument("--no-replay", action="store_true", help="no policy_order.csv (no `semlb replay` runs)")
    a = ap.parse_args()
    if not os.path.isdir(a.runs):
        print(f"measured_time.py: {a.runs}: not a folder (scripts/gpu/measured_time.sh's OUT)", file=sys.stderr)
        sys.exit(2)
    os.makedirs(a.out, exist_ok=True)

    cost = []
    for name in sorted(os.listdir(os.path.join(a.runs, "cost"))) if os.path.isdir(os.path.join(a.runs, "cost")) else []:
        rows = read_csv(os.path.join(a.runs, "cost", name, "run.csv"))
        timing, rnd = name.rsplit("_", 1)
        cost.append((int(rnd), timing, sum(float(r["wall_s"]) for r in rows)))
    if cost:
        write_csv(os.path.join(a.out, "timer_cost.csv"), ["round", "timing", "loop_wall_s"], cost)

    turns = os.path.join(a.runs, "turns")
    if os.path.isdir(os.path.join(turns, "np1")):
        rows = []
        one = rank_times(os.path.join(turns, "np1"))
        for np_ in (2, 4):
            d = os.path.join(turns, f"np{np_}")
            if not os.path.isdir(d):
                continue
            for step, rs in rank_times(d).items():
                total, single = sum(r["device_s"] for r in rs), one[step][0]["device_s"]
                rows.append(("sum_of_ranks", np_, step, -1, total, single, total / single - 1))
        if os.path.isdir(os.path.join(turns, "alone0")):
            two = rank_times(os.path.join(turns, "np2"))
            first = min(two)
            for q in (0, 1):
                alone = rank_times(os.path.join(turns, f"alone{q}"))
                t, ref = two[first][q]["device_s"], alone[first][0]["device_s"]
                rows.append(("rank_vs_alone", 2, first, q, t, ref, t / ref - 1))
        write_csv(os.path.join(a.out, "turns_validation.csv"),
                  ["check", "ranks", "step", "rank", "device_s", "reference_s", "relative_difference"], rows)

    runs = e2e_runs(a.runs)
    record = os.path.join(a.runs, "record", "workload.h5")
    if not runs:
        return
    end = []
    for policy, ranks, launch, d in runs:
        m = loop_seconds(d, a.nvlink_gbs)
        end.append((a.scene, policy, ranks, launch, m["mean_imbalance"], m["migration"], m["loop_s"], m["compute_s"],
                    m["exchange_s"], m["migrate_s"], m["migrate_measured_s"], m["ideal_s"]))
    header = ["scene", "policy", "ranks", "launch", "mean_imbalance", "migration", "loop_s", "compute_s", "exchange_s",
              "migrate_s", "migrate_measured_s", "ideal_s"]
    write_csv(os.path.join(a.out, "end_to_end.csv"), header, end)

    summary = []
    static = {(r[2], r[3]): r[6] for r in end if r[1] == "static"}
    for policy in sorted({r[1] for r in end}):
        for ranks in sorted({r[2] for r in end}):
            rs = [r for r in end if r[1] == policy and r[2] == ranks]
            if not rs:
                continue
            imb, imb_ci = interval95([r[4] for r in rs])
            mig, mig_ci = interval95([r[5] for r in rs])
            loop, loop_ci = interval95([r[6] for r in rs])
            saved = [static[(r[2], r[3])] - r[6] for r in rs if (r[2], r[3]) in static]
            sv, sv_ci = interval95(saved) if saved else (float("nan"), float("nan"))
            summary.append((a.scene, policy, ranks, len(rs), imb, imb_ci, mig, mig_ci, loop, loop_ci, sv, sv_ci))
    write_csv(os.path.join(a.out, "end_to_end_summary.csv"),
              ["scene", "policy", "ranks", "launches", "mean_imbalance", "mean_imbalance_ci95", "migration",
               "migration_ci95", "loop_s", "loop_s_ci95", "static_minus_loop_s", "static_minus_loop_s_ci95"], summary)

    moved = []
    for policy, ranks, launch, d in runs:
        rt = rank_times(d)
        steps = list(rt)
        # migrate_s of an interval holds the migration at the end of the interval before it (measure() runs first)
        for prev, step in zip(steps, steps[1:]):
            slices = int(rt[prev][0]["moved_slices"])
            if slices > 0:
                moved.append((policy, ranks, launch, step, slices, max(r["migrate_s"] for r in rt[step]),
                              max(r["migrate_bytes"] for r in rt[step])))
    if moved:
        x, y = np.array([m[4] for m in moved], float), np.array([m[5] for m in moved], float)
        if len(set(x)) > 1:
            slope, intercept = np.polyfit(x, y, 1)
        else:  # one count of slices moved: no slope to fit, the seconds per slice alone
            slope, intercept = float(np.mean(y / x)), 0.0
        write_csv(os.path.join(a.out, "migration_cost.csv"),
                  ["policy", "ranks", "launch", "step", "moved_slices", "migrate_s", "migrate_bytes"], moved)
        write_csv(os.path.join(a.out, "migration_fit.csv"), ["s_per_slice", "s_per_interval", "intervals"],
                  [(float(slope), float(intercept), len(moved))])

    if not os.path.exists(record):
        return
    w = Workload(record)
    parts = parts_rows(w, os.path.dirname(record), runs, a.scene)
    if parts:
        write_csv(os.path.join(a.out, "parts_additivity.csv"),
                  ["scene", "policy", "ranks", "launch", "part", "ranks_sum_s", "one_rank_s", "relative_difference",
                   "by_elements_mean_abs_rel_error"], parts)
    fitted = {(p, r, l) for p, r, l, _ in runs if p == "static" and l == 1}
    fit_rows = np.vstack([model_rows(w, d) for p, r, l, d in runs if (p, r, l) in fitted])
    model = fit_time_model(fit_rows)
    val = []
    for policy, ranks, launch, d in runs:
        rows = model_rows(w, d)
        err = np.abs(predict(rows, model) - rows[:, -1]) / rows[:, -1]
        val.append((a.scene, policy, ranks, launch, int((policy, ranks, launch) in fitted), float(err.mean()),
                    float(err.max())) + tuple(model[k] for k in MODEL_KEYS))
    write_csv(os.path.join(a.out, "time_model_validation.csv"),
              ["scene", "policy", "ranks", "launch", "fitted", "mean_abs_rel_error", "max_abs_rel_error"] +
              list(MODEL_KEYS), val)

    if a.no_replay:
        return
    lo, hi = (int(x) for x in a.seeds.split("-"))
    per_slice = [m[6] / m[4] for m in moved] if moved else [0.0]
    migrate_per_slice = float(np.mean(per_slice)) / (a.nvlink_gbs * 1e9)
    # the list keys where the record has list seconds (version 3); a version 2 record's model is the other two
    keys = MODEL_KEYS if w.list_s is not None else ("ghost_weight", "rank_overhead_s")
    list_by = "triggers" if w.triggers is not None else "work"
    model_args = (["--time-model", f"list_by={list_by}"] if w.list_s is not None else []) + \
        [x for k in keys for x in ("--time-model", f"{k}={model[k]!r}")]
    order = []
    for ranks in sorted({r[2] for r in end}):
        measured = {p: np.mean([r[6] for r in end if r[1] == p and r[2] == ranks]) for p in sorted({r[1] for r in end})}
        replayed = {}
        for p in measured:
            loops = []
            for seed in range(lo, hi + 1):
                out = subprocess.run([a.semlb, "replay", "--workload", record, "--ranks", str(ranks), "--policy", p,
                                      "--seed", str(seed),
                                      "--time-model", f"migrate_s_per_slice={migrate_per_slice!r}"] + model_args,
                                     check=True, capture_output=True, text=True).stdout
                loops.append(json.loads(out)["loop_s"])
            replayed[p] = float(np.mean(loops))
        rank_m = {p: i + 1 for i, p in enumerate(sorted(measured, key=measured.get))}
        rank_r = {p: i + 1 for i, p in enumerate(sorted(replayed, key=replayed.get))}
        for p in measured:
            order.append((ranks, p, float(measured[p]), replayed[p], rank_m[p], rank_r[p]))
    write_csv(os.path.join(a.out, "policy_order.csv"),
              ["ranks", "policy", "measured_loop_s", "replayed_loop_s", "measured_rank", "replayed_rank"], order)


if __name__ == "__main__":
    main()
