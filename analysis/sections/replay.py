"""Report sections (beyond the paper's figures): policies replayed on engine traces, and the per-slice work model."""
from collections import OrderedDict

from .common import Part, md_table, register

REPLAY = "replay_score/replay_score.csv"
MODEL = "trace_model/trace_model.csv"
COMMITTED = {"cpu": "committed, results/cpu (the 2-core VM)", "gpu": "committed, results/gpu (H200s)",
             "surrogate": "committed, results/surrogate"}


def origin(trace):
    """Where a trace (path relative to the results folder) came from: a committed folder or this run."""
    return COMMITTED.get(trace.split("/", 1)[0], "fresh: this run's `make experiments`")


def replay_score_table(rows):
    """Per trace (rows) and policy (columns): mean I_global % / migrated slices under `semlb replay --score`; one
    table and one mean-over-traces row per origin (committed and fresh traces are never averaged together)."""
    policies = list(OrderedDict.fromkeys(r["policy"] for r in rows))
    cell = {(r["trace"], r["policy"]): r for r in rows}
    out = ["# Policies replayed on recorded engine traces", "",
           "Each trace's `slice_work` taken as the true work (`semlb replay --score`): mean I_global % / migrated "
           "slices per policy, from the trace's first partition. foresight: the offline floor (not deployable). "
           "Committed traces and this run's are listed and averaged apart."]
    for where, traces in OrderedDict((o, [t for t in OrderedDict.fromkeys(r["trace"] for r in rows) if origin(t) == o])
                                     for o in OrderedDict.fromkeys(origin(r["trace"]) for r in rows)).items():
        body = []
        for t in traces:
            first = next(cell[(t, p)] for p in policies if (t, p) in cell)
            body.append([t, first["ranks"], first["events"]] + [
                f"{100 * float(cell[(t, p)]['mean_imbalance']):.2f} / {cell[(t, p)]['migration']}"
                if (t, p) in cell else "—" for p in policies])
        mean = {p: [float(cell[(t, p)]["mean_imbalance"]) for t in traces if (t, p) in cell] for p in policies}
        mig = {p: [float(cell[(t, p)]["migration"]) for t in traces if (t, p) in cell] for p in policies}
        body.append([f"**mean over these {len(traces)} traces**", "", ""] + [
            f"**{100 * sum(mean[p]) / len(mean[p]):.2f} / {sum(mig[p]) / len(mig[p]):.1f}**" if mean[p] else "—"
            for p in policies])
        out += ["", f"## Traces {where}", "", md_table(["trace", "P", "events"] + policies, body,
                                                        align="lrr" + "l" * len(policies))]
    return "\n".join(out) + "\n"


def trace_model_table(rows):
    """analysis/trace_model.py's CSV: R^2 and relative error of the per-slice work model per trace, by origin."""
    out = ["# Per-slice work model against measured rank times", "",
           "Predicted rank time = sum of `slice_work` over the rank's slices on the recorded partition; R^2 around "
           "each event's mean rank time. `modelled` traces have R^2 = 1 by construction and are not pooled; "
           "committed traces and this run's are pooled apart (pooled_measured_committed, pooled_measured).", "",
           ]
    body = []
    for r in rows:
        where = ("committed" if r["trace"] == "pooled_measured_committed" else "fresh") \
            if r["trace"].startswith("pooled") else origin(r["trace"]).split(",")[0].split(":")[0]
        body.append((r["trace"], where, r["timing"], r["ranks"], r["events"], r["points"], f"{float(r['r2']):.3f}",
                     f"{100 * float(r['mean_rel_error']):.1f}", f"{100 * float(r['max_rel_error']):.1f}"))
    out.append(md_table(["trace", "origin", "timing", "P", "events", "points", "R^2", "mean rel. error %",
                         "max rel. error %"], body, align="lllrrrrrr"))
    return "\n".join(out) + "\n"


def build_replay(ctx):
    rows = ctx.rows(REPLAY)
    if not rows:
        return None
    n = len({r["trace"] for r in rows})
    return Part([("This run (replay of recorded traces)", ctx.cpu_run(REPLAY, "per trace", 1, "per trace", f"{n} traces", what="semlb replay --score"),
                  ctx.source(REPLAY) + "\n\n" + ctx.table("replay_score", replay_score_table(rows)))],
                "Not in the paper (it evaluates controllers in its surrogate only).",
                "No paper comparison: how the policies rank on the engine's own work profiles.")


def build_model(ctx):
    rows = ctx.rows(MODEL)
    if not rows:
        return None
    return Part([("This run", ctx.cpu_run(MODEL, "per trace", 1, "per trace", f"{len(rows)} rows"),
                  "From `trace_model/trace_model.csv` (`analysis/trace_model.py`).\n\n"
                  + ctx.table("trace_model", trace_model_table(rows)))],
                "Not in the paper.", "No paper comparison: on the CPU traces, rank times are mostly scheduler noise.")


register("replay_score", 18, "Policies replayed on recorded engine traces", build_replay, [REPLAY])
register("trace_model", 19, "Per-slice work model against measured rank times", build_model, [MODEL])
