"""Report section (beyond the paper's figures): what each effect of the epidermis scene costs per step."""
from .common import Part, md_table, plt, register

CSV = "effects_cost/effects_cost.csv"
GPU = "gpu/effects_cost/effects_cost.csv"


def phases(row):
    """Phase -> seconds summed over the run, in the row's order."""
    return {k: float(v) for k, v in (item.split("=") for item in row["phases"].split(";") if item)}


def ms_per_step(row):
    """The one definition of ms per step: wall seconds over the timed steps x 1000 (= s_per_1000_steps)."""
    return 1000.0 * float(row["seconds"]) / int(row["steps"])


def split(row):
    """Phase -> ms per step: ms_per_step shared out by each phase's share of the summed phase timers (the timers
    overlap and include synchronisation, so their sum is not the step time)."""
    ph = phases(row)
    total = sum(ph.values())
    return {k: ms_per_step(row) * v / total if total > 0 else 0.0 for k, v in ph.items()}


def table(rows, title):
    names = []
    for r in rows:
        names += [k for k in phases(r) if k not in names]
    out = [f"# {title}", "",
           f"ms per step = wall time over the {rows[0]['steps']} timed steps / steps x 1000 (the figure's bar height). "
           "Phase columns: each phase's share of the summed phase timers, in % (the timers overlap, so their sum "
           "is not the step time).", "",
           ]
    body = []
    for r in rows:
        ph = phases(r)
        total = sum(ph.values()) or 1.0
        body.append((r["effects"], r["elements"], f"{ms_per_step(r):.2f}",
                     *(f"{100 * ph[n] / total:.0f}" if n in ph else "-" for n in names)))
    out.append(md_table(["effects", "elements at end", "ms / step"] + [f"{n} %" for n in names], body,
                        align="lrr" + "r" * len(names)))
    return "\n".join(out) + "\n"


def figure(rows, where):
    """Stacked bars: ms per step of each effect set, split by phase shares; the value on top of each bar."""
    p = plt()
    fig, ax = p.subplots(figsize=(8, 4.5))
    names = []
    for r in rows:
        names += [k for k in phases(r) if k not in names]
    bottom = [0.0] * len(rows)
    for n in names:
        vals = [split(r).get(n, 0.0) for r in rows]
        ax.bar(range(len(rows)), vals, bottom=bottom, label=n)
        bottom = [b + v for b, v in zip(bottom, vals)]
    for i, r in enumerate(rows):
        ax.annotate(f"{ms_per_step(r):.2f}", (i, bottom[i]), xytext=(0, 2), textcoords="offset points", ha="center",
                    fontsize=8)
    ax.set_xticks(range(len(rows)), [r["effects"].replace("+", "+\n") for r in rows], fontsize=7)
    ax.set_xlabel("effects in the scene")
    ax.set_ylabel("wall time per step (ms)")
    ax.set_title(where, fontsize=9)
    ax.set_ylim(0, max(bottom) * 1.15 if bottom else 1)
    ax.legend(fontsize=8, title="phase (share of timers)", title_fontsize=8)
    ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    return fig


def build(ctx):
    runs = []
    rows = ctx.rows(CSV)
    if rows:
        effects = ctx.names("effects")
        note = f"`all` = every effect the binary registers: {', '.join(effects)} (`semlb list effects`).\n\n"
        where = (f"this run: {rows[0]['backend']}, {rows[0]['precision']}, {rows[0]['cells']} cells, "
                 f"{rows[0]['steps']} steps, {__import__('os').cpu_count()} shared cores")
        runs.append(("This run", ctx.cpu_run(CSV, "1", 1, "-", f"{rows[0]['steps']} timed steps per row"),
                     ctx.source(CSV) + "\n\n" + note + ctx.table("effects_cost", table(rows, "What each effect costs, this run"))
                     + "\n" + ctx.figure("effects_cost", figure(rows, where))))
    gpu = ctx.committed_rows(GPU)
    if gpu:
        card = ctx.committed_gpu(GPU)
        where = f"one {card}: {gpu[0]['backend']}, {gpu[0]['precision']}, {gpu[0]['cells']} cells, {gpu[0]['steps']} steps"
        runs.append(("Committed paper profile (GPU)",
                     f"profile **paper** · machine: 1 {card} ({gpu[0].get('device', '?')}) · ranks: 1 · cores: - · "
                     f"launches: 1 per row · intervals: - · {gpu[0]['steps']} timed steps per row",
                     "From " + ctx.committed_source(GPU) + ".\n\n"
                     + ctx.table("effects_cost_gpu", table(gpu, f"What each effect costs, one {card}")) + "\n"
                     + ctx.figure("effects_cost_gpu", figure(gpu, where))))
    if not runs:
        return None
    return Part(runs, "Not in the paper (its timings are of the element interactions only).",
                "No paper comparison. Each row is one timed run: differences of a few % (or, on the GPU, the cell "
                "stage's uneven cost from one run to the next) are run-to-run noise, so an effect set can time faster "
                "than a subset of it.")


register("effects_cost", 12, "What each effect of the scene costs per step", build, [CSV])
