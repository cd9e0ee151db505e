"""Report section (beyond the paper's figures): Holt smoothing parameters tuned on training seeds."""
import statistics
from collections import OrderedDict

from .common import Part, md_table, register


def holt_tuning_table(rows):
    """Mean imbalance per (alpha, beta) over training seeds and ranks; the best pair first."""
    cells = OrderedDict()
    for r in rows:
        cells.setdefault((float(r["holt.alpha"]), float(r["holt.beta"])), []).append(r)
    scored = sorted((statistics.fmean(float(r["mean_imbalance"]) for r in rs),
                     statistics.fmean(float(r["migration"]) for r in rs), a, b) for (a, b), rs in cells.items())
    out = ["# Holt smoothing parameters (training seeds only)", "",
           "Mean over the grid's ranks and training seeds; sorted by imbalance (lower is better).", "",
           md_table(["alpha", "beta", "imbalance %", "migration"],
                    [(f"{a:g}", f"{b:g}", f"{100 * i:.3f}", f"{m:.0f}") for i, m, a, b in scored], align="rrrr")]
    return "\n".join(out) + "\n"



CSV = "holt_tuning/holt_tuning.csv"


def build(ctx):
    rows = ctx.rows(CSV)
    if not rows:
        return None
    ranks = ",".join(sorted({r["ranks"] for r in rows}, key=int))
    return Part([("This run (surrogate, training seeds)", ctx.cpu_run(CSV, ranks, 1, f"{rows[0].get('events', '?')} events per rollout",
                                                                  what="the surrogate, no engine"),
                  ctx.source(CSV) + "\n\n" + ctx.table("holt_tuning", holt_tuning_table(rows)))],
                "The paper names Holt-based forecasting (its refs.) without its smoothing parameters.",
                "Sets the holt policy's alpha and beta used in the controller evaluation; nothing to compare.")


register("holt_tuning", 14, "Holt smoothing parameters (training seeds)", build, [CSV])
