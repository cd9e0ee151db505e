"""Report section for the paper's load-balance figure: runtime, mean imbalance and migration per policy."""
import os
import statistics
from collections import OrderedDict

from .common import Part, gpu_machines, md_table, mean_sd, order_policies, plt, register, t_interval

CSV = "load_balance/load_balance.csv"
E2E = "end_to_end/load_balance.csv"
GPU = [("gpu/load_balance/load_balance_435661_4ranks_4gpus.csv", "C"),
       ("gpu/load_balance/load_balance_435661_8ranks_8gpus.csv", "D")]
PAPER = {"static": 11.3, "reactive": 3.8, "gru": 3.5}
PAPER_LINE = ("8 L40S GPUs, 435K cells, 100,000 iterations: mean imbalance static 11.3%, reactive 3.8%, RNN 3.5%; "
              "RNN runtime 9.0% below static and comparable to (slightly below) reactive; reactive migrates 7.7x the "
              "slices of the RNN.")
E2E_ORDER = [("static", "workload"), ("reactive", "workload"), ("gru", "workload"), ("gromacs_dlb", "workload"),
             ("static", "uniform")]


def load_balance_table(rows):
    """One row per run: loop, compute, mean I_global, migrated slices (and the machine where rows name one)."""
    many = "machine" in rows[0]
    out = ["# Load balancing end to end", "",
           "Runtime of the time-stepping loop (start-up excluded), computation-only time, mean global imbalance "
           "(T_max-T_min)/T_mean over the rebalancing intervals and migrated slices, per initial partition and policy.",
           "", md_table(["initial", "policy", "runtime (s)", "compute (s)", "mean imbalance %", "migrated slices"]
                        + (["machine"] if many else []),
                        [(r["initial"], r["policy"], f"{float(r['wall_s']):.2f}", f"{float(r['compute_s']):.2f}",
                          f"{100 * float(r['mean_imbalance']):.1f}", r["migrated_slices"])
                         + ((r["machine"],) if many else ()) for r in rows], align="llrrrr" + ("l" if many else ""))]
    return "\n".join(out) + "\n"


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
           f"{first['ranks']} ranks, {first['gpus']} GPUs, {first['cells_start']} cells at the start, {first['steps']} "
           f"steps; machine: {first['machine']}. Mean ± sd over launches; Δ loop = the policy's loop time minus "
           "static's (workload start) in the same launch, mean and 95% t-interval over launches.", "",
           ]
    body = []
    for (pol, init), launches in groups.items():
        rs = list(launches.values())
        f = lambda c: mean_sd([float(r[c]) for r in rs])  # noqa: E731
        (lm, ls), (cm, cs), (im, isd), (mm, ms) = f("loop_s"), f("compute_s"), f("mean_imbalance"), f("migrated_slices")
        paired = [float(r["loop_s"]) - float(base[l]["loop_s"]) for l, r in launches.items() if l in base]
        if (pol, init) == ("static", "workload") or not paired:
            delta = pct = "-"
        else:
            d, h = t_interval(paired)
            sm = statistics.fmean(float(base[l]["loop_s"]) for l in launches if l in base)
            delta = f"{d:+.2f} [{d - h:+.2f}, {d + h:+.2f}]"
            pct = f"{100 * d / sm:+.1f}% [{100 * (d - h) / sm:+.1f}, {100 * (d + h) / sm:+.1f}]"
        body.append((pol, init, len(rs), rs[0]["cells_end"], f"{lm:.2f} ± {ls:.2f}", f"{cm:.2f} ± {cs:.2f}",
                     f"{100 * im:.1f} ± {100 * isd:.1f}", f"{mm:.0f} ± {ms:.0f}", delta, pct))
    out.append(md_table(["policy", "initial", "launches", "cells end", "loop (s)", "compute (s)", "mean imbalance %",
                         "migrated slices", "Δ loop vs static (s)", "Δ loop %"], body, align="llrrrrrrrr"))
    return "\n".join(out) + "\n"


