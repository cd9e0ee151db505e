#!/usr/bin/env python3
"""Tables (markdown) and figures (PNG) from the CSVs under results/; stdlib csv + matplotlib, no pandas."""
import argparse
import csv
import math
import os
import statistics
import sys
from collections import OrderedDict

POLICY_ORDER = ["static", "persistence", "holt", "reactive", "gru", "oracle"]


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def atomic_write(path, text_or_fig):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    tmp = path + ".tmp"
    if isinstance(text_or_fig, str):
        with open(tmp, "w") as f:
            f.write(text_or_fig)
    else:
        text_or_fig.savefig(tmp, dpi=130, format="png")
    os.replace(tmp, path)


def grouped(rows, value):
    """(policy, ranks) -> list of floats, policies in the paper's order."""
    groups = OrderedDict()
    policies = sorted({r["policy"] for r in rows}, key=lambda p: (POLICY_ORDER.index(p) if p in POLICY_ORDER else 99, p))
    ranks = sorted({int(r["ranks"]) for r in rows})
    for p in policies:
        for P in ranks:
            vals = [float(r[value]) for r in rows if r["policy"] == p and int(r["ranks"]) == P]
            if vals:
                groups[(p, P)] = vals
    return policies, ranks, groups


def by(rows, column):
    """column value -> rows with it, in first-seen order."""
    out = OrderedDict()
    for r in rows:
        out.setdefault(r[column], []).append(r)
    return out


def mean_sd(vals):
    return statistics.fmean(vals), (statistics.stdev(vals) if len(vals) > 1 else 0.0)


def controller_table(rows):
    policies, ranks, imb = grouped(rows, "mean_imbalance")
    _, _, mig = grouped(rows, "migration")
    seeds = len({r["seed"] for r in rows})
    events = sorted({r["events"] for r in rows})
    out = ["# Controller evaluation (surrogate, held-out seeds, hard integer boundaries)", "",
           f"{seeds} seeds per cell, {', '.join(events)}-event rollouts. Imbalance = time-averaged "
           "I_global = (T_max - T_min)/T_mean in percent (mean ± sd over seeds); migration = slices moved "
           "over the rollout (mean ± sd).", "",
           "| policy | " + " | ".join(f"P={P} imbalance % | P={P} migration" for P in ranks) + " |",
           "|---|" + "---:|---:|" * len(ranks)]
    for p in policies:
        cells = []
        for P in ranks:
            if (p, P) not in imb:
                cells += ["", ""]
                continue
            mi, si = mean_sd(imb[(p, P)])
            mm, sm = mean_sd(mig[(p, P)])
            cells += [f"{100 * mi:.2f} ± {100 * si:.2f}", f"{mm:.0f} ± {sm:.0f}"]
        out.append(f"| {p} | " + " | ".join(cells) + " |")
    return "\n".join(out) + "\n"


def controller_figure(rows):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    policies, ranks, imb = grouped(rows, "mean_imbalance")
    _, _, mig = grouped(rows, "migration")
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    width = 0.8 / max(1, len(policies))
    colors = plt.get_cmap("tab10")
    for k, p in enumerate(policies):
        for ax, data in ((axes[0], imb), (axes[1], mig)):
            xs, ys = [], []
            for i, P in enumerate(ranks):
                for j, v in enumerate(data.get((p, P), [])):
                    n = len(data[(p, P)])
                    xs.append(i + (k - (len(policies) - 1) / 2) * width + (j / max(1, n - 1) - 0.5) * width * 0.6)
                    ys.append(100 * v if data is imb else v)
            ax.scatter(xs, ys, s=9, color=colors(k), label=p if ax is axes[0] else None, alpha=0.75)
    floor = min([100 * v for vals in imb.values() for v in vals if v > 0] or [1e-3])
    axes[0].set_yscale("log")
    axes[0].set_ylim(bottom=floor / 2)
    axes[0].set_ylabel("time-averaged global imbalance (%)")
    axes[0].set_title("(a) imbalance")
    axes[1].set_yscale("symlog", linthresh=10)
    axes[1].set_ylabel("slices migrated over the rollout")
    axes[1].set_title("(b) migration (linear below 10)")
    for ax in axes:
        ax.set_xticks(range(len(ranks)), [f"P={P}" for P in ranks])
        ax.grid(alpha=0.3, which="both")
    fig.legend(loc="upper center", ncol=len(policies), frameon=False)
    fig.tight_layout(rect=(0, 0, 1, 0.92))
    return fig


def holt_tuning_table(rows):
    """Mean imbalance per (alpha, beta) over training seeds and ranks; the best pair first."""
    cells = OrderedDict()
    for r in rows:
        cells.setdefault((float(r["holt.alpha"]), float(r["holt.beta"])), []).append(r)
    scored = sorted((statistics.fmean(float(r["mean_imbalance"]) for r in rs),
                     statistics.fmean(float(r["migration"]) for r in rs), a, b) for (a, b), rs in cells.items())
    out = ["# Holt smoothing parameters (training seeds only)", "",
           "Mean over the grid's ranks and training seeds; sorted by imbalance (lower is better).", "",
           "| alpha | beta | imbalance % | migration |", "|---:|---:|---:|---:|"]
    out += [f"| {a:g} | {b:g} | {100 * i:.3f} | {m:.0f} |" for i, m, a, b in scored]
    return "\n".join(out) + "\n"


