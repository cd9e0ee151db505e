"""Report section: the controller evaluation on the engine's own workloads (replays through the time model)."""
import os
import sys

import numpy as np

from .common import Part, md_table, plt as _pyplot, register, setup as setup_line
from .frontier import DEPLOYABLE, pareto_front

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import engine_eval  # noqa: E402  (analysis/engine_eval.py: the tables and the targets, also a command of its own)
import provenance  # noqa: E402

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
    runs, summary, key = [], None, None
    rows = ctx.rows(CSV)
    if rows:
        seeds = sorted({r["seed"] for r in rows})
        setup, body, summary = run_part(ctx, rows, "controller_eval_engine",
                                        ctx.cpu_run(CSV, ",".join(sorted({r["ranks"] for r in rows}, key=int)), 1,
                                                    "every recorded event", f"{len(seeds)} replay seed(s)",
                                                    what="replays of workloads recorded on one H200, no engine"),
                                        ctx.source(CSV))
        runs.append(("This run (replays of the committed test workloads)", setup, body))
        key = choice_table(engine_eval.read_points_rows(rows))
    committed = ctx.committed_rows(COMMITTED)
    if committed:
        setup, body, s = run_part(ctx, committed, "controller_eval_engine_paper",
                                  setup_line("paper", "workloads recorded on 1 NVIDIA H200 (results/gpu/workloads/README.md), "
                                             "replayed on a CPU, no engine", "2,4,8,16", "-", 1, "every recorded event",
                                             "3 replay seeds"),
                                  "From " + ctx.committed_source(COMMITTED) + ".")
        runs.append(("Committed paper profile", setup, body))
        summary = summary or s
        key = key or choice_table(engine_eval.read_points_rows(committed))
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
    return Part(runs, PAPER_LINE, reading, held == total, f"{held} of {total} targets hold",
                basis="run" if rows else "gpu", key_table=key)


register("controller_eval_engine", 5.5, "Controller evaluation on the engine's workloads: imbalance, migration, loop time",
         build, [CSV], paper="fig:rnn_prediction", claim="not evaluated in the paper (surrogate scenarios only)")


NOT_DEPLOYABLE = ("foresight", "oracle", "lazy_oracle")  # they know the future work: floors, not choices
ON_WS = ("persistence", "holt")  # repartition on forecast W_s, from which the time model derives rank times


def choice_rows(points_by_key):
    """Per P: (P, best (policy, setting), its loop time against static's per workload (list of ratios), its mean
    imbalance and migration over the workloads, the shipped GRU's ratios, the reference reactive's ratios, workloads).
    Best: the deployable (policy, setting) present on every workload at that P with the least mean loop-time ratio."""
    out = []
    for P in sorted({p for (_, p) in points_by_key}):
        ws = sorted(w for (w, p) in points_by_key if p == P)
        static = {w: next((q for q in points_by_key[(w, P)] if q["policy"] == "static"), None) for w in ws}
        if not all(static.values()):
            continue
        per = {}
        for w in ws:
            for q in points_by_key[(w, P)]:
                if q["policy"] not in NOT_DEPLOYABLE:
                    per.setdefault((q["policy"], q["setting"]), {})[w] = q
        full = {k: v for k, v in per.items() if len(v) == len(ws)}
        ratio = {k: [v[w]["loop_s"] / static[w]["loop_s"] for w in ws] for k, v in full.items()}
        best = min(ratio, key=lambda k: (np.mean(ratio[k]), k))
        timed = [k for k in ratio if k[0] not in ON_WS]
        best_t = min(timed, key=lambda k: (np.mean(ratio[k]), k)) if timed else None
        mean = lambda k, c: float(np.mean([full[k][w][c] for w in ws]))  # noqa: E731
        ref = next((k for k in ratio if engine_eval.is_reference_reactive({"policy": k[0], "setting": k[1]})), None)
        out.append((P, best, ratio[best], mean(best, "imbalance"), mean(best, "migration"),
                    ratio.get(("gru", "")), ratio.get(ref) if ref else None, ws, best_t,
                    ratio[best_t] if best_t else None))
    return out


def named(k):
    """'policy `setting`' of a (policy, setting) key."""
    return "-" if k is None else k[0] + (f" `{k[1]}`" if k[1] else "")


def pct(ratios):
    """'-12.3% (-20.1 .. -4.0)': the mean saving against static and its range over the workloads ('-' for None)."""
    if not ratios:
        return "-"
    r = 100 * (np.asarray(ratios) - 1)
    return f"{r.mean():+.1f}%" + (f" ({r.min():+.1f} .. {r.max():+.1f})" if len(r) > 1 else "")


