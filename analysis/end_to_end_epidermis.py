#!/usr/bin/env python3
"""One row of results/gpu/end_to_end_epidermis.csv per `semlb sim` run folder (docs/performance.md "End to end on one
node with 2 H200s").

Usage: end_to_end_epidermis.py --machine TEXT --gpus N [--append] --out CSV RUN_DIR...

Each RUN_DIR is the --out folder of one run: scene.yaml, run.csv and, for a decomposed run, rank_times.csv.
Columns (seconds for the whole run):
  loop_s        sum of run.csv's wall_s (the stepping loop; set-up and the first snapshot excluded)
  compute_s     one device: the sum of the phase columns; decomposed: per rebalancing interval the slowest
                rank's computation time (rank_times.csv compute_s), summed (docs/performance.md "Multi-GPU on H200s")
  cell_stage_s  run.csv's cells_s (one device; decomposed: the slowest rank's, as run.csv logs it)
  exchange_s    decomposed: per interval the slowest rank's ghost exchange, summed; 0 on one device
Errors (a missing file or column) stop with the folder named and exit code 2, writing nothing.
"""
import argparse
import csv
import os
import sys

import yaml

COLUMNS = ["gpus", "ranks", "cells_start", "cells_end", "elements_end", "steps", "precision", "loop_s", "compute_s",
           "cell_stage_s", "exchange_s", "machine"]


def fail(msg):
    print(f"end_to_end_epidermis.py: {msg}", file=sys.stderr)
    sys.exit(2)


def rows_of(path):
    if not os.path.exists(path):
        fail(f"{path}: no such file")
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def run_row(folder, gpus, machine):
    """The CSV row (a dict of COLUMNS) of one run folder."""
    with open(os.path.join(folder, "scene.yaml")) as f:
        scene = yaml.safe_load(f)
    log = rows_of(os.path.join(folder, "run.csv"))
    if not log:
        fail(f"{folder}/run.csv: no rows")
    phases = [c for c in log[0] if c.endswith("_s") and c not in ("wall_s", "exchange_s", "migrate_s")
              and not c.startswith("bytes")]
    total = lambda col: sum(float(r[col]) for r in log) if col in log[0] else 0.0
    ranks, compute, exchange = 1, sum(total(p) for p in phases), 0.0
    times = os.path.join(folder, "rank_times.csv")
    if os.path.exists(times):
        intervals = {}
        for r in rows_of(times):
            intervals.setdefault(int(r["step"]), []).append(r)
        ranks = max(int(r["rank"]) for rs in intervals.values() for r in rs) + 1
        compute = sum(max(float(r["compute_s"]) for r in rs) for rs in intervals.values())
        exchange = sum(max(float(r["exchange_s"]) for r in rs) for rs in intervals.values())
    first_step = int(log[0]["step"]) - int(scene.get("output", {}).get("log_every", 100))
    return {"gpus": gpus, "ranks": ranks, "cells_start": scene["tissue"]["cells"], "cells_end": log[-1]["cells"],
            "elements_end": log[-1]["elements"], "steps": int(log[-1]["step"]) - max(first_step, 0),
            "precision": scene["backend"]["precision"], "loop_s": f"{total('wall_s'):.4g}", "compute_s": f"{compute:.4g}",
            "cell_stage_s": f"{total('cells_s'):.4g}", "exchange_s": f"{exchange:.4g}", "machine": machine}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--machine", required=True, help="e.g. 'NVIDIA H200 (x2 node)' or 'PoCL, 2-core CPU'")
    ap.add_argument("--gpus", type=int, required=True, help="GPUs the run used (0: CPU)")
    ap.add_argument("--out", required=True)
    ap.add_argument("--append", action="store_true", help="add rows to an existing CSV")
    ap.add_argument("runs", nargs="+")
    a = ap.parse_args()
    rows = [run_row(d, a.gpus, a.machine) for d in a.runs]  # all checked before anything is written
    exists = a.append and os.path.exists(a.out)
    with open(a.out, "a" if exists else "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=COLUMNS, lineterminator="\n")
        if not exists:
            w.writeheader()
        w.writerows(rows)


if __name__ == "__main__":
    main()