def frontier_table(rows, eval_rows):
    """Lazy-oracle imbalance and migration per (P, tau), beside the GRU target that reactive's rows of
    controller_eval imply (migration <= reactive/8 within +0.5 points; nan without them)."""
    reactive = {p: (statistics.fmean(float(r["mean_imbalance"]) for r in rs),
                    statistics.fmean(float(r["migration"]) for r in rs))
                for p, rs in by([r for r in eval_rows if r["policy"] == "reactive"], "ranks").items()}
    out = ["# What one-step foresight buys per migrated slice (lazy oracle, held-out seeds)", "",
           "Mean over seeds. Target: the GRU's bound, reactive's imbalance + 0.5 points at 1/8 of its "
           "migration (reactive from controller_eval.csv in the same results folder).", "",
           "| P | tau | imbalance % | migration | target imbalance % | target migration |",
           "|---:|---:|---:|---:|---:|---:|"]
    for p, rs in sorted(by(rows, "ranks").items(), key=lambda kv: int(kv[0])):
        ri, rm = reactive.get(p, (float("nan"), float("nan")))
        for tau, ts in sorted(by(rs, "lazy_oracle.tau").items(), key=lambda kv: float(kv[0])):
            out.append(f"| {p} | {float(tau):g} | {100 * statistics.fmean(float(r['mean_imbalance']) for r in ts):.2f} | "
                       f"{statistics.fmean(float(r['migration']) for r in ts):.1f} | {100 * ri + 0.5:.2f} | {rm / 8:.1f} |")
    return "\n".join(out) + "\n"


# Families that a simulation can run (rank times, slice work); lazy_oracle needs the next interval's true work.
DEPLOYABLE = ["reactive", "gromacs_dlb", "hoomd_balance", "all_tensor", "lammps_shift"]
FRONTIER_FAMILIES = DEPLOYABLE + ["lazy_oracle", "foresight"]


def setting_points(rows):
    """P -> [(family, setting, mean imbalance (fraction), mean migration)], one per (policy, POLICY.KEY cells), means
    over seeds. The setting names the row's own policy's parameter cells ("tau=0.05 alpha=0.5"; "defaults" if none)."""
    params = [c for c in rows[0] if "." in c]
    cells = OrderedDict()
    for r in rows:
        label = " ".join(f"{c.split('.', 1)[1]}={r[c]}" for c in params if r[c] and c.startswith(r["policy"] + "."))
        cells.setdefault((int(r["ranks"]), r["policy"], label or "defaults"), []).append(r)
    out = OrderedDict()
    for (P, policy, label), rs in sorted(cells.items(), key=lambda kv: kv[0][0]):
        out.setdefault(P, []).append((policy, label, statistics.fmean(float(r["mean_imbalance"]) for r in rs),
                                      statistics.fmean(float(r["migration"]) for r in rs)))
    return out


def dominates(q, p):
    """q is no worse than p in imbalance and migration and better in one (points as from setting_points)."""
    return q[2] <= p[2] and q[3] <= p[3] and (q[2] < p[2] or q[3] < p[3])


def pareto_front(points):
    """The points no other point dominates, by imbalance ascending (so migration descending); of equal points the
    first is kept."""
    front, seen = [], set()
    for p in points:
        if (p[2], p[3]) not in seen and not any(dominates(q, p) for q in points):
            front.append(p)
            seen.add((p[2], p[3]))
    return sorted(front, key=lambda p: p[2])


def migration_at(front, imbalance):
    """The migration FRONT (from pareto_front) needs for IMBALANCE: linear in imbalance between neighbouring front
    points, the front's least migration past its largest imbalance, None below its smallest imbalance."""
    if not front or imbalance < front[0][2]:
        return None
    if imbalance >= front[-1][2]:
        return front[-1][3]
    for a, b in zip(front, front[1:]):
        if a[2] <= imbalance <= b[2]:
            return a[3] + (b[3] - a[3]) * (imbalance - a[2]) / (b[2] - a[2])


def imbalance_at(front, migration):
    """The imbalance FRONT (from pareto_front) reaches with MIGRATION slices: linear in migration between neighbouring
    front points, the front's least imbalance past its largest migration, None below its least migration."""
    if not front or migration < front[-1][3]:
        return None
    if migration >= front[0][3]:
        return front[0][2]
    for a, b in zip(front, front[1:]):
        if b[3] <= migration <= a[3]:
            return a[2] if a[3] == b[3] else a[2] + (b[2] - a[2]) * (a[3] - migration) / (a[3] - b[3])


def shipped_gru(points):
    """The shipped GRU's point (family gru, no parameter cells: the default weights), else the first gru point."""
    grus = [p for p in points if p[0] == "gru"]
    return next((p for p in grus if p[1] == "defaults"), grus[0] if grus else None)


def floor_gap(points):
    """For one P's points, at the GRU's migration: (gru point, the best deployable front's imbalance (least over
    the deployable families of imbalance_at; None if none moves that little), foresight's imbalance there (None
    without foresight rows), the share of the distance from the deployable front to the floor the GRU closes:
    (front - gru) / (front - floor); None when either is missing or the front is on the floor)."""
    gru = shipped_gru(points)
    if gru is None:
        return None, None, None, None
    fronts = [imbalance_at(pareto_front([p for p in points if p[0] == fam]), gru[3]) for fam in DEPLOYABLE]
    best = min((f for f in fronts if f is not None), default=None)
    floor = imbalance_at(pareto_front([p for p in points if p[0] == "foresight"]), gru[3])
    share = None if best is None or floor is None or best <= floor else (best - gru[2]) / (best - floor)
    return gru, best, floor, share