def groups_of(rows, loop_col):
    """label -> {'loop': [...], 'imb': [% ...], 'mig': [...]} per (policy, initial), one value per launch/run."""
    out = OrderedDict()
    rank = {p: i for i, p in enumerate(order_policies(r["policy"] for r in rows))}
    keyed = sorted(rows, key=lambda r: (r["initial"] != "workload", rank[r["policy"]]))
    for r in keyed:
        lab = r["policy"] if r["initial"] == "workload" else f"{r['policy']} ({r['initial']})"
        g = out.setdefault(lab, {"loop": [], "imb": [], "mig": []})
        g["loop"].append(float(r[loop_col]))
        g["imb"].append(100 * float(r["mean_imbalance"]))
        g["mig"].append(float(r["migrated_slices"]))
    return out


def figure(groups, where, paper=True):
    """Three panels as the paper's: runtime, mean imbalance, migrated slices per policy. Bars: the mean over
    launches; dots: each launch; whiskers: the range of the launches (no spread drawn for one launch); n under each
    bar. The paper's imbalances as open diamonds."""
    p = plt()
    fig, axes = p.subplots(1, 3, figsize=(13, 4.2))
    labels = list(groups)
    for ax, (key, title) in zip(axes, [("loop", "runtime of the loop (s)"), ("imb", "mean global imbalance (%)"),
                                       ("mig", "migrated slices")]):
        for i, lab in enumerate(labels):
            vals = groups[lab][key]
            m = sum(vals) / len(vals)
            ax.bar(i, m, color="#2a7ab9", alpha=0.75)
            ax.plot([i] * len(vals), vals, "k.", ms=6)
            if len(vals) > 1:
                ax.plot([i, i], [min(vals), max(vals)], "k-", lw=1)
            ax.annotate(f"n={len(vals)}", (i, 0), xytext=(0, 2), textcoords="offset points", ha="center",
                        fontsize=7, color="white" if m > 0 else "k")
        if key == "imb" and paper:
            xs = [i for i, lab in enumerate(labels) if lab in PAPER]
            ax.plot(xs, [PAPER[labels[i]] for i in xs], "D", mfc="none", mec="tab:red", ms=8, label="paper (8 L40S)")
            ax.legend(fontsize=7)
        ax.set_xticks(range(len(labels)))
        ax.set_xticklabels(labels, rotation=30, ha="right", fontsize=8)
        ax.set_ylim(bottom=0)
        ax.set_title(title, fontsize=10)
        ax.grid(axis="y", alpha=0.3)
    fig.suptitle(where + " · bar: mean, dots: launches, whisker: their range", fontsize=9)
    fig.tight_layout()
    return fig


def summary(groups):
    """'static I% / reactive I% M / gru I% M, gru loop x% vs static' from groups_of."""
    g = {k: v for k, v in groups.items()}
    m = lambda k, c: sum(g[k][c]) / len(g[k][c])  # noqa: E731
    parts = []
    for pol in ("static", "reactive", "gru"):
        if pol in g:
            parts.append(f"{pol} {m(pol, 'imb'):.1f}%" + (f" / {m(pol, 'mig'):.0f} slices" if pol != "static" else ""))
    text = ", ".join(parts)
    ok = None
    if all(k in g for k in ("static", "reactive", "gru")):
        dt = 100 * (m("gru", "loop") / m("static", "loop") - 1)
        ratio = m("reactive", "mig") / m("gru", "mig") if m("gru", "mig") > 0 else float("inf")
        text += f"; gru loop {dt:+.1f}% vs static, reactive migrates {ratio:.1f}x gru's slices"
        ok = m("gru", "imb") <= m("reactive", "imb") <= m("static", "imb") and dt < 0 and ratio > 1
    return ok, text


