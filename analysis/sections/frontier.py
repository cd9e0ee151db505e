"""Report section (beyond the paper's figures): balancer families' imbalance-migration fronts and the GRU."""
import math
import statistics
from collections import OrderedDict

from .common import Part, md_table, plt as _pyplot, register


# Families that a simulation can run (rank times, slice work); lazy_oracle needs the next interval's true work.
DEPLOYABLE = ["reactive", "gromacs_dlb", "hoomd_balance", "all_tensor", "lammps_shift"]



FRONTIER_FAMILIES = DEPLOYABLE + ["lazy_oracle", "foresight"]



def setting_points(rows):
    """P -> [(family, setting, mean imbalance (fraction), mean migration)], one per (policy, POLICY.KEY cells), means
    over seeds. The setting names the row's own policy's parameter cells ("tau=0.05 alpha=0.5"; "defaults" if none)."""
    params = [c for c in rows[0] if "." in c]
    cells = OrderedDict()
    for r in rows:
        label = " ".join(f"{c.split('.', 1)[1]}={r[c]}" for c in params if r[c] and c.startswith(r["policy"] + "."))
        cells.setdefault((int(r["ranks"]), r["policy"], label or "defaults"), []).append(r)
    out = OrderedDict()
    for (P, policy, label), rs in sorted(cells.items(), key=lambda kv: kv[0][0]):
        out.setdefault(P, []).append((policy, label, statistics.fmean(float(r["mean_imbalance"]) for r in rs),
                                      statistics.fmean(float(r["migration"]) for r in rs)))
    return out



def dominates(q, p):
    """q is no worse than p in imbalance and migration and better in one (points as from setting_points)."""
    return q[2] <= p[2] and q[3] <= p[3] and (q[2] < p[2] or q[3] < p[3])



def pareto_front(points):
    """The points no other point dominates, by imbalance ascending (so migration descending); of equal points the
    first is kept."""
    front, seen = [], set()
    for p in points:
        if (p[2], p[3]) not in seen and not any(dominates(q, p) for q in points):
            front.append(p)
            seen.add((p[2], p[3]))
    return sorted(front, key=lambda p: p[2])



def migration_at(front, imbalance):
    """The migration FRONT (from pareto_front) needs for IMBALANCE: linear in imbalance between neighbouring front
    points, the front's least migration past its largest imbalance, None below its smallest imbalance."""
    if not front or imbalance < front[0][2]:
        return None
    if imbalance >= front[-1][2]:
        return front[-1][3]
    for a, b in zip(front, front[1:]):
        if a[2] <= imbalance <= b[2]:
            return a[3] + (b[3] - a[3]) * (imbalance - a[2]) / (b[2] - a[2])



def imbalance_at(front, migration):
    """The imbalance FRONT (from pareto_front) reaches with MIGRATION slices: linear in migration between neighbouring
    front points, the front's least imbalance past its largest migration, None below its least migration."""
    if not front or migration < front[-1][3]:
        return None
    if migration >= front[0][3]:
        return front[0][2]
    for a, b in zip(front, front[1:]):
        if b[3] <= migration <= a[3]:
            return a[2] if a[3] == b[3] else a[2] + (b[2] - a[2]) * (a[3] - migration) / (a[3] - b[3])



def shipped_gru(points):
    """The shipped GRU's point (family gru, no parameter cells: the default weights), else the first gru point."""
    grus = [p for p in points if p[0] == "gru"]
    return next((p for p in grus if p[1] == "defaults"), grus[0] if grus else None)



def floor_gap(points):
    """For one P's points, at the GRU's migration: (gru point, the best deployable front's imbalance (least over
    the deployable families of imbalance_at; None if none moves that little), foresight's imbalance there (None
    without foresight rows), the share of the distance from the deployable front to the floor the GRU closes:
    (front - gru) / (front - floor); None when either is missing or the front is on the floor)."""
    gru = shipped_gru(points)
    if gru is None:
        return None, None, None, None
    fronts = [imbalance_at(pareto_front([p for p in points if p[0] == fam]), gru[3]) for fam in DEPLOYABLE]
    best = min((f for f in fronts if f is not None), default=None)
    floor = imbalance_at(pareto_front([p for p in points if p[0] == "foresight"]), gru[3])
    share = None if best is None or floor is None or best <= floor else (best - gru[2]) / (best - floor)
    return gru, best, floor, share



