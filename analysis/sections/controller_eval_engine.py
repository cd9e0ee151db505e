"""Report section: the controller evaluation on the engine's own workloads (replays through the time model)."""
import os
import sys

from .common import Part, plt as _pyplot, register, setup as setup_line
from .frontier import DEPLOYABLE, pareto_front

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import engine_eval  # noqa: E402  (analysis/engine_eval.py: the tables and the targets, also a command of its own)

CSV = "controller_eval_engine/controller_eval_engine.csv"
COMMITTED = "gpu/workloads/controller_eval_engine_paper.csv"
PAPER_LINE = ("The paper evaluates the controllers on synthetic surrogate scenarios only (\"requiring no measured "
              "execution traces for training\") and claims the RNN lowers imbalance relative to reactive with far "
              "less migration; it reports no evaluation on recorded engine workloads.")


def pareto_figure(points_by_key, workload):
    """One workload's imbalance-migration plane, a panel per P: every deployable family's knob settings and their
    front, static, persistence/holt, every GRU weights file (the shipped one as a large star) and the foresight floor."""
    plt = _pyplot()
    ranks = sorted(P for (w, P) in points_by_key if w == workload)
    fig, axes = plt.subplots(1, len(ranks), figsize=(4.2 * len(ranks), 4.4), squeeze=False)
    for ax, P in zip(axes[0], ranks):
        points = points_by_key[(workload, P)]
        for fam in DEPLOYABLE:
            mine = [(p["policy"], p["setting"], p["imbalance"], p["migration"]) for p in points if p["policy"] == fam]
            if not mine:
                continue
            dots = ax.scatter([p[3] for p in mine], [100 * p[2] for p in mine], s=9, alpha=0.35)
            front = pareto_front(mine)
            ax.plot([p[3] for p in front], [100 * p[2] for p in front], "-", lw=1, color=dots.get_facecolor()[0],
                    label=fam)
        for p in points:
            x, y = p["migration"], 100 * p["imbalance"]
            if p["policy"] == "gru":
                shipped = p["setting"] == ""
                ax.scatter([x], [y], marker="*", s=220 if shipped else 70, color="crimson" if shipped else "grey",
                           edgecolor="black", linewidth=0.5, zorder=5, label="gru (shipped)" if shipped else None)
                if not shipped:
                    ax.annotate(p["setting"].removeprefix("weights=").removesuffix(".h5"), (x, y), fontsize=6,
                                xytext=(3, 3), textcoords="offset points")
            elif p["policy"] in ("static", "persistence", "holt") or (p["policy"] == "foresight" and p["setting"] == "lambda=0"):
                ax.scatter([x], [y], marker={"static": "s", "foresight": "v"}.get(p["policy"], "D"), s=40,
                           color="black", zorder=4)
                ax.annotate(p["policy"], (x, y), fontsize=7, xytext=(3, -9), textcoords="offset points")
        ax.set_yscale("log")
        ax.set_title(f"P = {P}")
        ax.set_xlabel("slices moved over the run")
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel("mean imbalance (%)")
    handles, labels = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=len(labels), fontsize=8, frameon=False)
    fig.suptitle(f"{os.path.basename(workload)}: imbalance against migration (means over the replay seeds; lines: each "
                 "family's front over its knob)", fontsize=10)
    fig.tight_layout(rect=(0, 0.06, 1, 1))
    return fig


def run_part(ctx, rows, name, setup, source):
    """(setup, body) of one CSV, and its target summary; a Pareto figure (a panel per P) per workload."""
    points = engine_eval.read_points_rows(rows)
    body = source + "\n\n"
    for w in sorted({w for (w, _) in points}):
        stem = os.path.splitext(os.path.basename(w))[0]
        body += ctx.figure(f"{name}_{stem}", pareto_figure(points, w))
    body += "\n" + ctx.table(name, "# Controllers on engine workloads\n" + engine_eval.render(points))
    return setup, body, engine_eval.summary(points)


def build(ctx):
    runs, summary = [], None
    rows = ctx.rows(CSV)
    if rows:
        seeds = sorted({r["seed"] for r in rows})
        setup, body, summary = run_part(ctx, rows, "controller_eval_engine",
                                        ctx.cpu_run(CSV, ",".join(sorted({r["ranks"] for r in rows}, key=int)), 1,
                                                    "every recorded event", f"{len(seeds)} replay seed(s)",
                                                    what="replays of workloads recorded on one H200, no engine"),
                                        ctx.source(CSV))
        runs.append(("This run (replays of the committed test workloads)", setup, body))
    committed = ctx.committed_rows(COMMITTED)
    if committed:
        setup, body, s = run_part(ctx, committed, "controller_eval_engine_paper",
                                  setup_line("paper", "workloads recorded on 1 NVIDIA H200 (results/gpu/workloads/README.md), "
                                             "replayed on a CPU, no engine", "2,4,8,16", "-", 1, "every recorded event",
                                             "3 replay seeds"),
                                  "From " + ctx.committed_source(COMMITTED) + ".")
        runs.append(("Committed paper profile", setup, body))
        summary = summary or s
    if not runs:
        return None
    held = sum(h for h, _ in summary.values())
    total = sum(n for _, n in summary.values())
    reading = ("Targets of the shipped GRU per (workload, P): " +
               "; ".join(f"{name}: {h} of {n} hold" for name, (h, n) in sorted(summary.items())) +
               " (front: no deployable setting dominates it; reactive: less imbalance than reactive tau 0.02 alpha 0.5 "
               "with at most 5% more migration; gap: at least half of reactive's gap to foresight closed). The rank "
               "times come from the time model, which derives them from W_s (docs/controllers.md \"Time model\"), so "
               "policies that repartition on W_s (persistence, holt) are scored more favourably than a machine would.")
    return Part(runs, PAPER_LINE, reading, held == total, f"{held} of {total} targets hold")


register("controller_eval_engine", 5.5, "Controller evaluation on the engine's workloads: imbalance, migration, loop time",
         build, [CSV], paper="fig:rnn_prediction")
