#!/usr/bin/env python3
"""Fit the surrogate's scenario parameters to engine traces, check the fit, and compare policy rankings.

Trace families (every trace.jsonl under --results, grouped by path and timing): `development` (cpu/end_to_end),
`gpu_epidermis` (gpu/engine_traces), `cpu_epidermis` (other CPU traces with measured timing) and
`cpu_epidermis_modelled` (timing: modelled, i.e. times are the work sums). A family's traces record the same
tissue under different partitions, so its statistics are pooled (mean over its traces).

Statistics of a trace (the same functions on engine traces and on surrogate rollouts; n_t = slice_work_t / sum):
  work_noise  sqrt(sum_(t,i) (n_ti - (n_(t-1)i + n_(t+1)i)/2)^2 / (1.5 sum_(t,i) n_ti^2)): multiplicative
              per-slice noise of std s gives a second difference of variance 1.5 s^2 n^2 when the true work is
              smooth in time (it equals s on such a series; real changes between events add to it);
  time_resid  rms over events and ranks of (T_r - P_r) / P_r, P_r = the rank's work sum scaled to sum T (the
              recorded partition; the same quantity as trace_model.py's relative error);
  drift       |least-squares slope| of the work centre sum_i x_i n_ti (x in [0, 1]) per event;
  growth      least-squares slope of log(sum_i slice_work_ti) per event;
  burst_rate  fraction of event transitions with a jump: the box-smoothed n (half-width max(1, S/200) slices)
              rising somewhere by more than JUMP (0.3) of max(its previous value, the mean slice level);
  burst_size  mean of that largest relative rise over the transitions with a jump (0 without any); both pooled
              over all transitions of a family's traces;
  growth period and offset are read from the traces' growth_phase (period = 1 / its step).
The fit is the method of simulated moments: each scenario parameter is paired with the statistic it drives
(work_noise <- work_noise, time_jitter <- time_resid, drift_speed <- drift (drift_walk = 0.15 and drift_max =
2.5 x drift_speed, the defaults' ratios), growth_rate <- growth, burst_size <- burst_size, burst_probability
<- burst_rate; in this order), and solved by bisection on the statistic of surrogate rollouts (static policy; the family's
ranks, slices, min_width, events; fixed fit seeds, so the simulated statistic is a deterministic function of
the parameter), coordinate by coordinate, ROUNDS times. The check applies the same statistics to rollouts on
other seeds: each within TOL (relative) or its absolute floor of the family's value.
The rank comparison: every policy the engine runs (`semlb list engine-policies --json`: all but those that need the
true work of the next interval) replayed on each trace (`semlb replay --score`, averaged over the
family) and rolled out on the fitted surrogate (--rank-seeds), ranked by mean imbalance and by migration;
Kendall tau-b between the two rankings.

Usage: fit_surrogate.py --semlb BIN --results DIR [--csv CSV] [--table MD] [--params-csv CSV]
       fit_surrogate.py --semlb BIN --traces DIR --fit-only   (one family from every trace under DIR; prints JSON)
Exit 2 with FILE:LINE: field 'NAME': reason on a bad trace. Python stdlib only (numpy/scipy are not installed).
"""
import argparse
import csv
import glob
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np
from scipy import stats as _stats

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import semlb_names  # noqa: E402
from sections.common import md_table  # noqa: E402
from trace_model import TraceError, find_traces, read_trace, rank_sums, scene_timing, write_csv  # noqa: E402

JUMP = 0.3
ROUNDS = 2
BISECT_STEPS = 7
FIT_SEEDS = "9000-9003"
CHECK_SEEDS = "9100-9103"
RANK_SEEDS = "9200-9219"
# parameter -> (statistic, low, high, log-scale bisection)
PARAMETERS = [("work_noise", "work_noise", 0.0, 0.9, False), ("time_jitter", "time_resid", 0.0, 0.9, False),
              ("drift_speed", "drift", 1e-6, 0.05, True), ("growth_rate", "growth", -0.2, 0.5, False),
              ("burst_size", "burst_size", 0.01, 100.0, True), ("burst_probability", "burst_rate", 0.0, 1.0, False)]
