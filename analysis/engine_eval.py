#!/usr/bin/env python3
"""Tables and targets of the controller evaluation on engine workloads (experiments/controller_eval_engine.yaml).

Each (workload, policy, knob setting, P) is averaged over the replay seeds. Per workload and P the table lists static,
the reference reactive (tau 0.02, alpha 0.5), each family's setting with the lowest imbalance and the one on the
family's front closest to the shipped GRU's migration, every GRU weights file, and the foresight floor (lambda 0).
Targets (docs/train.md "Engine workloads"), for the shipped GRU (`gru` without gru.weights):
  front:    no deployable setting (every policy but foresight) has both less-or-equal imbalance and migration, one less;
  reactive: imbalance below the reference reactive's with at most 5% more migration;
  gap:      it closes at least half the imbalance gap between the reference reactive and foresight (lambda 0).
and for the learned controller (`learned_repartition` without a setting; docs/controllers.md "learned_repartition"):
  learned loop:     its loop time within 1% of the best other deployable setting's (every policy but foresight, over its
                    knobs, the GRU included) and at most static's;
  learned reactive: less imbalance than the reference reactive with fewer slices moved.
Usage: engine_eval.py --csv CSV [--md OUT.md]   (prints the tables; exit 2 naming the file and column on bad input).
"""
import argparse
import csv
import math
import os
import sys
from collections import defaultdict

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sections.common import md_table  # noqa: E402

KNOB_PREFIXES = ("reactive.", "gromacs_dlb.", "hoomd_balance.", "all_tensor.", "lammps_shift.", "foresight.", "gru.",
                 "holt.", "persistence.", "learned_repartition.")
LEARNED = "learned_repartition"


def read_points(path):
    """{(workload, ranks): [point]} of a CSV file (read_points_rows); ValueError naming the file on bad input."""
    with open(path) as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise ValueError(f"{path}: no rows")
    try:
        return read_points_rows(rows)
    except ValueError as err:
        raise ValueError(f"{path}:{err}")


def read_points_rows(rows):
    """{(workload, ranks): [point]} with point = dict(policy, setting, imbalance, migration, loop_s, seeds): each
    (workload, policy, knob setting, P) averaged over the replay seeds. ValueError "LINE: field ..." on a bad row."""
    groups = defaultdict(list)
    knobs = [c for c in rows[0] if c.startswith(KNOB_PREFIXES)]

    def cell(r, n, name, parse):
        text = r.get(name)
        if text is None:
            raise ValueError(f"{n}: field '{name}': missing (the row has {len([v for v in r.values() if v is not None])} "
                             f"of the header's {len(rows[0])} cells)")
        try:
            value = parse(text)
        except ValueError:
            raise ValueError(f"{n}: field '{name}': '{text}' is not a number")
        if isinstance(value, float) and not math.isfinite(value):
            raise ValueError(f"{n}: field '{name}': '{text}' is not finite")
        return value

    for n, r in enumerate(rows, 2):
        if None in r:  # more cells than the header
            raise ValueError(f"{n}: {len(r[None])} cells beyond the header's {len(rows[0])}")
        key = (cell(r, n, "workload", str), cell(r, n, "ranks", int), cell(r, n, "policy", str),
               tuple((k, r[k] or "") for k in knobs if (r[k] or "") != ""))
        groups[key].append(tuple(cell(r, n, c, float) for c in ("mean_imbalance", "migration", "loop_s")))
    out = defaultdict(list)
    for (w, p, policy, setting), v in groups.items():
        out[(w, p)].append({"policy": policy, "setting": " ".join(f"{k.split('.', 1)[1]}={x}" for k, x in setting),
                            "imbalance": math.fsum(x[0] for x in v) / len(v), "migration": math.fsum(x[1] for x in v) / len(v),
                            "loop_s": math.fsum(x[2] for x in v) / len(v), "seeds": len(v)})
    return out


def summary(points_by_key):
    """{target: (holding cells, cells)} over every (workload, P)."""
    out = defaultdict(lambda: [0, 0])
    for key in points_by_key:
        for name, (ok, _) in evaluate(points_by_key[key])[1].items():
            out[name][0] += ok
            out[name][1] += 1
    return dict(out)


def is_reference_reactive(p):
    return p["policy"] == "reactive" and p["setting"] in ("", "tau=0.02 alpha=0.5", "alpha=0.5 tau=0.02")


def dominates(a, b):
    return a["imbalance"] <= b["imbalance"] and a["migration"] <= b["migration"] and (
        a["imbalance"] < b["imbalance"] or a["migration"] < b["migration"])


