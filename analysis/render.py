#!/usr/bin/env python3
"""Renders semlb state files (final.h5 or snapshots) as a PNG: cells as coloured blobs by type, like the paper's
epidermal figure; several states become panels in the given order, titled by their time (h). Usage:
render.py STATE.h5 [STATE.h5 ...] OUT.png [--view ELEV AZIM]"""
import argparse
import os
import sys

COLOURS = {0: "#2a7ab9", 1: "#e3a72f", 2: "#c0392b"}
NAMES = {0: "basal", 1: "spinous", 2: "granular"}


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("states", nargs="+")
    ap.add_argument("out")
    ap.add_argument("--view", nargs=2, type=float, default=(22, -60), metavar=("ELEV", "AZIM"))
    a = ap.parse_args()
    import h5py
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    cols = min(3, len(a.states))
    rows = (len(a.states) + cols - 1) // cols
    fig = plt.figure(figsize=(8 if cols == 1 else 5.5 * cols, 5 if rows == 1 else 4.2 * rows))
    for k, state in enumerate(a.states):
        try:
            with h5py.File(state, "r") as f:
                pos, cell, ctype = f["/elements/position"][:], f["/elements/cell"][:], f["/elements/type"][:]
                step, time = f.attrs.get("step", 0), f.attrs.get("time", None)
        except (OSError, KeyError) as e:
            print(f"render: {state}: {e}", file=sys.stderr)
            return 2
        ids, inverse = np.unique(cell, return_inverse=True)
        counts = np.bincount(inverse)
        centre = np.stack([np.bincount(inverse, weights=pos[:, d]) / counts for d in range(3)], axis=1)
        radius = np.sqrt(np.bincount(inverse, weights=((pos - centre[inverse]) ** 2).sum(1)) / counts)
        types = np.zeros(len(ids), dtype=int)
        types[inverse] = ctype
        ax = fig.add_subplot(rows, cols, k + 1, projection="3d")
        for t, colour in COLOURS.items():
            m = types == t
            if m.any():
                ax.scatter(*centre[m].T, s=(6 * radius[m] / cols) ** 2, c=colour, alpha=0.75, edgecolors="k",
                           linewidths=0.2, label=f"{NAMES[t]} ({m.sum()})")
        ax.view_init(*a.view)
        span = (centre.max(0) - centre.min(0)).clip(min=1.0)
        ax.set_box_aspect(span)
        ax.set_xlabel("x (um)")
        ax.set_ylabel("y (um)")
        ax.set_zlabel("z (um)")
        when = f"{float(time):.0f} h (day {float(time) / 24:.1f}), " if time is not None else ""
        ax.set_title(f"{when}{len(ids)} cells, {len(pos)} elements, step {step}", fontsize=9 if cols > 1 else 12)
        ax.legend(loc="upper left", fontsize=7 if cols > 1 else 8)
    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
    tmp = a.out + ".tmp"
    fig.savefig(tmp, dpi=130, format="png")
    os.replace(tmp, a.out)
    print(f"render: wrote {a.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