def gru_verdict(points):
    """For one P's points: (gru point or None, deployable points dominating it, the least migration a deployable
    family's front needs at its imbalance (migration_at; None if none reaches it), GRU migration / that or None).
    Targets: (a) none dominates; (b) ratio <= 1/2. Fronts are per family: a line between two settings of one family
    stands for the knob values between them; nothing lies between two families."""
    gru = shipped_gru(points)
    if gru is None:
        return None, [], None, None
    deployable = [p for p in points if p[0] in DEPLOYABLE]
    beaten_by = sorted((q for q in deployable if dominates(q, gru)), key=lambda q: (q[3], q[2]))
    needs = [migration_at(pareto_front([p for p in deployable if p[0] == fam]), gru[2]) for fam in DEPLOYABLE]
    need = min((n for n in needs if n is not None), default=None)
    ratio = None if need is None else (gru[3] / need if need > 0 else (0.0 if gru[3] == 0 else math.inf))
    return gru, beaten_by, need, ratio


def balancer_frontier_table(rows):
    by_p = setting_points(rows)
    seeds = len({r["seed"] for r in rows})
    events = sorted({r["events"] for r in rows})
    out = ["# The frontier: what each balancer family trades, and where the shipped GRU sits (held-out seeds)", "",
           f"Each point is one setting's mean over {seeds} seeds ({', '.join(events)}-event rollouts): imbalance = "
           "time-averaged I_global in percent, migration = slices moved over the rollout. Deployable families: "
           + ", ".join(DEPLOYABLE) + "; lazy_oracle knows the next interval's true work (a foresight bound, not "
           "deployable). The targets are the shipped GRU's (default weights, migration penalty 2); the gru family's "
           "front below adds the same recipe trained with other migration penalties where the manifest lists them "
           "(gru.weights).", "",
           "Targets: (a) no deployable setting dominates the GRU (no worse in both, better in one); (b) at the GRU's "
           "imbalance the GRU migrates at most half of what the best deployable front needs: the least, over the "
           "deployable families, of the family's Pareto front interpolated linearly in imbalance between its points.", "",
           "| P | GRU imbalance % | GRU migration | dominated by | deployable front's migration at the GRU's imbalance "
           "| GRU / front | (a) | (b) |", "|---:|---:|---:|---|---:|---:|---|---|"]
    for P, points in by_p.items():
        gru, beaten_by, need, ratio = gru_verdict(points)
        if gru is None:
            out.append(f"| {P} | | | no gru rows | | | | |")
            continue
        dom = "none" if not beaten_by else (
            f"{len(beaten_by)} setting{'s' if len(beaten_by) > 1 else ''}, least migration: {beaten_by[0][0]} "
            f"{beaten_by[0][1]} ({100 * beaten_by[0][2]:.2f} %, {beaten_by[0][3]:.1f})")
        need_s = "unreached" if need is None else f"{need:.1f}"
        ratio_s = "" if ratio is None else ("inf" if math.isinf(ratio) else f"{ratio:.2f}")
        b = need is None or ratio <= 0.5
        out.append(f"| {P} | {100 * gru[2]:.2f} | {gru[3]:.1f} | {dom} | {need_s} | {ratio_s} | "
                   f"{'holds' if not beaten_by else 'fails'} | {'holds' if b else 'fails'} |")
    out += ["", "\"unreached\": no deployable setting reaches the GRU's imbalance at any migration ((b) holds).", "",
            "The floor: foresight (docs/controllers.md) knows the true work of every interval and minimises summed "
            "I_global + lambda x slices moved (exact at P = 2; at P > 2 a feasible path found by block coordinate "
            "descent, so an upper bound on the floor). At the GRU's migration, each front's imbalance (linear in "
            "migration between its points) and the share of the distance from the best deployable front down to "
            "foresight that the GRU closes, (front - GRU) / (front - floor); target at P = 2: at least 0.5.", "",
            "| P | GRU migration | best deployable front's imbalance % there | foresight's imbalance % there | GRU "
            "imbalance % | share of the gap closed |", "|---:|---:|---:|---:|---:|---:|"]
    for P, points in by_p.items():
        gru, best, floor, share = floor_gap(points)
        if gru is None:
            continue
        out.append(f"| {P} | {gru[3]:.1f} | {'unreached' if best is None else f'{100 * best:.2f}'} | "
                   f"{'' if floor is None else f'{100 * floor:.2f}'} | {100 * gru[2]:.2f} | "
                   f"{'' if share is None else f'{share:.2f}'} |")
    out += ["", "\"unreached\": no deployable setting migrates as little as the GRU.", "",
            "Migration each family's front needs at the GRU's imbalance (same interpolation; \"unreached (x)\": the "
            "family's lowest imbalance x % is above the GRU's):", "",
            "| family | " + " | ".join(f"P={P}" for P in by_p) + " |", "|---|" + "---:|" * len(by_p)]
    for fam in FRONTIER_FAMILIES:
        cells = []
        for P, points in by_p.items():
            gru, front = gru_verdict(points)[0], pareto_front([q for q in points if q[0] == fam])
            need = migration_at(front, gru[2]) if gru and front else None
            cells.append("" if not gru or not front else
                         f"unreached ({100 * front[0][2]:.2f})" if need is None else f"{need:.1f}")
        out.append(f"| {fam} | " + " | ".join(cells) + " |")
    for P, points in by_p.items():
        out += ["", f"## P = {P}: Pareto front of each family", "", "| family | setting | imbalance % | migration |",
                "|---|---|---:|---:|"]
        for fam in FRONTIER_FAMILIES + ["gru"]:
            for p in pareto_front([q for q in points if q[0] == fam]):
                out.append(f"| {fam} | {p[1]} | {100 * p[2]:.2f} | {p[3]:.1f} |")
    return "\n".join(out) + "\n"


