"""Report section for the paper's rank-balance figure: each rank's computation time per interval, per policy."""
from collections import OrderedDict

from .common import Part, md_table, order_policies, plt, register

CSV = "rank_balance/rank_balance.csv"
DEV_CSV = "end_to_end/rank_balance.csv"  # experiments/end_to_end_ranks.yaml: Day 0-5 of the developing epidermis
GPU = [("gpu/rank_balance/rank_balance_435661_4ranks_4gpus.csv", "machine C: 4 H200s", "4 H200s, one per rank"),
       ("gpu/rank_balance/rank_balance_435661_8ranks_8gpus.csv", "machine D: 8 H200s", "8 H200s, one per rank")]
PAPER_LINE = ("8 L40S GPUs, 435K cells, 100,000 iterations (qualitative, no numbers): static keeps persistent "
              "differences between ranks; reactive narrows the spread after imbalance shows; the RNN tightens the "
              "curves further and slightly lowers per-rank times.")


def spread(rows, policy):
    """Mean over intervals of (T_max - T_min)/T_mean of the ranks' computation times (I_global), and the count of
    intervals; (nan, 0) without rows."""
    steps = OrderedDict()
    for r in rows:
        if r["policy"] == policy:
            steps.setdefault(int(r["step"]), []).append(float(r["compute_s"]))
    vals = [(max(t) - min(t)) / (sum(t) / len(t)) for t in steps.values() if sum(t) > 0]
    return (sum(vals) / len(vals) if vals else float("nan")), len(vals)


def table(rows, title):
    pols = order_policies(r["policy"] for r in rows)
    ranks = len({r["rank"] for r in rows})
    out = [f"# {title}", "", f"{ranks} ranks. I_global of the ranks' computation times per interval, mean over "
           "the intervals, and the mean per-rank computation time per interval.", "",
           ]
    body = []
    for p in pols:
        s, n = spread(rows, p)
        ts = [float(r["compute_s"]) for r in rows if r["policy"] == p]
        moved = sum(int(r["moved_slices"]) for r in rows if r["policy"] == p and r["rank"] == "0")
        body.append((p, n, f"{100 * s:.1f}", f"{sum(ts) / len(ts):.3f}", moved))
    out.append(md_table(["policy", "intervals", "mean I_global %", "mean rank time per interval (s)", "slices moved"],
                        body, align="lrrrr"))
    return "\n".join(out) + "\n"


def figure(rows, where):
    """One panel per policy, one line per rank: computation time per interval against iterations (10^3)."""
    p = plt()
    policies = order_policies(r["policy"] for r in rows)
    scale = 1000 if max(int(r["step"]) for r in rows) >= 5000 else 1
    fig, axes = p.subplots(1, len(policies), figsize=(4 * len(policies), 3.7), sharey=True, squeeze=False)
    for ax, pol in zip(axes[0], policies):
        for rank in sorted({r["rank"] for r in rows}, key=int):
            pts = sorted((int(r["step"]), float(r["compute_s"])) for r in rows if r["policy"] == pol and r["rank"] == rank)
            ax.plot([q[0] / scale for q in pts], [q[1] for q in pts], "o-", ms=3, lw=1, label=f"rank {rank}")
        s, n = spread(rows, pol)
        ax.set_title(f"{pol}: mean I_global {100 * s:.0f}%", fontsize=10)
        ax.set_xlabel("iteration (10$^3$)" if scale == 1000 else "iteration")
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel("computation time per interval (s)")
    axes[0][0].legend(fontsize=7, ncol=2)
    fig.suptitle(where, fontsize=9)
    fig.tight_layout()
    return fig


def verdict(rows):
    """(supported?, 'static x%, reactive y%, gru z%')."""
    s = {p: spread(rows, p)[0] for p in ("static", "reactive", "gru")}
    text = ", ".join(f"{p} {100 * v:.1f}%" for p, v in s.items())
    ok = s["gru"] <= s["reactive"] <= s["static"]
    return ok, text


def one(ctx, rows, name, title, heading, setup_line, source, where):
    body = source + "\n\n" + ctx.table(name, table(rows, title)) + "\n" + ctx.figure(name, figure(rows, where))
    return (heading, setup_line, body)


def build(ctx):
    runs, verdicts = [], []
    for rel, heading in ((CSV, "This run: scenes/epidermis.yaml"), (DEV_CSV, "This run: Day 0-5 (end_to_end_ranks)")):
        rows = ctx.rows(rel)
        if not rows:
            continue
        ranks = len({r["rank"] for r in rows})
        n = spread(rows, rows[0]["policy"])[1]
        name = "rank_balance" if rel == CSV else "end_to_end_rank_balance"
        where = (f"{ranks} CPU ranks time-sharing {__import__('os').cpu_count()} cores, {n} intervals, one launch per "
                 "policy: the rank times are mostly scheduler noise")
        runs.append(one(ctx, rows, name, f"Per-rank time, {heading.split(': ')[1]}", heading,
                        ctx.cpu_run(rel, str(ranks), 1, str(n), "ranks oversubscribed: timing mostly scheduler noise"),
                        ctx.source(rel), where))
        verdicts.append(("CPU " + heading.split(": ")[1], verdict(rows)))
    for rel, machine, gpus in GPU:
        rows = ctx.committed_rows(rel)
        if not rows:
            continue
        ranks = len({r["rank"] for r in rows})
        n = spread(rows, "static")[1]
        name = "rank_balance_gpu_" + rel.split("_")[-2]
        runs.append(one(ctx, rows, name, f"Per-rank time, {ranks} ranks on {gpus}",
                        f"Committed paper profile (GPU, {machine})",
                        f"profile **paper** (435,661 cells, epidermis scene) · machine: {machine} · ranks: {ranks} "
                        f"({gpus}) · cores: - · launches: 1 per policy · intervals: {n}",
                        "From " + ctx.committed_source(rel) + ".", f"{ranks} ranks on {gpus}, {machine.split(':')[0]}, {n} intervals, one launch per policy"))
        verdicts.append((f"{ranks}xH200", verdict(rows)))
    if not runs:
        return None
    gpu = [v for v in verdicts if "H200" in v[0]]
    lines = "; ".join(f"{k}: {t}" for k, (ok, t) in verdicts)
    held = [k for k, (ok, _) in gpu if ok]
    if gpu:
        reading = (f"Mean I_global of the rank times per interval: {lines}. The paper's ordering (static > reactive > "
                   f"RNN) holds on {', '.join(held) if held else 'no GPU run'}"
                   + ("" if len(held) == len(gpu) else f" and not on {', '.join(k for k, (ok, _) in gpu if not ok)}")
                   + ". The GPU runs are 20 intervals (2,000 steps), not the paper's 100,000 iterations; the CPU runs "
                   "time-share the cores, so their spread says little about the policies.")
    else:
        reading = f"{lines}; CPU ranks time-share the cores, so the spread is mostly scheduler noise."
    summary = "; ".join(f"{k}: {t}" for k, (ok, t) in gpu) + " (mean I_global of rank times)" if gpu else ""
    cpu = "; ".join(f"{k}: {t}" for k, (ok, t) in verdicts if "H200" not in k)
    return Part(runs, PAPER_LINE, reading, all(ok for _, (ok, _) in gpu) if gpu else None, summary,
                this_run=cpu + " (time-shared cores)" if cpu else "")


register("rank_balance", 3, "Per-rank computation time per interval: static, reactive and GRU", build, [CSV, DEV_CSV],
         paper="fig:rank_balance", claim="rank-time spread static > reactive > RNN (no numbers)")
