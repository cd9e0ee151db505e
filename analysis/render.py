#!/usr/bin/env python3
"""Renders semlb state files (final.h5 or snapshots) as the paper's epidermal figure: each cell an ellipsoid.

Each cell is the ellipsoid of its elements' gyration tensor G = mean (y - c)(y - c)^T: semi-axes sqrt(5 lambda_i)
along G's eigenvectors (a solid ellipsoid of semi-axes a_i has variance a_i^2 / 5 along them), at least half the
element spacing. A view projects it orthographically: the outline of an ellipsoid is the ellipse of the projected
tensor P G P^T, so the picture is exact. Cells are drawn far to near (painter's order) and shaded by depth, coloured
by type (names from `semlb list cell-types --json`; exit 2 naming the binary when it cannot list them). Default view: the side (x-z), which shows the layers; --view
ELEV AZIM gives an oblique one. Several states become panels stacked top to bottom, titled by their time (h, day),
with axes in um; --paraview FILE also writes a ParaView Python state that opens the snapshots.xmf beside the states.
Usage: render.py STATE.h5 [STATE.h5 ...] OUT.png [--view ELEV AZIM] [--semlb BINARY] [--paraview STATE.py]"""
import argparse
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import semlb_names  # noqa: E402

COLOURS = ["#2a7ab9", "#e3a72f", "#c0392b", "#6a9f3b", "#8e44ad"]


def read_state(path):
    """(positions n x 3, cell id per element, type per element, step, time h or None); OSError/KeyError if not a
    state."""
    import h5py
    with h5py.File(path, "r") as f:
        pos, cell, ctype = f["/elements/position"][:], f["/elements/cell"][:], f["/elements/type"][:]
        step, time = int(f.attrs.get("step", 0)), f.attrs.get("time", None)
    return pos, cell, ctype, step, (None if time is None else float(time))


def ellipsoids(pos, cell, ctype):
    """Per cell: centre (k x 3), gyration tensor scaled to the ellipsoid's shape matrix A = 5 G + s^2 I / 4 (its
    semi-axes sqrt of A's eigenvalues; s = the median nearest-element spacing estimate), type (k)."""
    import numpy as np
    ids, inverse = np.unique(cell, return_inverse=True)
    counts = np.bincount(inverse).astype(float)
    centre = np.stack([np.bincount(inverse, weights=pos[:, d]) / counts for d in range(3)], axis=1)
    d = pos - centre[inverse]
    gyr = np.zeros((len(ids), 3, 3))
    for i in range(3):
        for j in range(i, 3):
            gyr[:, i, j] = gyr[:, j, i] = np.bincount(inverse, weights=d[:, i] * d[:, j]) / counts
    # element spacing: a cell of n elements and gyration radius r_g holds its elements about r_g * (4/n)^(1/3) apart
    rg = np.sqrt(np.trace(gyr, axis1=1, axis2=2))
    spacing = float(np.median(rg * (4.0 / counts) ** (1 / 3))) if len(ids) else 1.0
    shape = 5.0 * gyr + (spacing / 2) ** 2 * np.eye(3)[None]
    types = np.zeros(len(ids), dtype=int)
    types[inverse] = ctype
    return centre, shape, types


def view_basis(elev, azim):
    """Rows: screen right, screen up, towards the viewer (orthographic), for elevation/azimuth in degrees
    (elev 0, azim -90: looking along +y, x right and z up)."""
    import numpy as np
    e, a = math.radians(elev), math.radians(azim)
    towards = np.array([math.cos(e) * math.cos(a), math.cos(e) * math.sin(a), math.sin(e)])
    right = np.array([-math.sin(a), math.cos(a), 0.0])
    up = np.cross(towards, right)
    return np.stack([right, up, towards])


def draw(ax, centre, shape, types, basis):
    """Draws the projected ellipses far to near, each lightened by its depth; returns the count per type."""
    import numpy as np
    from matplotlib.colors import to_rgb
    from matplotlib.patches import Ellipse
    proj = centre @ basis.T
    depth = proj[:, 2]
    dmin, dmax = (depth.min(), depth.max()) if len(depth) else (0, 1)
    for k in np.argsort(depth):
        s2 = basis[:2] @ shape[k] @ basis[:2].T
        w, v = np.linalg.eigh(s2)
        angle = math.degrees(math.atan2(v[1, 1], v[0, 1]))
        near = (depth[k] - dmin) / (dmax - dmin) if dmax > dmin else 1.0
        base = np.array(to_rgb(COLOURS[types[k] % len(COLOURS)]))
        light = 0.4 + 0.6 * near  # far cells darker, so the front row does not hide where the layers lie
        colour = base * light
        ax.add_patch(Ellipse((proj[k, 0], proj[k, 1]), 2 * math.sqrt(max(w[1], 1e-9)), 2 * math.sqrt(max(w[0], 1e-9)),
                             angle=angle, facecolor=colour, edgecolor="k", linewidth=0.25))
    return {t: int((types == t).sum()) for t in sorted(set(types.tolist()))}