def balancer_frontier_figure(rows):
    plt = _plt()
    by_p = setting_points(rows)
    cols = min(2, len(by_p))
    rows_n = (len(by_p) + cols - 1) // cols
    fig, axes = plt.subplots(rows_n, cols, figsize=(5.5 * cols, 4 * rows_n + 0.6), squeeze=False)
    colors = plt.get_cmap("tab10")
    for ax in axes.flat[len(by_p):]:
        ax.set_visible(False)
    for ax, (P, points) in zip(axes.flat, by_p.items()):
        for k, fam in enumerate(FRONTIER_FAMILIES):
            front = pareto_front([q for q in points if q[0] == fam])
            if front:
                ax.plot([100 * p[2] for p in front], [p[3] for p in front], "o-" if fam in DEPLOYABLE else "s--",
                        ms=4, color=colors(k), label=fam)
        shipped = shipped_gru(points)
        others = sorted((p for p in points if p[0] == "gru" and p is not shipped), key=lambda p: p[2])
        if others:  # the same recipe trained with other migration penalties
            ax.plot([100 * p[2] for p in others], [p[3] for p in others], "x:", ms=8, color="black",
                    label="gru (other penalties)")
        if shipped:
            ax.plot([100 * shipped[2]], [shipped[3]], "*", ms=14, color="black", label="gru (shipped)")
        ax.set_yscale("symlog", linthresh=1)
        ax.set_title(f"P = {P}")
        ax.set_xlabel("time-averaged imbalance (%)")
        ax.grid(alpha=0.3, which="both")
    for row in axes:
        row[0].set_ylabel("slices migrated per rollout (log above 1)")
    handles, labels = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="upper center", ncol=(len(labels) + 1) // 2, frameon=False, fontsize=8)
    fig.tight_layout(rect=(0, 0, 1, 1 - 0.6 / (4 * rows_n + 0.6)))
    return fig


def training_curve_table(rows):
    out = ["# GRU training curve (validation seeds, hard integer boundaries)", "",
           "Validation imbalance (time-averaged I_global, %) and migration (slices per rollout) of the GRU after "
           "each number of training steps, with the reactive rule on the same rollouts.", "",
           "| step | wall s | GRU imbalance % | GRU migration | reactive imbalance % | reactive migration |",
           "|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        out.append(f"| {int(float(r['step']))} | {float(r['wall_seconds']):.0f} | {100 * float(r['val_imbalance']):.3f} | "
                   f"{float(r['val_migration']):.1f} | {100 * float(r['reactive_imbalance']):.3f} | "
                   f"{float(r['reactive_migration']):.1f} |")
    return "\n".join(out) + "\n"


def training_curve_figure(rows):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    steps = [float(r["step"]) for r in rows]
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    for ax, key, ref, label, scale in ((axes[0], "val_imbalance", "reactive_imbalance", "imbalance (%)", 100),
                                       (axes[1], "val_migration", "reactive_migration", "slices migrated per rollout", 1)):
        ax.plot(steps, [scale * float(r[key]) for r in rows], "o-", label="GRU")
        ax.axhline(scale * float(rows[-1][ref]), color="tab:red", ls="--", label="reactive")
        ax.set_xlabel("training step")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
        top = ax.secondary_xaxis("top", functions=(
            lambda x: x * float(rows[-1]["wall_seconds"]) / max(1.0, steps[-1]),
            lambda t: t * max(1.0, steps[-1]) / float(rows[-1]["wall_seconds"])))
        top.set_xlabel("wall time (s)")
    axes[0].legend()
    fig.tight_layout()
    return fig


def _plt():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def _timed(rows):
    return [r for r in rows if r.get("seconds")]


def single_device_table(rows):
    out = ["# Single-device element-interaction time", "",
           "Mechanics only; seconds per 1000 iterations (measured over `steps` iterations and scaled), element-steps "
           "per second, and the density of the tissue: elements per cutoff cube around an element, candidates in "
           "its 27-bin stencil and neighbours within the cutoff.", "",
           "| backend | precision | elements | s / 1000 it. | element-steps/s | per cutoff cube | candidates | within cutoff |",
           "|---|---|---:|---:|---:|---:|---:|---:|"]
    for r in _timed(rows):
        out.append(f"| {r['backend']} | {r['precision']} | {r['elements']} | {float(r['s_per_1000_steps']):.3g} | "
                   f"{float(r['element_steps_per_s']):.3g} | {float(r['per_cutoff_cube']):.1f} | "
                   f"{float(r['candidates']):.0f} | {float(r['neighbours']):.0f} |")
    skipped = sorted({r["backend"] for r in rows if not r.get("seconds")})
    if skipped:
        out += ["", "Not run above their `max_cells` (too slow on this profile): " + ", ".join(skipped) + "."]
    return "\n".join(out) + "\n"


def single_device_figure(rows):
    plt = _plt()
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    xs_all = []
    for b in sorted({r["backend"] for r in rows}):
        pts = sorted((int(r["elements"]), float(r["s_per_1000_steps"])) for r in _timed(rows) if r["backend"] == b)
        if pts:
            ax.loglog([p[0] for p in pts], [p[1] for p in pts], "o-", label=b)
            xs_all += pts
    if xs_all:
        x0, y0 = min(xs_all)
        xs = [x0, max(p[0] for p in xs_all)]
        ax.loglog(xs, [y0 * x / x0 for x in xs], "k:", label="O(n)")
        ax.loglog(xs, [y0 * (x / x0) ** 2 for x in xs], "k--", label="O(n$^2$)")
    ax.set_xlabel("elements")
    ax.set_ylabel("seconds per 1000 iterations")
    ax.grid(alpha=0.3, which="both")
    ax.legend()
    fig.tight_layout()
    return fig


