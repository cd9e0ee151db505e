#!/usr/bin/env python3
"""results/gpu/peer_yalla.csv from the output of scripts/gpu/peer_yalla/run.sh (the peer benchmark against ya||a).

Usage: peer_yalla.py --machine TEXT LOG > peer_yalla.csv
LOG holds rounds of `semlb bench engine` tables (one per semlb variant: the full or the half neighbour list, whose
"list:" line says "(half: newton)") followed by ya||a lines ("yalla grid_solver n=N ... ms/force-eval=X"); each ya||a
line is paired with every semlb row of the same element count in the same round, one CSV row each.
ratio = yalla_ms_per_eval / semlb_ms_per_step (above 1: semlb faster). Exit 2 naming the line on a malformed log.
"""
import argparse
import csv
import re
import sys


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--machine", required=True)
    ap.add_argument("log")
    a = ap.parse_args()
    w = csv.writer(sys.stdout, lineterminator="\n")
    w.writerow(["elements", "semlb_ms_per_step", "yalla_ms_per_eval", "ratio", "precision", "machine", "round", "skin",
                "newton"])
    header, semlb, rnd, rows, after_yalla, last = None, {}, 0, 0, True, None
    for n, line in enumerate(open(a.log), 1):
        f = line.split()
        if line.startswith("# semlb bench engine"):
            if after_yalla:  # the first table of a round
                rnd, semlb, after_yalla = rnd + 1, {}, False
            header = None
        elif f and f[0] == "backend":
            header = f
        elif header and f and f[0].startswith("opencl"):
            skin = f[header.index("skin")] if "skin" in header else "0"  # the neighbour list's skin (um); 0: none
            last = [float(f[header.index("ms/step")]), f[header.index("precision")], skin, 0]
            semlb.setdefault(int(f[header.index("elements")]), []).append(last)
        elif line.lstrip().startswith("list:") and "(half: newton)" in line and last:
            last[3] = 1
        elif line.startswith("yalla"):
            after_yalla = True
            m = re.search(r"n=(\d+) .*ms/force-eval=([0-9.]+)", line)
            if not m or int(m.group(1)) not in semlb:
                print(f"peer_yalla.py: {a.log}:{n}: no semlb row for this ya||a line", file=sys.stderr)
                sys.exit(2)
            y = float(m.group(2))
            for ms, precision, skin, newton in semlb[int(m.group(1))]:
                w.writerow([m.group(1), ms, y, f"{y / ms:.3g}", precision, a.machine, rnd, float(skin), newton])
                rows += 1
    if not rows:
        print(f"peer_yalla.py: {a.log}: no ya||a lines", file=sys.stderr)
        sys.exit(2)


if __name__ == "__main__":
    main()
