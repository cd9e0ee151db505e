"""Hand-made runs for tests/analysis/test_measured_time.sh: a run folder as scripts/gpu/measured_time.sh leaves it."""
import csv
import json
import os

# rank_times.csv's columns that analysis/measured_time.py reads (engine/run/driver.hpp, rank_times)
COLUMNS = ["step", "rank", "compute_s", "exchange_s", "migrate_s", "imbalance", "moved_slices", "wall_s", "device_s",
           "exchange_bytes", "migrate_bytes"]


def write_run(root, name, bounds_per_event, rank_row, slices):
    """ROOT/e2e/NAME: trace.jsonl with each event's boundaries, and rank_times.csv with one row per event e (step
    10 (e + 1)) and rank q: rank_row(e, cuts, q) gives its COLUMNS after step and rank, cuts = [0] + boundaries +
    [slices]."""
    d = os.path.join(root, "e2e", name)
    os.makedirs(d)
    with open(os.path.join(d, "trace.jsonl"), "w") as t:
        for e, b in enumerate(bounds_per_event):
            t.write(json.dumps({"event": e, "boundaries": b}) + "\n")
    with open(os.path.join(d, "rank_times.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(COLUMNS)
        for e, b in enumerate(bounds_per_event):
            cuts = [0] + b + [slices]
            for q in range(len(cuts) - 1):
                w.writerow([10 * (e + 1), q] + list(rank_row(e, cuts, q)))
