"""Report sections (beyond the paper's figures): what accuracy costs in time, fixed tissue and Day 0-5."""
from collections import OrderedDict

from .common import Part, md_table, plt as _pyplot, register


def accuracy_table(rows):
    out = ["# What accuracy costs in time", "",
           "Final element positions after the same simulated time against the reference run "
           f"({rows[0]['reference']}); RMS and maximum distance in um.", "",
           md_table(["precision", "cutoff (um)", "dt (h)", "steps", "wall s", "RMS error (um)", "max error (um)"],
                    [(r["precision"], r["cutoff"], r["dt"], r["steps"], f"{float(r['wall_s']):.3g}",
                      f"{float(r['rms_error_um']):.3g}", f"{float(r['max_error_um']):.3g}") for r in rows],
                    align="lrrrrrr")]
    return "\n".join(out) + "\n"



def pair_exp_table(rows):
    """accuracy_vs_time/pair_exp.csv (experiments/accuracy_pair_exp.yaml): per exp of the pair force law and dt, the
    wall time and the error against the reference run, with the wall time against the built-in exp's at the same dt."""
    def same(r):  # the runs a row's wall time is held against: the builtin's at its precision, dt and cutoff
        return r["precision"], r["dt"], r["cutoff"]
    builtin = {same(r): float(r["wall_s"]) for r in rows if r["pair_exp"] == "builtin"}
    def ratio(r):
        base = builtin.get(same(r), 0.0)
        return f"{float(r['wall_s']) / base:.3f}" if base > 0 else "-"
    return "\n".join([
        "# The pair force law's exp", "",
        "Each exp of the pair force law (`backend.pair_exp`, docs/engine.md \"Pair exp\") against the reference run "
        f"({rows[0]['reference']}): at the reference's dt and cutoff the error is the exp's (and the precision's) alone.",
        "", md_table(["pair exp", "precision", "cutoff (um)", "dt (h)", "steps", "wall s", "wall / builtin's",
                      "RMS error (um)", "max error (um)"],
                     [(r["pair_exp"], r["precision"], r["cutoff"], r["dt"], r["steps"], f"{float(r['wall_s']):.3g}",
                       ratio(r), f"{float(r['rms_error_um']):.3g}", f"{float(r['max_error_um']):.3g}") for r in rows],
                     align="llrrrrrrr")]) + "\n"


def accuracy_figure(rows):
    plt = _pyplot()
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



def development_accuracy_table(rows, types):
    """accuracy_vs_time/development.csv (runner engine_observables): per run the wall time and the largest error over
    the sample times on each observable, then the observables over time. `types`: the cell-type names by index
    (`semlb list cell-types`), which name the CSV's cells-per-type columns."""
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
           md_table(["precision", "dt (h)", "cutoff (um)", "wall s", f"cells Day 5 ({'/'.join(types)})", "cells error %",
                     "thickness error (um)", "work centre error (um)", "work profile error %"],
                    [(prec, dt, cutoff, f"{float(rs[-1]['wall_s']):.3g}",
                      f"{rs[-1]['cells']} ({'/'.join(rs[-1][t] for t in types)})", f"{worst(rs, 'cells_error', 100):.3g}",
                      f"{worst(rs, 'thickness_error_um'):.3g}", f"{worst(rs, 'work_centre_error_um'):.3g}",
                      f"{worst(rs, 'work_profile_error', 100):.3g}") for (prec, dt, cutoff), rs in runs.items()],
                    align="lrrrlrrrr")]
    over = [(f"{float(hours):g}", prec, dt, cutoff, *(r[t] for t in types), f"{float(r['thickness_um']):.3g}",
             f"{float(r['work_centre_um']):.4g}", f"{100 * float(r['work_profile_error']):.3g}")
            for hours in sorted({r["time_h"] for r in rows}, key=float)
            for (prec, dt, cutoff), rs in runs.items() for r in rs if r["time_h"] == hours]
    out += ["", "Over time (hours of simulated time):", "",
            md_table(["h", "precision", "dt (h)", "cutoff (um)", *types, "thickness (um)", "work centre (um)",
                      "work profile error %"], over, align="rlrr" + "r" * (len(types) + 3))]
    return "\n".join(out) + "\n"