def evaluate(points):
    """(table rows, targets dict) for one workload and P."""
    gru = next((p for p in points if p["policy"] == "gru" and p["setting"] == ""), None)
    reactive = next((p for p in points if is_reference_reactive(p)), None)
    foresight = [p for p in points if p["policy"] == "foresight"]
    floor = min(foresight, key=lambda p: p["imbalance"]) if foresight else None
    learned = next((p for p in points if p["policy"] == LEARNED and p["setting"] == ""), None)
    deployable = [p for p in points if p["policy"] not in ("foresight", "gru", LEARNED)]
    rows = []
    for p in points:
        if p["policy"] in ("static", "gru", "persistence", "holt", LEARNED) or is_reference_reactive(p):
            rows.append(p)
    families = defaultdict(list)
    for p in deployable:
        if p["policy"] not in ("static", "persistence", "holt"):
            families[p["policy"]].append(p)
    for fam, pts in sorted(families.items()):
        best = min(pts, key=lambda p: p["imbalance"])
        rows.append(dict(best, note="lowest imbalance"))
        if gru:
            front = [p for p in pts if not any(dominates(q, p) for q in pts)]
            near = min(front, key=lambda p: abs(p["migration"] - gru["migration"]))
            if near is not best:
                rows.append(dict(near, note="front, nearest the GRU's migration"))
    if floor:
        rows.append(dict(floor, note="floor"))
    targets = {}
    if gru and reactive and floor:
        dom = [p for p in deployable if dominates(p, gru)]
        targets["front"] = (not dom, f"{len(dom)} deployable settings dominate it" + (
            f", e.g. {dom[0]['policy']} {dom[0]['setting']} {100 * dom[0]['imbalance']:.2f}% / {dom[0]['migration']:.0f}" if dom else ""))
        ok = gru["imbalance"] < reactive["imbalance"] and gru["migration"] <= 1.05 * reactive["migration"]
        targets["reactive"] = (ok, f"{100 * gru['imbalance']:.2f}% / {gru['migration']:.0f} vs reactive "
                                   f"{100 * reactive['imbalance']:.2f}% / {reactive['migration']:.0f}")
        gap = reactive["imbalance"] - floor["imbalance"]
        share = (reactive["imbalance"] - gru["imbalance"]) / gap if gap > 0 else float("nan")
        targets["gap"] = (share >= 0.5, f"closes {share:.2f} of the gap ({100 * reactive['imbalance']:.2f}% -> "
                                         f"{100 * floor['imbalance']:.2f}%)")
    static = next((p for p in points if p["policy"] == "static"), None)
    others = [p for p in points if p["policy"] not in ("foresight", LEARNED)]
    if learned and others and static:
        best = min(others, key=lambda p: p["loop_s"])
        excess = learned["loop_s"] / best["loop_s"] - 1
        targets["learned loop"] = (excess <= 0.01 and learned["loop_s"] <= static["loop_s"],
                                   f"{learned['loop_s']:.3f} s, {100 * excess:+.2f}% against the best other "
                                   f"({best['policy']} {best['setting'] or 'default'} {best['loop_s']:.3f} s); static "
                                   f"{static['loop_s']:.3f} s")
    if learned and reactive:
        targets["learned reactive"] = (
            learned["imbalance"] < reactive["imbalance"] and learned["migration"] < reactive["migration"],
            f"{100 * learned['imbalance']:.2f}% / {learned['migration']:.0f} vs reactive "
            f"{100 * reactive['imbalance']:.2f}% / {reactive['migration']:.0f}")
    return rows, targets


def render(points_by_key):
    out = []
    for (w, p) in sorted(points_by_key, key=lambda k: (k[0], k[1])):
        rows, targets = evaluate(points_by_key[(w, p)])
        out.append(f"\n#### {os.path.basename(w)}, P = {p}\n")
        out.append(md_table(["policy", "setting", "imbalance %", "migration", "loop s", "note"],
                            [(r["policy"], r["setting"] or "default", f"{100 * r['imbalance']:.2f}", f"{r['migration']:.0f}",
                              f"{r['loop_s']:.3f}", r.get("note", "")) for r in rows], align="llrrrl"))
        for name, (ok, text) in targets.items():
            out.append(f"- target {name}: {'holds' if ok else 'misses'} ({text})")
    return "\n".join(out) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    ap.add_argument("--csv", required=True)
    ap.add_argument("--md", help="markdown file to write")
    a = ap.parse_args()
    try:
        points = read_points(a.csv)
    except OSError as err:
        print(f"engine_eval.py: --csv {a.csv}: {err.strerror}", file=sys.stderr)
        return 2
    except ValueError as err:
        print(f"engine_eval.py: {err}", file=sys.stderr)
        return 2
    text = render(points)
    print(text)
    if a.md:
        with open(a.md + ".tmp", "w") as f:
            f.write(text)
        os.replace(a.md + ".tmp", a.md)
    return 0


if __name__ == "__main__":
    sys.exit(main())
