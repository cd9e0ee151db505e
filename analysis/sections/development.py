"""Report sections for the paper's epidermal-development figure (Day 0-5 as ellipsoids) and the epidermis render."""
import os

from .common import Part, md_table, read_rows, register

FIG = "figures/development.png"
SUMMARY = "figures/development.csv"   # analysis/render.py --summary: cells per type and thickness per panel
STATE = "figures/development_paraview.py"
PAPER_LINE = ("Snapshots Day 0 to Day 5, cells as coloured ellipsoids by type: progressive proliferation, "
              "differentiation and a multilayered (stratified) tissue; no numbers.")


def build(ctx):
    if not os.path.exists(ctx.path(FIG)):
        return None
    body = ["`make development`: Day 0-5 of `scenes/epidermis_development.yaml` (dt 0.1 h x 1,200 steps, a snapshot "
            "every 24 h), drawn by `analysis/render.py`: each cell the ellipsoid of its elements' gyration tensor, "
            "seen from the side (x-z), coloured by type.", "", f"![{FIG}]({FIG})", ""]
    if os.path.exists(ctx.path(STATE)):
        body += [f"ParaView: `{STATE}` (File > Load State, Python state) opens the same snapshots as element spheres "
                 "coloured by type.", ""]
    reading = "Figure only: no per-day summary CSV beside it."
    supported = None
    if os.path.exists(ctx.path(SUMMARY)):
        rows = read_rows(ctx.path(SUMMARY))
        types = [c for c in rows[0] if c not in ("time_h", "step", "cells", "elements", "thickness_um")]
        body.append(md_table(["day", "cells", "elements", *types, "thickness (um)"],
                             [(f"{float(r['time_h']) / 24:.1f}" if r["time_h"] else "?", r["cells"], r["elements"],
                               *(r[t] for t in types), f"{float(r['thickness_um']):.1f}") for r in rows],
                             align="r" * (len(types) + 4)))
        a, b = rows[0], rows[-1]
        grown = int(b["cells"]) > int(a["cells"])
        differentiated = sum(1 for t in types[1:] if int(b[t]) > 0)
        thicker = float(b["thickness_um"]) > float(a["thickness_um"])
        supported = grown and differentiated >= 1 and thicker
        reading = (f"{'Agrees' if supported else 'Differs'} qualitatively: {a['cells']} -> {b['cells']} cells, "
                   f"{differentiated} of {len(types) - 1} later types present by the last panel "
                   f"({', '.join(f'{b[t]} {t}' for t in types)}), thickness {float(a['thickness_um']):.1f} -> "
                   f"{float(b['thickness_um']):.1f} um. At {a['cells']} cells (the paper: 435K) the layers are a few "
                   "cells wide; the scene's proliferative front only reaches mid-sheet by Day 5, so the right half "
                   "stays one layer.")
    setup = ctx.cpu_run(FIG, "1", 1, "6 snapshots (Day 0-5)", "one process")
    summary = "" if supported is None else reading.split(": ", 1)[1].split(". ")[0]
    return Part([("This run", setup, "\n".join(body))], PAPER_LINE, reading, supported, summary)


def build_epidermis(ctx):
    fig = "figures/epidermis.png"
    if not os.path.exists(ctx.path(fig)):
        return None
    return Part([("This run", ctx.cpu_run(fig, "1", 1, "-", "3000 steps of scenes/epidermis.yaml, one process"),
                  f"`make epidermis`, drawn by `analysis/render.py` (side view).\n\n![{fig}]({fig})\n")],
                "Not a figure of the paper (its scene, not its use case).", "No paper comparison.")


register("development", 6, "Epidermal development, Day 0-5: cells as ellipsoids, coloured by type", build, [FIG],
         paper="fig:epidermal_visualization", claim="proliferation, differentiation, stratified tissue (no numbers)")
register("epidermis", 20, "The epidermis scene after 3000 steps", build_epidermis, [])
