#!/usr/bin/env python3
"""Renders a semlb state file (final.h5 or a snapshot) as a PNG: cells as coloured blobs by type, like the
paper's epidermal figure. Usage: render.py STATE.h5 OUT.png [--view ELEV AZIM]"""
import argparse
import os
import sys

COLOURS = {0: "#2a7ab9", 1: "#e3a72f", 2: "#c0392b"}
NAMES = {0: "basal", 1: "spinous", 2: "granular"}


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("state")
    ap.add_argument("out")
    ap.add_argument("--view", nargs=2, type=float, default=(22, -60), metavar=("ELEV", "AZIM"))
    a = ap.parse_args()
    import h5py
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    try:
        with h5py.File(a.state, "r") as f:
            pos, cell, ctype = f["/elements/position"][:], f["/elements/cell"][:], f["/elements/type"][:]
            step = f.attrs.get("step", 0)
    except (OSError, KeyError) as e:
        print(f"render: {a.state}: {e}", file=sys.stderr)
        return 2
    ids, inverse = np.unique(cell, return_inverse=True)
    counts = np.bincount(inverse)
    centre = np.stack([np.bincount(inverse, weights=pos[:, d]) / counts for d in range(3)], axis=1)
    radius = np.sqrt(np.bincount(inverse, weights=((pos - centre[inverse]) ** 2).sum(1)) / counts)
    types = np.zeros(len(ids), dtype=int)
    types[inverse] = ctype
    fig = plt.figure(figsize=(8, 5))
    ax = fig.add_subplot(projection="3d")
    for t, colour in COLOURS.items():
        m = types == t
        if m.any():
            ax.scatter(*centre[m].T, s=(6 * radius[m]) ** 2, c=colour, alpha=0.75, edgecolors="k", linewidths=0.2,
                       label=f"{NAMES[t]} ({m.sum()})")
    ax.view_init(*a.view)
    span = (centre.max(0) - centre.min(0)).clip(min=1.0)
    ax.set_box_aspect(span)
    ax.set_xlabel("x (um)")
    ax.set_ylabel("y (um)")
    ax.set_zlabel("z (um)")
    ax.set_title(f"{len(ids)} cells, {len(pos)} elements, step {step}")
    ax.legend(loc="upper left", fontsize=8)
    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
    tmp = a.out + ".tmp"
    fig.savefig(tmp, dpi=130, format="png")
    os.replace(tmp, a.out)
    print(f"render: wrote {a.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