def gru_verdict(points):
    """For one P's points: (gru point or None, deployable points dominating it, the least migration a deployable
    family's front needs at its imbalance (migration_at; None if none reaches it), GRU migration / that or None).
    Targets: (a) none dominates; (b) ratio <= 1/2. Fronts are per family: a line between two settings of one family
    stands for the knob values between them; nothing lies between two families."""
    gru = shipped_gru(points)
    if gru is None:
        return None, [], None, None
    deployable = [p for p in points if p[0] in DEPLOYABLE]
    beaten_by = sorted((q for q in deployable if dominates(q, gru)), key=lambda q: (q[3], q[2]))
    needs = [migration_at(pareto_front([p for p in deployable if p[0] == fam]), gru[2]) for fam in DEPLOYABLE]
    need = min((n for n in needs if n is not None), default=None)
    ratio = None if need is None else (gru[3] / need if need > 0 else (0.0 if gru[3] == 0 else math.inf))
    return gru, beaten_by, need, ratio



def balancer_frontier_table(rows):
    by_p = setting_points(rows)
    seeds = len({r["seed"] for r in rows})
    events = sorted({r["events"] for r in rows})
    out = ["# The frontier: what each balancer family trades, and where the shipped GRU sits (held-out seeds)", "",
           f"Each point is one setting's mean over {seeds} seeds ({', '.join(events)}-event rollouts): imbalance = "
           "time-averaged I_global in percent, migration = slices moved over the rollout. Deployable families: "
           + ", ".join(DEPLOYABLE) + "; lazy_oracle knows the next interval's true work (a foresight bound, not "
           "deployable). The targets are the shipped GRU's (default weights, migration penalty 2); the gru family's "
           "front below adds the same recipe trained with other migration penalties where the manifest lists them "
           "(gru.weights).", "",
           "Targets: (a) no deployable setting dominates the GRU (no worse in both, better in one); (b) at the GRU's "
           "imbalance the GRU migrates at most half of what the best deployable front needs: the least, over the "
           "deployable families, of the family's Pareto front interpolated linearly in imbalance between its points.", "",
           ]
    body = []
    for P, points in by_p.items():
        gru, beaten_by, need, ratio = gru_verdict(points)
        if gru is None:
            body.append((P, "", "", "no gru rows", "", "", "", ""))
            continue
        dom = "none" if not beaten_by else (
            f"{len(beaten_by)} setting{'s' if len(beaten_by) > 1 else ''}, least migration: {beaten_by[0][0]} "
            f"{beaten_by[0][1]} ({100 * beaten_by[0][2]:.2f} %, {beaten_by[0][3]:.1f})")
        need_s = "unreached" if need is None else f"{need:.1f}"
        ratio_s = "" if ratio is None else ("inf" if math.isinf(ratio) else f"{ratio:.2f}")
        b = need is None or ratio <= 0.5
        body.append((P, f"{100 * gru[2]:.2f}", f"{gru[3]:.1f}", dom, need_s, ratio_s,
                     "holds" if not beaten_by else "fails", "holds" if b else "fails"))
    out += [md_table(["P", "GRU imbalance %", "GRU migration", "dominated by",
                      "deployable front's migration at the GRU's imbalance", "GRU / front", "(a)", "(b)"], body,
                     align="rrrlrrll"),
            "", "\"unreached\": no deployable setting reaches the GRU's imbalance at any migration ((b) holds).", "",
            "The floor: foresight (docs/controllers.md) knows the true work of every interval and minimises summed "
            "I_global + lambda x slices moved (exact at P = 2; at P > 2 a feasible path found by block coordinate "
            "descent, so an upper bound on the floor). At the GRU's migration, each front's imbalance (linear in "
            "migration between its points) and the share of the distance from the best deployable front down to "
            "foresight that the GRU closes, (front - GRU) / (front - floor); target at P = 2: at least 0.5.", "",
            ]
    body = []
    for P, points in by_p.items():
        gru, best, floor, share = floor_gap(points)
        if gru is None:
            continue
        body.append((P, f"{gru[3]:.1f}", "unreached" if best is None else f"{100 * best:.2f}",
                     "" if floor is None else f"{100 * floor:.2f}", f"{100 * gru[2]:.2f}",
                     "" if share is None else f"{share:.2f}"))
    out += [md_table(["P", "GRU migration", "best deployable front's imbalance % there", "foresight's imbalance % there",
                      "GRU imbalance %", "share of the gap closed"], body, align="rrrrrr"),
            "", "\"unreached\": no deployable setting migrates as little as the GRU.", "",
            "Migration each family's front needs at the GRU's imbalance (same interpolation; \"unreached (x)\": the "
            "family's lowest imbalance x % is above the GRU's):", "",
            ]
    body = []
    for fam in FRONTIER_FAMILIES:
        cells = []
        for P, points in by_p.items():
            gru, front = gru_verdict(points)[0], pareto_front([q for q in points if q[0] == fam])
            need = migration_at(front, gru[2]) if gru and front else None
            cells.append("" if not gru or not front else
                         f"unreached ({100 * front[0][2]:.2f})" if need is None else f"{need:.1f}")
        body.append([fam] + cells)
    out.append(md_table(["family"] + [f"P={P}" for P in by_p], body, align="l" + "r" * len(by_p)))
    for P, points in by_p.items():
        out += ["", f"## P = {P}: Pareto front of each family", "",
                md_table(["family", "setting", "imbalance %", "migration"],
                         [(fam, p[1], f"{100 * p[2]:.2f}", f"{p[3]:.1f}") for fam in FRONTIER_FAMILIES + ["gru"]
                          for p in pareto_front([q for q in points if q[0] == fam])], align="llrr")]
    return "\n".join(out) + "\n"