def paraview_state(path, xmf, names):
    """A ParaView Python state file (File > Load State, or `pvpython PATH`): the snapshots as element spheres
    coloured by type, seen from the side."""
    text = f'''# ParaView state (Python) written by analysis/render.py: the Day 0-5 snapshots of {os.path.basename(os.path.dirname(xmf))}.
# Open with File > Load State (choose Python state) or `pvpython {os.path.basename(path)}`; the time bar steps the days.
# Elements are spheres of radius 1.2 um coloured by the cell type index ({", ".join(f"{i} {n}" for i, n in enumerate(names)) or "0, 1, 2"}).
from paraview.simple import *
reader = XDMFReader(registrationName="tissue", FileNames=[{xmf!r}])
glyph = Glyph(registrationName="elements", Input=reader, GlyphType="Sphere")
glyph.ScaleArray = ["POINTS", "No scale array"]
glyph.ScaleFactor = 2.4
glyph.GlyphMode = "All Points"
view = GetActiveViewOrCreate("RenderView")
shown = Show(glyph, view)
ColorBy(shown, ("POINTS", "type"))
shown.LookupTable = GetColorTransferFunction("type")
shown.LookupTable.InterpretValuesAsCategories = 1
shown.LookupTable.Annotations = {[str(x) for i, n in enumerate(names) for x in (i, n)]!r}
view.CameraPosition = [0.0, -1.0, 0.0]
view.CameraViewUp = [0.0, 0.0, 1.0]
view.ResetCamera()
GetAnimationScene().UpdateAnimationUsingDataTimeSteps()
Render()
'''
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, path)
    print(f"render: wrote {path}")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("states", nargs="+")
    ap.add_argument("out")
    ap.add_argument("--view", nargs=2, type=float, default=(0.0, -90.0), metavar=("ELEV", "AZIM"),
                    help="degrees; default 0 -90: the side view (x right, z up)")
    ap.add_argument("--semlb", default=os.path.join(os.path.dirname(HERE), "build", "cli", "semlb"),
                    help="the binary whose cell types name the colours")
    ap.add_argument("--paraview", help="also write a ParaView Python state for the snapshots.xmf beside the states")
    ap.add_argument("--summary", help="also write a CSV per state: time_h, step, cells, elements, cells per type, "
                    "thickness_um (z extent of the elements)")
    a = ap.parse_args()
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    from matplotlib.patches import Patch
    summary = []
    data = []
    for state in a.states:
        try:
            data.append(read_state(state))
        except (OSError, KeyError) as e:
            print(f"render: {state}: {e}", file=sys.stderr)
            return 2
    try:
        names = semlb_names.names(a.semlb, "cell-types")
    except semlb_names.NamesError as e:
        print(f"render: {e}", file=sys.stderr)
        return 2
    basis = view_basis(*a.view)
    side = abs(a.view[0]) < 1e-9 and abs(((a.view[1] + 90) % 180)) < 1e-9
    allpos = np.concatenate([d[0] for d in data]) @ basis.T
    lo, hi = allpos.min(0) - 6, allpos.max(0) + 6
    width, height = hi[0] - lo[0], hi[1] - lo[1]
    panel_h = max(1.4, min(4.5, 10.0 * height / max(width, 1e-9)))
    fig, axes = plt.subplots(len(data), 1, figsize=(10, 0.9 + (panel_h + 0.55) * len(data)), squeeze=False,
                             sharex=True)
    for ax, (pos, cell, ctype, step, time) in zip(axes[:, 0], data):
        centre, shape, types = ellipsoids(pos, cell, ctype)
        counts = draw(ax, centre, shape, types, basis)
        summary.append([time if time is not None else "", step, len(centre), len(pos)]
                       + [counts.get(t, 0) for t in range(max(len(names), max(counts, default=0) + 1))]
                       + [float(pos[:, 2].max() - pos[:, 2].min())])
        ax.set_xlim(lo[0], hi[0])
        ax.set_ylim(lo[1], hi[1])
        ax.set_aspect("equal")
        ax.set_ylabel("z (um)" if side else "screen up (um)", fontsize=9)
        when = f"{time:.0f} h (Day {time / 24:.1f})" if time is not None else f"step {step}"
        mix = ", ".join(f"{counts[t]} {names[t] if t < len(names) else f'type {t}'}" for t in counts)
        ax.set_title(f"{when}: {len(centre)} cells ({mix}), {len(pos)} elements", fontsize=9, loc="left")
        ax.tick_params(labelsize=8)
        ax.grid(alpha=0.2)
    axes[-1, 0].set_xlabel("x (um)" if side else "screen right (um)", fontsize=9)
    used = sorted({int(t) for d in data for t in np.unique(d[2])})
    handles = [Patch(facecolor=COLOURS[t % len(COLOURS)], edgecolor="k",
                     label=names[t] if t < len(names) else f"type {t}") for t in used]
    view = "side view (looking along y)" if side else f"view elevation {a.view[0]:g}, azimuth {a.view[1]:g} degrees"
    fig.legend(handles=handles, loc="upper right", ncol=len(handles), fontsize=9, frameon=False)
    fig.suptitle(f"Cells as ellipsoids of their elements' gyration tensor, coloured by type; {view}; near cells "
                 "brighter", fontsize=9, x=0.01, ha="left")
    fig.tight_layout(rect=(0, 0, 1, 1 - 0.35 / fig.get_figheight()))
    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
    tmp = a.out + ".tmp"
    fig.savefig(tmp, dpi=130, format="png")
    os.replace(tmp, a.out)
    print(f"render: wrote {a.out}")
    if a.summary:
        width = max(len(r) for r in summary) - 5
        head = ["time_h", "step", "cells", "elements"] + [names[t] if t < len(names) else f"type_{t}"
                                                          for t in range(width)] + ["thickness_um"]
        tmp = a.summary + ".tmp"
        with open(tmp, "w") as f:
            f.write(",".join(head) + "\n")
            for r in summary:
                r = r[:4] + r[4:-1] + [0] * (width - len(r[4:-1])) + r[-1:]
                f.write(",".join(f"{v:.6g}" if isinstance(v, float) else str(v) for v in r) + "\n")
        os.replace(tmp, a.summary)
        print(f"render: wrote {a.summary}")
    if a.paraview:
        xmf = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(a.states[0]))), "snapshots.xmf")
        paraview_state(a.paraview, xmf, names)
    return 0


if __name__ == "__main__":
    sys.exit(main())
