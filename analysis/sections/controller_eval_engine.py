"""Report section: the controller evaluation on the engine's own workloads (issue 25; replays through the time model)."""
import os
import sys

from .common import Part, register, setup as setup_line

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import engine_eval  # noqa: E402  (analysis/engine_eval.py: the tables and the targets, also a command of its own)

CSV = "controller_eval_engine/controller_eval_engine.csv"
COMMITTED = "gpu/workloads/controller_eval_engine_paper.csv"
PAPER_LINE = ("The paper evaluates the controllers on synthetic surrogate scenarios only (\"requiring no measured "
              "execution traces for training\") and claims the RNN lowers imbalance relative to reactive with far "
              "less migration; it reports no evaluation on recorded engine workloads.")


def run_part(ctx, rows, name, setup, source):
    """(setup, body) of one CSV, and its target summary."""
    points = engine_eval.read_points_rows(rows)
    body = source + "\n\n" + ctx.table(name, "# Controllers on engine workloads\n" + engine_eval.render(points))
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