def accuracy_table(rows):
    out = ["# What accuracy costs in time", "",
           "Final element positions after the same simulated time against the reference run "
           f"({rows[0]['reference']}); RMS and maximum distance in um.", "",
           "| precision | cutoff (um) | dt (h) | steps | wall s | RMS error (um) | max error (um) |",
           "|---|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        out.append(f"| {r['precision']} | {r['cutoff']} | {r['dt']} | {r['steps']} | {float(r['wall_s']):.3g} | "
                   f"{float(r['rms_error_um']):.3g} | {float(r['max_error_um']):.3g} |")
    return "\n".join(out) + "\n"


def accuracy_figure(rows):
    plt = _plt()
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    for prec, marker in (("double", "o"), ("float", "x")):
        for cutoff in sorted({r["cutoff"] for r in rows}, key=float):
            pts = sorted((float(r["wall_s"]), float(r["rms_error_um"])) for r in rows
                         if r["precision"] == prec and r["cutoff"] == cutoff and float(r["rms_error_um"]) > 0)
            if pts:
                ax.loglog([p[0] for p in pts], [p[1] for p in pts], marker + "-", label=f"{prec}, cutoff {cutoff} um")
    ax.set_xlabel("wall time (s)")
    ax.set_ylabel("RMS position error (um)")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