def choice_table(points_by_key):
    """The which-controller table: per P, the best deployable policy and setting by loop time, and what it, the
    shipped GRU and reactive change against static."""
    rows = [(P, named(bt), pct(rt), named(b), pct(r), f"{100 * imb:.2f}", f"{mig:.0f}", pct(g), pct(x), len(ws))
            for P, b, r, imb, mig, g, x, ws, bt, rt in choice_rows(points_by_key)]
    return md_table(["P", "run this", "loop vs static (range over workloads)", "best of all (W_s forecasts too)",
                     "its loop vs static", "its imbalance %", "its slices moved", "shipped gru vs static",
                     "reactive vs static", "workloads"], rows)


MEASURED = ("gpu/measured/epidermis_half/end_to_end_summary.csv",  # five policies, P = 2, 4, 8, one scene each:
            "gpu/measured/epidermis_development/end_to_end_summary.csv",  # each has its own commit (provenance)
            "gpu/measured/learned_repartition/end_to_end_summary.csv")  # the learned controller's own call
SCENES = {"epidermis_half": "the paper's regime (epidermis, left half proliferating, 435,661 cells)",
          "epidermis_development": "a proliferative front (development scene, Day 2-3, paper size)"}


def scene_order(scene):
    """A scene's place in SCENES (the others after them)."""
    return list(SCENES).index(scene) if scene in SCENES else 99


def measured_points(rows):
    """(scene, P, rows at that P, static's row, the least mean loop time's row) of a measured summary, scenes in SCENES'
    order and P ascending; a (scene, P) without static is left out."""
    for scene in sorted({r["scene"] for r in rows}, key=scene_order):
        for P in sorted({int(r["ranks"]) for r in rows if r["scene"] == scene}):
            at = [r for r in rows if r["scene"] == scene and int(r["ranks"]) == P]
            static = next((r for r in at if r["policy"] == "static"), None)
            if static:
                yield scene, P, at, static, min(at, key=lambda r: float(r["loop_s"]))


def measured_choice(ctx):
    """Per committed measured CSV, scene and P, from the measured end-to-end runs on one H200 (docs/measured_time.md):
    the policy with the least mean loop time and its saving against static with the 95% interval over launches (runs
    of different calls are not mixed: each CSV is one call's interleaved launches). '' when none is committed."""
    lines = []
    for source in MEASURED:
        rows = ctx.committed_rows(source)
        if not rows:
            continue
        policies = ", ".join(sorted({r["policy"] for r in rows}))
        lines += [f"**Measured on one H200** ({ctx.committed_source(source)}; {policies}; P ranks taking turns, device "
                  "timers, launches interleaved in one call, docs/measured_time.md). Lowest mean loop time at each P, "
                  "its loop time against static (± 95% interval over launches), and the shipped GRU's:", ""]
        by_scene = {}
        for scene, P, at, static, best in measured_points(rows):
            def saving(r, base=float(static["loop_s"])):
                return (f"{-100 * float(r['static_minus_loop_s']) / base:+.1f}% "
                        f"(± {100 * float(r['static_minus_loop_s_ci95']) / base:.1f})")
            gru = next((r for r in at if r["policy"] == "gru"), None)
            by_scene.setdefault(scene, []).append(f"P = {P}: `{best['policy']}` {saving(best)}" +
                                                  (f", gru {saving(gru)}" if gru and gru is not best else ""))
        for scene, parts in by_scene.items():
            lines.append(f"- {SCENES.get(scene, scene)}: " + "; ".join(parts) + ".")
        lines.append("")
    if lines:
        lines += ["Negative: faster than static. Where the interval includes zero, no policy beats static there.", ""]
    return "\n".join(lines)