STATS = ["work_noise", "time_resid", "drift", "growth", "burst_rate", "burst_size"]
TOL = 0.25
FLOOR = {"work_noise": 0.01, "time_resid": 0.01, "drift": 2e-4, "growth": 2e-3, "burst_rate": 0.1, "burst_size": 0.25}


def lsq_slope(ys):
    """Least-squares slope of ys against 0, 1, ..., len-1 (numpy.polyfit; 0 for fewer than 2 points)."""
    if len(ys) < 2:
        return 0.0
    return float(np.polyfit(np.arange(len(ys), dtype=float), np.asarray(ys, dtype=float), 1)[0])


def normalised(work):
    total = math.fsum(work)
    return [w / total for w in work] if total > 0 else None


def box(values, h):
    """Mean over the window [i - h, i + h] clipped to the array."""
    pre = [0.0]
    for v in values:
        pre.append(pre[-1] + v)
    n = len(values)
    return [(pre[min(n, i + h + 1)] - pre[max(0, i - h)]) / (min(n, i + h + 1) - max(0, i - h)) for i in range(n)]


def statistics(events):
    """The statistics above of one trace (a list of event dicts: slice_work, times, boundaries)."""
    norm = [normalised(e["slice_work"]) for e in events]
    norm = [n for n in norm if n is not None]
    num = den = 0.0
    for a, b, c in zip(norm, norm[1:], norm[2:]):
        num += math.fsum((y - (x + z) / 2) ** 2 for x, y, z in zip(a, b, c))
        den += math.fsum(y * y for y in b)
    work_noise = math.sqrt(num / (1.5 * den)) if den > 0 else 0.0
    resid = []
    for e in events:
        times = e["times"]
        pred = rank_sums(e["slice_work"], e["boundaries"])
        st, sp = math.fsum(times), math.fsum(pred)
        if st <= 0 or sp <= 0:
            continue
        resid += [(t - p * st / sp) / (p * st / sp) for t, p in zip(times, pred) if p > 0]
    time_resid = math.sqrt(math.fsum(r * r for r in resid) / len(resid)) if resid else 0.0
    centres = [math.fsum((i + 0.5) / len(n) * v for i, v in enumerate(n)) for n in norm]
    totals = [math.fsum(e["slice_work"]) for e in events]
    logs = [math.log(t) for t in totals if t > 0]
    jumps = []
    if norm:
        h = max(1, len(norm[0]) // 200)
        smooth = [box(n, h) for n in norm]
        level = 1.0 / len(norm[0])
        for a, b in zip(smooth, smooth[1:]):
            jumps.append(max((y - x) / max(x, level) for x, y in zip(a, b)))
    return {"work_noise": work_noise, "time_resid": time_resid, "drift": abs(lsq_slope(centres)),
            "growth": lsq_slope(logs), "jumps": jumps}


def pooled(stats):
    """Mean of each statistic over traces; burst_rate and burst_size from all their transitions together."""
    out = {k: math.fsum(s[k] for s in stats) / len(stats) for k in STATS if k not in ("burst_rate", "burst_size")}
    jumps = [j for s in stats for j in s["jumps"]]
    big = [j for j in jumps if j > JUMP]
    out["burst_rate"] = len(big) / len(jumps) if jumps else 0.0
    out["burst_size"] = math.fsum(big) / len(big) if big else 0.0
    return out


def growth_schedule(events):
    """(period, offset) of the surrogate's growth events from the trace's growth_phase ((0, 0) if absent)."""
    ph = [e.get("growth_phase") for e in events]
    if len(ph) < 2 or any(p is None for p in ph):
        return 0, 0
    steps = [(b - a) % 1.0 for a, b in zip(ph, ph[1:])]
    steps = sorted(s for s in steps if s > 0)
    if not steps:
        return 0, 0
    period = max(1, round(1.0 / steps[len(steps) // 2]))
    return period, round(-ph[0] * period) % period


def family_of(rel, timing):
    if rel.startswith("cpu/end_to_end"):
        return "development"
    if rel.startswith("gpu/"):
        return "gpu_epidermis"
    return "cpu_epidermis_modelled" if timing == "modelled" else "cpu_epidermis"


class Surrogate:
    """`semlb surrogate` runs with scenario overrides; statistics of its dumped traces (cached by arguments)."""

    def __init__(self, semlb, shape):
        self.semlb, self.shape, self.cache = semlb, shape, {}
        self.tmp = tempfile.mkdtemp(prefix="fit_surrogate_")

    def overrides(self, params):
        o = {"slices": self.shape["slices"], "min_width": self.shape["min_width"]}
        if self.shape["period"] > 0:
            o["growth_period"], o["growth_offset"] = self.shape["period"], self.shape["offset"]
        for k, v in params.items():
            o[k] = v
        if "drift_speed" in params:
            o["drift_walk"], o["drift_max"] = 0.15 * params["drift_speed"], 2.5 * params["drift_speed"]
        return o

    def run(self, params, policies, seeds, dump):
        out = os.path.join(self.tmp, "run")
        shutil.rmtree(out, ignore_errors=True)
        cmd = [self.semlb, "surrogate", "--policies", ",".join(policies), "--ranks", str(self.shape["ranks"]), "--seeds", seeds,
               "--events", str(self.shape["events"]), "--out", out, "--no-timing", "--quiet"]
        for k, v in self.overrides(params).items():
            cmd += ["--scenario", f"{k}={v!r}" if isinstance(v, float) else f"{k}={v}"]
        if dump:
            cmd.append("--dump-traces")
        r = subprocess.run(cmd, capture_output=True, text=True)
        if r.returncode != 0:
            raise RuntimeError(f"{' '.join(cmd)}: exit {r.returncode}: {r.stderr.strip()}")
        return out

    def stats(self, params, seeds):
        key = (tuple(sorted(params.items())), seeds)
        if key not in self.cache:
            out = self.run(params, ["static"], seeds, True)
            self.cache[key] = pooled([statistics([e for _, e in read_trace(p)])
                                      for p in sorted(glob.glob(os.path.join(out, "traces", "*.jsonl")))])
        return self.cache[key]

    def scores(self, params, seeds, policies):
        """policy -> (mean imbalance, mean migration) over the seeds, for each of `policies`."""
        out = self.run(params, policies, seeds, False)
        acc = {}
        with open(os.path.join(out, "controller_eval.csv")) as f:
            for row in csv.DictReader(f):
                acc.setdefault(row["policy"], []).append((float(row["mean_imbalance"]), float(row["migration"])))
        return {p: (math.fsum(a for a, _ in v) / len(v), math.fsum(m for _, m in v) / len(v)) for p, v in acc.items()}

    def close(self):
        shutil.rmtree(self.tmp, ignore_errors=True)


def fit(sur, target, seeds=FIT_SEEDS):
    """Simulated-moments fit: {parameter: value}, each found by bisection so that the surrogate's statistic on
    `seeds` matches target[statistic] (increasing in the parameter; a target outside the reachable range gives
    the nearer bound)."""
    params = {"work_noise": 0.1, "time_jitter": 0.02, "drift_speed": 0.0002, "growth_rate": 0.0005,
              "burst_probability": 0.05, "burst_size": 1.0}
    for _ in range(ROUNDS):
        for name, stat, lo, hi, log in PARAMETERS:
            def at(v):
                return sur.stats(dict(params, **{name: v}), seeds)[stat]
            if target[stat] <= at(lo):
                params[name] = lo if not (name == "drift_speed") else 0.0
                continue
            if target[stat] >= at(hi):
                params[name] = hi
                continue
            a, b = lo, hi
            for _ in range(BISECT_STEPS):
                m = math.sqrt(a * b) if log else (a + b) / 2
                a, b = (m, b) if at(m) < target[stat] else (a, m)
            params[name] = math.sqrt(a * b) if log else (a + b) / 2
    return params


def check(sur, params, target, seeds=CHECK_SEEDS):
    """statistic -> (family value, fitted surrogate's value on other seeds, within tolerance)."""
    got = sur.stats(params, seeds)
    return {k: (target[k], got[k], abs(got[k] - target[k]) <= max(TOL * abs(target[k]), FLOOR[k])) for k in STATS}


def kendall_tau_b(x, y):
    """Kendall tau-b of paired lists (scipy.stats.kendalltau, ties as in tau-b); nan when either is constant."""
    if len(set(x)) < 2 or len(set(y)) < 2:
        return float("nan")
    return float(_stats.kendalltau(x, y, variant="b").statistic)


def ranks(values):
    """1-based ranks, ties sharing the mean rank (scipy.stats.rankdata)."""
    return [float(r) for r in _stats.rankdata(values)]


def replay_scores(semlb, path, policies):
    """policy -> (mean imbalance, migration) of `semlb replay --score` on one trace, for each of `policies`."""
    out = {}
    for p in policies:
        r = subprocess.run([semlb, "replay", "--policy", p, "--trace", path, "--score"], capture_output=True, text=True)
        if r.returncode != 0:
            raise RuntimeError(f"semlb replay --policy {p} --trace {path}: exit {r.returncode}: {r.stderr.strip()}")
        j = json.loads(r.stdout.strip().splitlines()[-1])
        out[p] = (j["mean_imbalance"], j["migration"])
    return out


def load_families(root):
    fams = {}
    for path in find_traces(root):
        rel = os.path.relpath(os.path.dirname(path), root)
        events = [e for _, e in read_trace(path)]
        fams.setdefault(family_of(rel, scene_timing(os.path.dirname(path))), []).append((path, events))
    return fams


def shape_of(traces):
    e0 = traces[0][1]
    period, offset = growth_schedule(e0)
    return {"ranks": len(e0[0]["times"]), "slices": e0[0]["slices"], "min_width": e0[0]["min_width"],
            "events": min(len(ev) for _, ev in traces), "period": period, "offset": offset}


def main():
    ap = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    ap.add_argument("--semlb", required=True, help="the semlb binary")
    ap.add_argument("--results", help="folder searched for trace.jsonl files (families by path)")
    ap.add_argument("--traces", help="with --fit-only: every trace.jsonl under this folder is one family")
    ap.add_argument("--fit-only", action="store_true", help="fit and check only; print one JSON line")
    ap.add_argument("--csv", help="rank comparison CSV (family, policy, engine and surrogate scores)")
    ap.add_argument("--params-csv", help="fitted parameters and fit check CSV")
    ap.add_argument("--table", help="markdown table")
    a = ap.parse_args()
    root = a.traces if a.fit_only else a.results
    if not root or not os.path.isdir(root):
        print(f"--{'traces' if a.fit_only else 'results'}: '{root}' is not a folder", file=sys.stderr)
        return 2
    try:
        fams = {"all": [(p, [e for _, e in read_trace(p)]) for p in find_traces(root)]} if a.fit_only else load_families(root)
    except TraceError as err:
        print(err, file=sys.stderr)
        return 2
    if not any(fams.values()):
        print(f"no trace.jsonl under '{root}'", file=sys.stderr)
        return 2
    try:  # the policies ranked: every one the engine runs (`semlb list engine-policies`)
        policies = [] if a.fit_only else semlb_names.names(a.semlb, "engine-policies")
    except semlb_names.NamesError as err:
        print(err, file=sys.stderr)
        return 2
    param_rows, rank_rows, summary = [], [], []
    for fam in sorted(fams):
        traces = fams[fam]
        shape = shape_of(traces)
        target = pooled([statistics(ev) for _, ev in traces])
        sur = Surrogate(a.semlb, shape)
        try:
            params = fit(sur, target)
            chk = check(sur, params, target)
            if a.fit_only:
                print(json.dumps({"shape": shape, "target": target, "params": params,
                                  "check": {k: list(v) for k, v in chk.items()}}))
                return 0
            for (name, stat, *_r) in PARAMETERS:
                t, g, ok = chk[stat]
                param_rows.append({"family": fam, "traces": len(traces), "parameter": name, "value": params[name],
                                   "statistic": stat, "engine": t, "surrogate": g, "ok": int(ok)})
            sim = sur.scores(params, RANK_SEEDS, policies)
        finally:
            sur.close()
        eng = {p: [0.0, 0.0] for p in policies}
        for path, _ in traces:
            for p, (imb, mig) in replay_scores(a.semlb, path, policies).items():
                eng[p][0] += imb / len(traces)
                eng[p][1] += mig / len(traces)
        taus = {}
        for i, metric in enumerate(["imbalance", "migration"]):
            x, y = [eng[p][i] for p in policies], [sim[p][i] for p in policies]
            taus[metric] = (kendall_tau_b(x, y), ranks(x), ranks(y))
        for k, p in enumerate(policies):
            rank_rows.append({"family": fam, "policy": p, "ranks": shape["ranks"], "slices": shape["slices"], "events": shape["events"],
                              "engine_imbalance": eng[p][0], "surrogate_imbalance": sim[p][0],
                              "engine_imbalance_rank": taus["imbalance"][1][k], "surrogate_imbalance_rank": taus["imbalance"][2][k],
                              "engine_migration": eng[p][1], "surrogate_migration": sim[p][1],
                              "engine_migration_rank": taus["migration"][1][k], "surrogate_migration_rank": taus["migration"][2][k]})
        summary.append((fam, len(traces), shape, params, chk, taus["imbalance"][0], taus["migration"][0]))
        print(f"{fam}: {len(traces)} traces, tau imbalance {taus['imbalance'][0]:.3f}, tau migration {taus['migration'][0]:.3f}, "
              f"fit check {sum(v[2] for v in chk.values())}/{len(chk)}", file=sys.stderr)
    if a.params_csv:
        write_csv(a.params_csv, ["family", "traces", "parameter", "value", "statistic", "engine", "surrogate", "ok"], param_rows)
    if a.csv:
        write_csv(a.csv, list(rank_rows[0].keys()), rank_rows)
    if a.table:
        write_table(a.table, summary, rank_rows)
    return 0


def write_table(path, summary, rank_rows):
    lines = ["# Surrogate fitted to engine traces: do policies rank the same?", "",
             "Generated by `analysis/fit_surrogate.py` (`make surrogate-fit`); estimator and reading: docs/controllers.md "
             "\"Surrogate fitted to engine traces\". Kendall tau-b between the policies' ranks on the engine traces (replay, "
             f"mean over the family's traces) and on the fitted surrogate (seeds {RANK_SEEDS}).", "",
             md_table(["family", "traces", "P", "slices", "events", "tau (imbalance)", "tau (migration)", "fit check"],
                      [(fam, n, shape["ranks"], shape["slices"], shape["events"], f"{ti:.2f}", f"{tm:.2f}",
                        f"{sum(v[2] for v in chk.values())}/{len(chk)}") for fam, n, shape, params, chk, ti, tm in summary],
                      align="l" * 8)]
    body = []
    for fam, n, shape, params, chk, ti, tm in summary:
        cells = []
        for name, stat, *_ in PARAMETERS:
            t, g, ok = chk[stat]
            cells.append(f"{params[name]:.4g} ({t:.3g} / {g:.3g}{'' if ok else ' *'})")
        body.append([fam] + cells + [f"{shape['period']}/{shape['offset']}"])
    lines += ["", "Fitted parameters (statistic: engine / fitted surrogate on check seeds; * = outside tolerance):", "",
              md_table(["family"] + [n for n, *_ in PARAMETERS] + ["growth period/offset"], body,
                       align="l" * (len(PARAMETERS) + 2))]
    lines += ["", "Per policy: mean imbalance % (rank) and migration in slices (rank), engine replay vs surrogate:", "",
              md_table(["family", "policy", "engine imbalance", "surrogate imbalance", "engine migration",
                        "surrogate migration"],
                       [(r["family"], r["policy"], f"{100 * r['engine_imbalance']:.2f} ({r['engine_imbalance_rank']:g})",
                         f"{100 * r['surrogate_imbalance']:.2f} ({r['surrogate_imbalance_rank']:g})",
                         f"{r['engine_migration']:.1f} ({r['engine_migration_rank']:g})",
                         f"{r['surrogate_migration']:.1f} ({r['surrogate_migration_rank']:g})") for r in rank_rows],
                       align="l" * 6)]
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    with open(path + ".tmp", "w") as f:
        f.write("\n".join(lines) + "\n")
    os.replace(path + ".tmp", path)


if __name__ == "__main__":
    sys.exit(main())