def development_accuracy_table(rows):
    """accuracy_vs_time/development.csv (runner engine_observables): per run the wall time and the largest error over
    the sample times on each observable, then the observables over time."""
    runs = OrderedDict()
    for r in rows:
        runs.setdefault((r["precision"], r["dt"], r["cutoff"]), []).append(r)
    def worst(rs, col, scale=1.0):
        return max(abs(float(r[col])) for r in rs) * scale
    out = ["# What accuracy costs in time, on the developing epidermis", "",
           f"Day 0-5 of `scenes/epidermis_development.yaml` at {rows[0]['cells']} cells, one process, against the reference "
           f"run ({rows[0]['reference']}). Errors are the largest over the sample times: cells per type "
           "(sum over types of |n - n_ref| / cells of the reference, %), thickness (z extent of the tissue, um), the "
           "centre of the per-slice work W_s (um) and the work profile (share of W_s in other slices than the "
           "reference's, %).", "",
           "| precision | dt (h) | cutoff (um) | wall s | cells Day 5 (basal/spinous/granular) | cells error % | "
           "thickness error (um) | work centre error (um) | work profile error % |",
           "|---|---:|---:|---:|---|---:|---:|---:|---:|"]
    for (prec, dt, cutoff), rs in runs.items():
        last = rs[-1]
        out.append(f"| {prec} | {dt} | {cutoff} | {float(last['wall_s']):.3g} | {last['cells']} "
                   f"({last['basal']}/{last['spinous']}/{last['granular']}) | {worst(rs, 'cells_error', 100):.3g} | "
                   f"{worst(rs, 'thickness_error_um'):.3g} | {worst(rs, 'work_centre_error_um'):.3g} | "
                   f"{worst(rs, 'work_profile_error', 100):.3g} |")
    out += ["", "Over time (hours of simulated time):", "",
            "| h | precision | dt (h) | cutoff (um) | basal | spinous | granular | thickness (um) | work centre (um) | "
            "work profile error % |", "|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for hours in sorted({r["time_h"] for r in rows}, key=float):
        for (prec, dt, cutoff), rs in runs.items():
            for r in rs:
                if r["time_h"] == hours:
                    out.append(f"| {float(hours):g} | {prec} | {dt} | {cutoff} | {r['basal']} | {r['spinous']} | "
                               f"{r['granular']} | {float(r['thickness_um']):.3g} | {float(r['work_centre_um']):.4g} | "
                               f"{100 * float(r['work_profile_error']):.3g} |")
    return "\n".join(out) + "\n"


def development_accuracy_figure(rows):
    """accuracy_vs_time/development.csv: cells per type, thickness and the work-profile error over Day 0-5, one line
    style per run (the reference solid), wall time in the legend."""
    plt = _plt()
    runs = OrderedDict()
    for r in rows:
        runs.setdefault((r["precision"], r["dt"], r["cutoff"]), []).append(r)
    fig, axes = plt.subplots(1, 3, figsize=(13, 4))
    styles = ["-", "--", ":", "-."]
    for i, ((prec, dt, cutoff), rs) in enumerate(runs.items()):
        days = [float(r["time_h"]) / 24 for r in rs]
        label = f"{prec}, dt {dt} h, cutoff {cutoff} um ({float(rs[-1]['wall_s']):.3g} s)"
        ls = styles[i % len(styles)]
        for t, colour in (("basal", "tab:blue"), ("spinous", "tab:orange"), ("granular", "tab:green")):
            axes[0].plot(days, [int(r[t]) for r in rs], ls, color=colour, label=f"{t}" if i == 0 else None)
        axes[1].plot(days, [float(r["thickness_um"]) for r in rs], ls, color="k", label=label)
        axes[2].plot(days, [100 * float(r["work_profile_error"]) for r in rs], ls, color="k", label=label)
    axes[0].set_ylabel("cells (line style: run)")
    axes[1].set_ylabel("thickness: z extent (um)")
    axes[2].set_ylabel("work profile error (% of W_s in other slices)")
    for ax in axes:
        ax.set_xlabel("day")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    axes[1].legend(fontsize=7)
    fig.tight_layout()
    return fig


def effects_table(rows):
    out = ["# What each effect costs", "",
           "Time per step of each effect set (same tissue and backend) and the time of each phase.", "",
           "| effects | elements at end | ms / step | phases (s over the run) |", "|---|---:|---:|---|"]
    for r in rows:
        out.append(f"| {r['effects']} | {r['elements']} | {float(r['s_per_1000_steps']):.3g} | "
                   f"{r['phases'].replace(';', ', ')} |")
    return "\n".join(out) + "\n"


def effects_figure(rows):
    plt = _plt()
    fig, ax = plt.subplots(figsize=(7, 4))
    phases = []
    for r in rows:
        for item in r["phases"].split(";"):
            if item and item.split("=")[0] not in phases:
                phases.append(item.split("=")[0])
    bottom = [0.0] * len(rows)
    for ph in phases:
        vals = []
        for r in rows:
            d = dict(item.split("=") for item in r["phases"].split(";") if item)
            vals.append(1000 * float(d.get(ph, 0)) / int(r["steps"]))
        ax.bar(range(len(rows)), vals, bottom=bottom, label=ph)
        bottom = [b + v for b, v in zip(bottom, vals)]
    ax.set_xticks(range(len(rows)), [r["effects"].replace("+", "+\n") for r in rows], fontsize=7)
    ax.set_ylabel("ms per step")
    ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


def strong_scaling_table(rows):
    out = ["# Strong scaling", "",
           "Computation-only time T_p (slowest rank per rebalancing interval, summed), S_p = T_1/T_p, E_p = S_p/p; "
           "end-to-end: the time-stepping loop (communication, balancing and I/O included) with its own efficiency, "
           "and the whole launch (start-up included).", "",
           "| cells | ranks | elements | T_p compute (s) | S_p | E_p | loop (s) | E_p loop | launch (s) |",
           "|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for cells in sorted({r["cells"] for r in rows}, key=int):
        group = sorted((r for r in rows if r["cells"] == cells), key=lambda r: int(r["ranks"]))
        t1 = float(group[0]["compute_s"]) * int(group[0]["ranks"])
        w1 = float(group[0]["wall_s"]) * int(group[0]["ranks"])
        for r in group:
            p, t, w = int(r["ranks"]), float(r["compute_s"]), float(r["wall_s"])
            s = t1 / t if t > 0 else 0
            ew = w1 / w / p if w > 0 else 0
            out.append(f"| {cells} | {p} | {r['elements']} | {t:.3f} | {s:.2f} | {100 * s / p:.0f}% | {w:.2f} | "
                       f"{100 * ew:.0f}% | {float(r.get('total_s', 0)):.2f} |")
    return "\n".join(out) + "\n"


def load_balance_table(rows):
    many = "machine" in rows[0]  # GPU CSVs gathered from several machines name each row's machine
    out = ["# Load balancing end to end", "",
           "Runtime of the time-stepping loop (start-up excluded), computation-only time, mean global imbalance (T_max-T_min)/T_mean over the rebalancing "
           "intervals and migrated slices, per initial partition and policy.", "",
           "| initial | policy | runtime (s) | compute (s) | mean imbalance % | migrated slices |" + (" machine |" if many else ""),
           "|---|---|---:|---:|---:|---:|" + ("---|" if many else "")]
    for r in rows:
        out.append(f"| {r['initial']} | {r['policy']} | {float(r['wall_s']):.2f} | {float(r['compute_s']):.2f} | "
                   f"{100 * float(r['mean_imbalance']):.1f} | {r['migrated_slices']} |" + (f" {r['machine']} |" if many else ""))
    return "\n".join(out) + "\n"


def rank_balance_figure(rows):
    plt = _plt()
    policies = list(OrderedDict.fromkeys(r["policy"] for r in rows))
    fig, axes = plt.subplots(1, len(policies), figsize=(4 * len(policies), 3.5), sharey=True, squeeze=False)
    for ax, pol in zip(axes[0], policies):
        for rank in sorted({r["rank"] for r in rows}, key=int):
            pts = sorted((int(r["step"]), float(r["compute_s"])) for r in rows if r["policy"] == pol and r["rank"] == rank)
            ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-", label=f"rank {rank}")
        ax.set_title(pol)
        ax.set_xlabel("step")
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel("computation time per interval (s)")
    axes[0][0].legend(fontsize=8)
    fig.tight_layout()
    return fig


# t quantiles t_{0.975, df} for the 95% interval (df 1..30; beyond, the normal 1.96 is within 2%)
T975 = [12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201, 2.179, 2.160, 2.145, 2.131,
        2.120, 2.110, 2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042]


def t_interval(diffs):
    """Mean and 95% t-interval half-width of paired differences (n >= 2; half-width inf for n = 1)."""
    m = statistics.fmean(diffs)
    if len(diffs) < 2:
        return m, math.inf
    df = len(diffs) - 1
    return m, (T975[df - 1] if df <= len(T975) else 1.96) * statistics.stdev(diffs) / math.sqrt(len(diffs))


E2E_ORDER = [("static", "workload"), ("reactive", "workload"), ("gru", "workload"), ("gromacs_dlb", "workload"),
             ("static", "uniform")]
# The paper's end-to-end numbers (8 GPUs, 100,000 iterations): mean imbalance per policy, GRU's runtime change
# against static and reactive's migration over GRU's.
PAPER_E2E = {"static": "11.3%", "gru": "3.5%", "runtime": "-9.0%", "migration": "7.7x"}


def e2e_groups(rows):
    """(policy, initial) -> {launch: row}, in E2E_ORDER, then any other pair first seen first."""
    out = OrderedDict((k, {}) for k in E2E_ORDER)
    for r in rows:
        out.setdefault((r["policy"], r["initial"]), {})[r["launch"]] = r
    return OrderedDict((k, v) for k, v in out.items() if v)


def end_to_end_table(rows):
    """Mean ± sd over launches per policy, and each policy's difference to static (workload start) paired by
    launch with its 95% t-interval; loop time, computation time, mean I_global, migrated slices."""
    groups = e2e_groups(rows)
    base = groups.get(("static", "workload"), {})
    first = rows[0]
    out = ["# End to end: the developing epidermis, Day 0-5 (issue 18)", "",
           f"{first['ranks']} ranks, {first['gpus']} GPUs, {first['cells_start']} cells at the start, {first['steps']} steps; "
           f"machine: {first['machine']}. Mean ± sd over launches; Δ loop = the policy's loop time minus static's "
           "(workload start) in the same launch, mean and 95% t-interval over launches.", "",
           "| policy | initial | launches | cells end | loop (s) | compute (s) | mean imbalance % | migrated slices | "
           "Δ loop vs static (s) | Δ loop % |",
           "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for (pol, init), launches in groups.items():
        rs = list(launches.values())
        f = lambda c: mean_sd([float(r[c]) for r in rs])
        (lm, ls), (cm, cs), (im, isd), (mm, ms) = f("loop_s"), f("compute_s"), f("mean_imbalance"), f("migrated_slices")
        paired = [float(r["loop_s"]) - float(base[l]["loop_s"]) for l, r in launches.items() if l in base]
        if (pol, init) == ("static", "workload") or not paired:
            delta = pct = "-"
        else:
            d, h = t_interval(paired)
            sm = statistics.fmean(float(base[l]["loop_s"]) for l in launches if l in base)
            delta = f"{d:+.2f} [{d - h:+.2f}, {d + h:+.2f}]"
            pct = f"{100 * d / sm:+.1f}% [{100 * (d - h) / sm:+.1f}, {100 * (d + h) / sm:+.1f}]"
        out.append(f"| {pol} | {init} | {len(rs)} | {rs[0]['cells_end']} | {lm:.2f} ± {ls:.2f} | {cm:.2f} ± {cs:.2f} | "
                   f"{100 * im:.1f} ± {100 * isd:.1f} | {mm:.0f} ± {ms:.0f} | {delta} | {pct} |")
    return "\n".join(out) + "\n"


def end_to_end_figure(rows):
    """The load-balance figure: loop time, mean imbalance and migrated slices per policy (mean, sd bars)."""
    plt = _plt()
    groups = e2e_groups(rows)
    labels = [p if i == "workload" else f"{p} ({i})" for p, i in groups]
    fig, axes = plt.subplots(1, 3, figsize=(13, 3.6))
    for ax, (col, scale, title) in zip(axes, [("loop_s", 1, "runtime (s)"), ("mean_imbalance", 100, "mean imbalance (%)"),
                                              ("migrated_slices", 1, "migrated slices")]):
        stats = [mean_sd([scale * float(r[col]) for r in g.values()]) for g in groups.values()]
        ax.bar(range(len(stats)), [m for m, _ in stats], yerr=[s for _, s in stats], capsize=3, color="#2a7ab9")
        ax.set_xticks(range(len(stats)))
        ax.set_xticklabels(labels, rotation=30, ha="right", fontsize=8)
        ax.set_title(title)
        ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    return fig


# --- Replay on recorded engine traces (experiments/replay_score.yaml, analysis/trace_model.py) ---
def replay_score_table(rows):
    """Per trace (rows) and policy (columns): mean I_global % / migrated slices under `semlb replay --score`."""
    policies = list(OrderedDict.fromkeys(r["policy"] for r in rows))
    traces = list(OrderedDict.fromkeys(r["trace"] for r in rows))
    cell = {(r["trace"], r["policy"]): r for r in rows}
    out = ["# Policies replayed on recorded engine traces", "",
           "Each trace's `slice_work` taken as the true work (`semlb replay --score`): mean I_global % / migrated "
           "slices per policy, from the trace's first partition. foresight: the offline floor (not deployable).", "",
           "| trace | P | events | " + " | ".join(policies) + " |",
           "|---|---:|---:|" + "---|" * len(policies)]
    for t in traces:
        first = next(cell[(t, p)] for p in policies if (t, p) in cell)
        vals = [f"{100 * float(cell[(t, p)]['mean_imbalance']):.2f} / {cell[(t, p)]['migration']}" if (t, p) in cell
                else "—" for p in policies]
        out.append(f"| {t} | {first['ranks']} | {first['events']} | " + " | ".join(vals) + " |")
    mean = {p: [float(cell[(t, p)]["mean_imbalance"]) for t in traces if (t, p) in cell] for p in policies}
    mig = {p: [float(cell[(t, p)]["migration"]) for t in traces if (t, p) in cell] for p in policies}
    out.append("| **mean over traces** | | | " + " | ".join(
        f"**{100 * sum(mean[p]) / len(mean[p]):.2f} / {sum(mig[p]) / len(mig[p]):.1f}**" for p in policies) + " |")
    return "\n".join(out) + "\n"


def trace_model_table(rows):
    """analysis/trace_model.py's CSV: R^2 and relative error of the per-slice work model per trace."""
    out = ["# Per-slice work model against measured rank times", "",
           "Predicted rank time = sum of `slice_work` over the rank's slices on the recorded partition; R^2 around "
           "each event's mean rank time. `modelled` traces have R^2 = 1 by construction and are not pooled.", "",
           "| trace | timing | P | events | points | R^2 | mean rel. error % | max rel. error % |",
           "|---|---|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        out.append(f"| {r['trace']} | {r['timing']} | {r['ranks']} | {r['events']} | {r['points']} | "
                   f"{float(r['r2']):.3f} | {100 * float(r['mean_rel_error']):.1f} | {100 * float(r['max_rel_error']):.1f} |")
    return "\n".join(out) + "\n"


REPORTS = {
    # csv (relative to results) -> [(output, builder[, another csv the builder also reads, empty if absent])]
    "controller_eval/controller_eval.csv": [("tables/controller_eval.md", controller_table),
                                            ("figures/controller_eval.png", controller_figure)],
    "controller_long/controller_long.csv": [("tables/controller_long.md", controller_table)],
    "holt_tuning/holt_tuning.csv": [("tables/holt_tuning.md", holt_tuning_table)],
    "foresight_frontier/foresight_frontier.csv": [("tables/foresight_frontier.md", frontier_table,
                                                   "controller_eval/controller_eval.csv")],
    "frontier/frontier.csv": [("tables/frontier.md", balancer_frontier_table),
                              ("figures/frontier.png", balancer_frontier_figure)],
    "training_curve/training_curve.csv": [("tables/training_curve.md", training_curve_table),
                                          ("figures/training_curve.png", training_curve_figure)],
    "single_device/single_device.csv": [("tables/single_device.md", single_device_table),
                                        ("figures/single_device.png", single_device_figure)],
    "accuracy_vs_time/accuracy_vs_time.csv": [("tables/accuracy_vs_time.md", accuracy_table),
                                              ("figures/accuracy_vs_time.png", accuracy_figure)],
    "accuracy_vs_time/development.csv": [("tables/accuracy_development.md", development_accuracy_table),
                                         ("figures/accuracy_development.png", development_accuracy_figure)],
    "effects_cost/effects_cost.csv": [("tables/effects_cost.md", effects_table),
                                      ("figures/effects_cost.png", effects_figure)],
    "strong_scaling/strong_scaling.csv": [("tables/strong_scaling.md", strong_scaling_table)],
    "load_balance/load_balance.csv": [("tables/load_balance.md", load_balance_table)],
    "rank_balance/rank_balance.csv": [("figures/rank_balance.png", rank_balance_figure)],
    "end_to_end/load_balance.csv": [("tables/end_to_end.md", end_to_end_table),
                                    ("figures/end_to_end_load_balance.png", end_to_end_figure)],
    "end_to_end/rank_balance.csv": [("figures/end_to_end_rank_balance.png", rank_balance_figure)],
    "replay_score/replay_score.csv": [("tables/replay_score.md", replay_score_table)],
    "trace_model/trace_model.csv": [("tables/trace_model.md", trace_model_table)],
}


# REPORT.md's order: the paper's (Sec. V: single device, scaling, load balancing, controllers, use case).
REPORT_ORDER = ["single_device", "accuracy_vs_time", "accuracy_development", "effects_cost", "strong_scaling", "load_balance", "rank_balance",
                "end_to_end", "end_to_end_load_balance", "end_to_end_rank_balance", "controller_eval", "controller_long",
                "holt_tuning", "foresight_frontier", "frontier", "replay_score", "trace_model", "training_curve", "development", "epidermis"]


def provenance(results, csv_rel):
    """'profile P, `command`' from the sweep's copy of its manifest (CSV.manifest.yaml), else ''."""
    path = os.path.join(results, os.path.splitext(csv_rel)[0] + ".manifest.yaml")
    if not os.path.exists(path):
        return ""
    with open(path) as f:
        first = f.readline().strip().lstrip("# ")
    profile = first.split("--profile ")[1].split()[0] if "--profile " in first else "?"
    return f"profile {profile}: `{first}`"


def write_report(results, made):
    """results/REPORT.md: every table (inline) and figure made, in the paper's order, each under the CSV, profile
    and command it came from; the end-to-end section quotes the paper's numbers beside ours."""
    def rank(out):
        stem = os.path.splitext(os.path.basename(out))[0]
        return REPORT_ORDER.index(stem) if stem in REPORT_ORDER else len(REPORT_ORDER)
    lines = ["# semlb results", "", f"Generated by analysis/report.py from {results}/.", ""]
    for out, csv_rel in sorted(made, key=lambda m: rank(m[0])):
        lines.append(f"## {out}")
        src = provenance(results, csv_rel) if csv_rel else ""
        lines.append(f"From `{csv_rel}`" + (f", {src}" if src else "") + "." if csv_rel else "From the Makefile's run.")
        lines.append("")
        if out.endswith(".md"):
            with open(os.path.join(results, out)) as f:
                lines.append(f.read().replace("\n# ", "\n### ").removeprefix("# "))
        else:
            lines.append(f"![{out}]({out})")
        if os.path.basename(out).startswith("end_to_end"):
            lines.append("")
            lines.append(f"Paper (8 GPUs, 435,661 cells, 100,000 iterations): static {PAPER_E2E['static']} mean imbalance, "
                         f"GRU {PAPER_E2E['gru']}; GRU runtime {PAPER_E2E['runtime']} against static; reactive migrates "
                         f"{PAPER_E2E['migration']} the slices of GRU.")
        lines.append("")
    atomic_write(os.path.join(results, "REPORT.md"), "\n".join(lines))
    print(f"report: wrote {os.path.join(results, 'REPORT.md')}")


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--results", default="results", help="results directory (default: results)")
    args = ap.parse_args()
    made = []  # (output, csv) in the order made
    for rel, outputs in REPORTS.items():
        path = os.path.join(args.results, rel)
        if not os.path.exists(path):
            continue
        rows = read_rows(path)
        if not rows:
            print(f"report: {path}: no rows", file=sys.stderr)
            return 2
        for out, build, *also in outputs:
            more = [read_rows(p) if os.path.exists(p) else [] for p in (os.path.join(args.results, a) for a in also)]
            atomic_write(os.path.join(args.results, out), build(rows, *more))
            print(f"report: wrote {os.path.join(args.results, out)}")
            made.append((out, rel))
    for fig in ("figures/development.png", "figures/epidermis.png"):  # rendered by the Makefile
        if os.path.exists(os.path.join(args.results, fig)):
            made.append((fig, ""))
    if not [m for m in made if m[1]]:
        print(f"report: no known CSV under {args.results}/ (run make experiments)", file=sys.stderr)
        return 2
    write_report(args.results, made)
    return 0


if __name__ == "__main__":
    sys.exit(main())