def measured_bottom_line(ctx):
    """The answer first: per scene and P, the policy with the least mean loop time in the measured summaries and its
    saving against static (± 95% over launches), from the current (not stale) summaries; a scene that has none shows
    its newest stale measurement per P instead, marked **stale** with the commit it was made with, so a kernel change
    leaves the reader the last answer and its age rather than none. At a P where the interval reaches zero the line
    says to run static. Then how to read what follows. '' when no measured summary is committed."""
    current, last = {}, {}  # scene -> {P: (saving %, ci %, policy, provenance, commit time, policies measured)}
    for source in MEASURED:
        rows = ctx.committed_rows(source)
        if not rows:
            continue
        prov = ctx.committed_provenance(source)
        fresh = prov["status"] == "fresh"
        when = provenance.commit_time(prov["commit"])
        for scene, P, rows_at, static, top in measured_points(rows):
            base = float(static["loop_s"])
            policies = {r["policy"] for r in rows_at}
            entry = (100 * float(top["static_minus_loop_s"]) / base,
                     100 * float(top["static_minus_loop_s_ci95"]) / base, top["policy"], prov, when, policies)
            at = (current if fresh else last).setdefault(scene, {})
            old = at.get(P)
            if old is not None and fresh:  # current summaries of one scene pool their policies
                entry = entry[:5] + (policies | old[5],)
            if old is None or (entry[0] > old[0] if fresh else (when, entry[0]) > (old[4], old[0])):
                at[P] = entry
            elif fresh:
                at[P] = old[:5] + (entry[5],)
    if not current and not last:
        return ""

    def answer(P, saving, ci, policy, unmeasured):
        missing = f" ({', '.join(sorted(unmeasured))} not in the call this line comes from)" if unmeasured else ""
        if saving - ci <= 0:
            return (f"P = {P}: `static` (the best, `{policy}`, saves {saving:.1f}% (± {ci:.1f} points), within the spread "
                    f"over launches){missing}")
        return f"P = {P}: `{policy}`, {saving:.1f}% (± {ci:.1f} points) less loop time than static{missing}"

    lines = ["**Bottom line** (measured on a GPU; a scene without a current measurement shows its last one, marked "
             "**stale**):", ""]
    for scene in sorted(set(current) | set(last), key=scene_order):
        at = current.get(scene) or last[scene]
        every = set().union(*(e[5] for e in at.values()))
        text = "; ".join(answer(P, *e[:3], every - e[5]) for P, e in sorted(at.items())) + "."
        if scene not in current:
            made = {}
            for P, e in sorted(at.items()):
                made.setdefault((e[3]["commit"][:7], e[3]["date"], e[3]["detail"]), []).append(str(P))
            text = ("**stale**, last measured with " + ", ".join(
                f"`{c}` ({d}; P = {', '.join(Ps)})" for (c, d, _), Ps in made.items()) +
                f"; the kernels or controllers changed since (last: `{next(iter(made))[2]}`): " + text +
                " Rerun `make gpu-results` for a current answer.")
        lines.append(f"- {SCENES.get(scene, scene)}: {text}")
    lines += ["",
              "How to read it: P ranks took turns on one H200, so each rank's device time is what a GPU of its own "
              "would take (docs/measured_time.md); the ghost exchange and migration are modelled at NVLink speed, "
              "not measured. Blocks marked **stale** were made with an engine or controllers that have changed "
              "since: history, shown with their commit; a current measurement of a scene replaces them. Replayed "
              "figures are the time model's estimates, not measurements. What each policy is: docs/controllers.md, "
              "\"The policies\".", ""]
    return "\n".join(lines)


def which_controller(ctx):
    """The report's "which controller" paragraph and table: the bottom line from the current measured runs, the
    measured end-to-end runs (when committed), then this run's replays (else the committed ones)."""
    measured = measured_bottom_line(ctx) + "\n" + measured_choice(ctx)
    text = which_controller_replayed(ctx)
    head = ("**Estimates, not measurements: replayed through the time model** (W_s as the truth; no run on a GPU "
            "stands behind these numbers):\n\n")
    return (measured + "\n" + (head + text if text else "")).strip()


def which_controller_replayed(ctx):
    """The replayed part of the "which controller" paragraph and table, from this run's replays (else the committed
    ones)."""
    rows, where = ctx.rows(CSV), f"`{CSV}` (this run)"
    if not rows:
        ctx.used_committed = []
        rows = ctx.committed_rows(COMMITTED)
        if not rows:
            return ""
        where = ctx.committed_source(COMMITTED)
    points = engine_eval.read_points_rows(rows)
    choice = choice_rows(points)
    if not choice:
        return ""
    lines = [f"From {where}: every policy and knob setting replayed on recorded engine workloads; loop time from the "
             "time model fitted to measured GPU runs (docs/controllers.md \"Time model\"), means over the replay "
             "seeds; foresight and the oracles are left out (they know the future work). At each P, the setting of a "
             "policy that balances on measured rank times with the least loop time relative to static, averaged over "
             "the workloads (range over the workloads in brackets):", ""]
    lines.append("; ".join(f"**P = {P}**: `{bt[0]}{' ' + bt[1] if bt[1] else ''}` ({pct(rt)} loop time vs static)"
                           for P, b, r, imb, mig, g, x, ws, bt, rt in choice if bt) + ".")
    lines += ["", "persistence and holt repartition on forecast W_s, from which the time model derives the rank times, "
              "so they score better here than they would on a machine (time is the judge, W_s a hint): they are "
              "counted only in \"best of all\".", "", choice_table(points)]
    return "\n".join(lines)
