"""Report section (beyond the paper's figures): the GRU's validation curve during training."""
from .common import Part, md_table, plt as _pyplot, register


def training_curve_table(rows):
    out = ["# GRU training curve (validation seeds, hard integer boundaries)", "",
           "Validation imbalance (time-averaged I_global, %) and migration (slices per rollout) of the GRU after "
           "each number of training steps, with the reactive rule on the same rollouts.", "",
           md_table(["step", "wall s", "GRU imbalance %", "GRU migration", "reactive imbalance %", "reactive migration"],
                    [(int(float(r["step"])), f"{float(r['wall_seconds']):.0f}", f"{100 * float(r['val_imbalance']):.3f}",
                      f"{float(r['val_migration']):.1f}", f"{100 * float(r['reactive_imbalance']):.3f}",
                      f"{float(r['reactive_migration']):.1f}") for r in rows], align="rrrrrr")]
    return "\n".join(out) + "\n"



def training_curve_figure(rows):
    plt = _pyplot()
    steps = [float(r["step"]) for r in rows]
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    for ax, key, ref, label, scale in ((axes[0], "val_imbalance", "reactive_imbalance", "imbalance (%)", 100),
                                       (axes[1], "val_migration", "reactive_migration", "slices migrated per rollout", 1)):
        ax.plot(steps, [scale * float(r[key]) for r in rows], "o-", label="GRU")
        ax.axhline(scale * float(rows[-1][ref]), color="tab:red", ls="--", label="reactive")
        ax.set_xlabel("training step")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
        top = ax.secondary_xaxis("top", functions=(
            lambda x: x * float(rows[-1]["wall_seconds"]) / max(1.0, steps[-1]),
            lambda t: t * max(1.0, steps[-1]) / float(rows[-1]["wall_seconds"])))
        top.set_xlabel("wall time (s)")
    axes[0].legend()
    fig.tight_layout()
    return fig



CSV = "training_curve/training_curve.csv"


def build(ctx):
    rows = ctx.rows(CSV)
    if not rows:
        return None
    body = (ctx.source(CSV) + "\n\n" + ctx.table("training_curve", training_curve_table(rows)) + "\n"
            + ctx.figure("training_curve", training_curve_figure(rows)))
    return Part([("This run (trainer, libtorch on the CPU)", ctx.cpu_run(CSV, "-", 1, f"{len(rows)} validations",
                                                                       what="libtorch trainer on the CPU"), body)],
                "The paper trains with pytorch 2.5.1 and gives no curve.",
                "No paper comparison; the shipped weights come from the paper profile (6000 steps, `make train`).")


register("training_curve", 17, "GRU training curve (validation seeds)", build, [CSV])