def build(ctx):
    runs, verdicts = [], []
    cores = os.cpu_count()
    small = ctx.rows(CSV)
    if small:
        ranks = ctx.manifest_setting(CSV, "ranks", "?")
        n = small[0].get("events", "?")
        g = groups_of(small, "wall_s")
        where = f"small profile: {ranks} CPU ranks time-sharing {cores} cores, 1 launch per policy, {n} intervals"
        runs.append(("This run: scenes/epidermis.yaml", ctx.cpu_run(CSV, str(ranks), 1, n,
                                                                    "ranks oversubscribed: timing mostly scheduler noise"),
                     ctx.source(CSV) + "\n\n" + ctx.table("load_balance", load_balance_table(small)) + "\n"
                     + ctx.figure("load_balance", figure(g, where))))
        verdicts.append(("CPU epidermis", summary(g)))
    e2e = ctx.rows(E2E)
    if e2e:
        launches = len({r["launch"] for r in e2e})
        steps = int(e2e[0]["steps"])
        every = ctx.manifest_setting(E2E, "rebalance_every", None)
        n = str(steps // int(every)) if every else "?"
        g = groups_of(e2e, "loop_s")
        where = (f"Day 0-5: {e2e[0]['ranks']} CPU ranks time-sharing {cores} cores, {launches} launches, {n} intervals")
        runs.append(("This run: Day 0-5 of the developing epidermis (end_to_end)",
                     ctx.cpu_run(E2E, e2e[0]["ranks"], launches, n, "ranks oversubscribed; 95% t-intervals over "
                                 f"{launches} launches"),
                     ctx.source(E2E) + "\n\n" + ctx.table("end_to_end", end_to_end_table(e2e)) + "\n"
                     + ctx.figure("end_to_end_load_balance", figure(g, where))))
        verdicts.append(("CPU Day 0-5", summary(g)))
    machines = gpu_machines()
    for rel, letter in GPU:
        rows = ctx.committed_rows(rel)
        if not rows:
            continue
        ranks = "4" if "4ranks" in rel else "8"
        mine = [r for r in rows if r.get("machine") == letter]
        n = rows[0]["events"]
        where = f"{ranks} ranks on {machines.get(letter, '?')} H200s (machine {letter}), 1 launch per policy, {n} intervals"
        g = groups_of(mine, "wall_s")
        name = f"load_balance_gpu_{ranks}"
        runs.append((f"Committed paper profile (GPU, {ranks} ranks on {ranks} H200s)",
                     f"profile **paper** (435,661 cells growing to {rows[0]['elements']} elements, 2,000 steps) · "
                     f"machine: {', '.join(sorted({r.get('machine', '?') for r in rows}))} "
                     f"(figure: machine {letter} only, one machine's rows) · ranks: {ranks} (one H200 each) · cores: - · "
                     f"launches: 1 per row · intervals: {n}",
                     "From " + ctx.committed_source(rel) + ".\n\n" + ctx.table(name, load_balance_table(rows)) + "\n"
                     + ctx.figure(name, figure(g, where))))
        verdicts.append((f"{ranks}xH200", summary(g)))
    if not runs:
        return None
    reading = " · ".join(f"{k}: {t}" for k, (_, t) in verdicts)
    gpu = [(k, ok) for k, (ok, _) in verdicts if "H200" in k]
    if gpu:
        held = [k for k, ok in gpu if ok]
        reading += (". The paper's result (RNN lowest imbalance, shorter than static, far less migration than "
                    f"reactive) holds on {', '.join(held) if held else 'none of the GPU runs'}"
                    + ("" if len(held) == len(gpu) else "; not supported on " + ", ".join(k for k, ok in gpu if not ok))
                    + ". One launch per row: launch-to-launch differences in rank speed (docs/engine.md) are as large as "
                    "the policy differences. The CPU rows time-share the cores and do not test the claim.")
    brief = ("; ".join(f"{k}: " + t.split(";")[0] for k, (_, t) in verdicts if "H200" in k)
               + " (paper 11.3 / 3.8 / 3.5%)") if gpu else ""
    cpu = "; ".join(f"{k}: " + t.split(";")[0] for k, (_, t) in verdicts if "H200" not in k)
    return Part(runs, PAPER_LINE, reading, all(ok for _, ok in gpu) if gpu else None, brief,
                this_run=cpu + " (CPU ranks time-share the cores: no test of the claim)" if cpu else "")


register("load_balance", 4, "End-to-end load balancing: runtime, mean imbalance and migrated slices", build, [CSV, E2E],
         paper="fig:load_balance", claim="imbalance static 11.3%, reactive 3.8%, RNN 3.5%; RNN runtime -9.0% vs static")