def balancer_frontier_figure(rows):
    plt = _pyplot()
    by_p = setting_points(rows)
    cols = min(2, len(by_p))
    rows_n = (len(by_p) + cols - 1) // cols
    fig, axes = plt.subplots(rows_n, cols, figsize=(5.5 * cols, 4 * rows_n + 0.6), squeeze=False)
    colors = plt.get_cmap("tab10")
    for ax in axes.flat[len(by_p):]:
        ax.set_visible(False)
    for ax, (P, points) in zip(axes.flat, by_p.items()):
        for k, fam in enumerate(FRONTIER_FAMILIES):
            front = pareto_front([q for q in points if q[0] == fam])
            if front:
                ax.plot([100 * p[2] for p in front], [p[3] for p in front], "o-" if fam in DEPLOYABLE else "s--",
                        ms=4, color=colors(k), label=fam)
        shipped = shipped_gru(points)
        others = sorted((p for p in points if p[0] == "gru" and p is not shipped), key=lambda p: p[2])
        if others:  # the same recipe trained with other migration penalties
            ax.plot([100 * p[2] for p in others], [p[3] for p in others], "x:", ms=8, color="black",
                    label="gru (other penalties)")
        if shipped:
            ax.plot([100 * shipped[2]], [shipped[3]], "*", ms=14, color="black", label="gru (shipped)")
        ax.set_yscale("symlog", linthresh=1)
        ax.set_title(f"P = {P}")
        ax.set_xlabel("time-averaged imbalance (%)")
        ax.grid(alpha=0.3, which="both")
    for row in axes:
        row[0].set_ylabel("slices migrated per rollout (log above 1)")
    handles, labels = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="upper center", ncol=(len(labels) + 1) // 2, frameon=False, fontsize=8)
    fig.tight_layout(rect=(0, 0, 1, 1 - 0.6 / (4 * rows_n + 0.6)))
    return fig



CSV = "frontier/frontier.csv"


def build(ctx):
    rows = ctx.rows(CSV)
    if not rows:
        return None
    ranks = ",".join(sorted({r["ranks"] for r in rows}, key=int))
    body = (ctx.source(CSV) + "\n\n" + ctx.table("frontier", balancer_frontier_table(rows)) + "\n"
            + ctx.figure("frontier", balancer_frontier_figure(rows)))
    return Part([("This run (surrogate)", ctx.cpu_run(CSV, ranks, 1, f"{rows[0].get('events', '?')} events per rollout",
                                                                  what="the surrogate, no engine"), body)],
                "Not in the paper: it compares the RNN with static, reactive and forecast policies only.",
                "No paper comparison; the tables say where the shipped GRU stands against production balancers.")


register("frontier", 16, "Production balancers' trade-off fronts and the shipped GRU", build, [CSV])
