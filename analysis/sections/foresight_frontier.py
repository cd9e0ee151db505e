"""Report section (beyond the paper's figures): what one-step foresight buys per migrated slice."""
import statistics

from .common import Part, by, md_table, register


def frontier_table(rows, eval_rows):
    """Lazy-oracle imbalance and migration per (P, tau), beside the GRU target that reactive's rows of
    controller_eval imply (migration <= reactive/8 within +0.5 points; nan without them)."""
    reactive = {p: (statistics.fmean(float(r["mean_imbalance"]) for r in rs),
                    statistics.fmean(float(r["migration"]) for r in rs))
                for p, rs in by([r for r in eval_rows if r["policy"] == "reactive"], "ranks").items()}
    out = ["# What one-step foresight buys per migrated slice (lazy oracle, held-out seeds)", "",
           "Mean over seeds. Target: the GRU's bound, reactive's imbalance + 0.5 points at 1/8 of its "
           "migration (reactive from controller_eval.csv in the same results folder).", "",
           ]
    body = []
    for p, rs in sorted(by(rows, "ranks").items(), key=lambda kv: int(kv[0])):
        ri, rm = reactive.get(p, (float("nan"), float("nan")))
        for tau, ts in sorted(by(rs, "lazy_oracle.tau").items(), key=lambda kv: float(kv[0])):
            body.append((p, f"{float(tau):g}", f"{100 * statistics.fmean(float(r['mean_imbalance']) for r in ts):.2f}",
                         f"{statistics.fmean(float(r['migration']) for r in ts):.1f}", f"{100 * ri + 0.5:.2f}",
                         f"{rm / 8:.1f}"))
    out.append(md_table(["P", "tau", "imbalance %", "migration", "target imbalance %", "target migration"], body,
                        align="r" * 6))
    return "\n".join(out) + "\n"



CSV = "foresight_frontier/foresight_frontier.csv"
EVAL = "controller_eval/controller_eval.csv"


def build(ctx):
    rows = ctx.rows(CSV)
    if not rows:
        return None
    ranks = ",".join(sorted({r["ranks"] for r in rows}, key=int))
    return Part([("This run (surrogate)", ctx.cpu_run(CSV, ranks, 1, f"{rows[0].get('events', '?')} events per rollout",
                                                                  what="the surrogate, no engine"),
                  ctx.source(CSV) + "\n\n" + ctx.table("foresight_frontier", frontier_table(rows, ctx.rows(EVAL) or [])))],
                "Not in the paper (a bound on what the GRU's migration target asks).",
                "No paper comparison: the lazy oracle bounds what any policy can reach with so few migrations.")


register("foresight_frontier", 15, "What one-step foresight buys per migrated slice (lazy oracle)", build, [CSV, EVAL])