def development_accuracy_figure(rows, types):
    """accuracy_vs_time/development.csv: cells per type, thickness and the work-profile error over Day 0-5, one line
    style per run (the reference solid), wall time in the legend; `types` as development_accuracy_table's."""
    plt = _pyplot()
    runs = OrderedDict()
    for r in rows:
        runs.setdefault((r["precision"], r["dt"], r["cutoff"]), []).append(r)
    fig, axes = plt.subplots(1, 3, figsize=(13, 4))
    styles = ["-", "--", ":", "-."]
    for i, ((prec, dt, cutoff), rs) in enumerate(runs.items()):
        days = [float(r["time_h"]) / 24 for r in rs]
        label = f"{prec}, dt {dt} h, cutoff {cutoff} um ({float(rs[-1]['wall_s']):.3g} s)"
        ls = styles[i % len(styles)]
        for t, colour in zip(types, ("tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple")):
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



CSV = "accuracy_vs_time/accuracy_vs_time.csv"
EXP = "accuracy_vs_time/pair_exp.csv"
DEV = "accuracy_vs_time/development.csv"
GPU = "gpu/accuracy_vs_time/accuracy_vs_time.csv"
GPU_EXP = "gpu/accuracy_vs_time/pair_exp.csv"


def build(ctx):
    runs = []
    rows = ctx.rows(CSV)
    exp = ctx.rows(EXP)
    if rows or exp:
        body = (ctx.source(CSV) + "\n\n" + ctx.table("accuracy_vs_time", accuracy_table(rows)) + "\n"
                + ctx.figure("accuracy_vs_time", accuracy_figure(rows)) if rows else "")
        if exp:
            body += "\n" + ctx.source(EXP) + "\n\n" + ctx.table("accuracy_pair_exp", pair_exp_table(exp))
        runs.append(("This run", ctx.cpu_run(CSV if rows else EXP, "1", 1, "-", f"{len(rows or []) + len(exp or [])} runs"),
                     body))
    gpu, gpu_exp = ctx.committed_rows(GPU), ctx.committed_rows(GPU_EXP)
    if gpu or gpu_exp:
        card = ctx.committed_gpu(GPU if gpu else GPU_EXP)
        runs.append(("Committed paper profile (GPU)", f"profile **paper** · machine: 1 {card} · ranks: 1 · cores: - · "
                     "launches: 1 per row · intervals: -",
                     ("From " + ctx.committed_source(GPU) + ".\n\n" + ctx.table("accuracy_vs_time_gpu", accuracy_table(gpu))
                      if gpu else "")
                     + ("\nFrom " + ctx.committed_source(GPU_EXP) + ".\n\n"
                        + ctx.table("accuracy_pair_exp_gpu", pair_exp_table(gpu_exp)) if gpu_exp else "")))
    if not runs:
        return None
    return Part(runs, "Not in the paper (it states its parameters, not what they cost).",
                "No paper comparison: chooses the time step, precision and cutoff the other experiments use.")


def build_dev(ctx):
    rows = ctx.rows(DEV)
    if not rows:
        return None
    runs = len({(r["precision"], r["dt"], r["cutoff"]) for r in rows})
    types = ctx.names("cell-types")  # the CSV's cells-per-type columns, by type index
    body = (ctx.source(DEV) + "\n\n" + ctx.table("accuracy_development", development_accuracy_table(rows, types)) + "\n"
            + ctx.figure("accuracy_development", development_accuracy_figure(rows, types)))
    return Part([("This run", ctx.cpu_run(DEV, "1", 1, "-", f"{runs} runs, {len(rows) // max(1, runs)} sample times"), body)],
                "Not in the paper.", "No paper comparison: the error each setting makes on Day 0-5.")


register("accuracy_vs_time", 10, "What accuracy costs in time (time step, precision, cutoff, pair exp)", build,
         [CSV, EXP])
register("accuracy_development", 11, "What accuracy costs on the developing epidermis, Day 0-5", build_dev, [DEV])
