#!/usr/bin/env python3
"""How busy a warp's lanes are in nl_forces' partner loop (docs/performance.md "Slots grouped by list length").

Usage: list_warps.py STATE.h5 --cutoff UM --skin UM [--within random|element] [--windows N] [--window-slots N]

STATE.h5 is a state file of `semlb sim` (/elements/position, um). The slots are ordered as opencl-binned's list build
orders them: bins of edge >= cutoff + skin over the tissue (z-major, x fastest); within a bin the device's atomic
scatter decides, modelled as random order (`--within random`, the default) or as the elements' own order (`element`,
closer to a GPU, whose atomics tend to follow the work-items): the two bracket the device. Each slot's list holds its partners within cutoff + skin (the full list), or only those after it in
slot order (the half list, `newton: true`). A warp of 32 consecutive slots loops as long as its longest list, so its
lanes' efficiency is sum(lengths) / (32 max length). Printed per list: that efficiency over the whole tissue (the half
list on N windows of consecutive slots, since its lists need the pairs), and what sorting the slots by length within
blocks of 64 .. 4096 consecutive slots (-DSEMLB_NL_GROUP_SORT sorts within the work-group of 128) would give.
A structural estimate on the CPU (scipy's cKDTree), not a GPU measurement: the loop's share of the kernel, the gathers
a permutation scatters and the sort's cost are the GPU's to tell (scripts/gpu/force_step.sh).
"""
import argparse
import sys

import h5py
import numpy as np
from scipy.spatial import cKDTree

WARP = 32
BLOCKS = (64, 128, 256, 1024, 4096)


def slot_order(x, cutoff, skin, within="random", seed=1):
    """Slots in bin order: bins of edge (cutoff + skin)(1 + 1e-4) over the tissue's box plus one cutoff, z-major with x
    fastest; within a bin in random order or in the elements' order (`within`). Returns the element index of each
    slot."""
    edge = (cutoff + skin) * (1 + 1e-4)
    lo = x.min(0) - cutoff
    ext = np.maximum(x.max(0) + cutoff - lo, edge)
    nb = np.maximum(1, np.floor(ext / edge)).astype(int)
    b = np.clip(np.floor((x - lo) / (ext / nb)).astype(int), 0, nb - 1)
    key = (b[:, 2] * nb[1] + b[:, 1]) * nb[0] + b[:, 0]
    tie = np.random.default_rng(seed).random(len(x)) if within == "random" else np.arange(len(x))
    return np.lexsort((tie, key))


def efficiency(lengths):
    """sum(lengths) / (32 sum of each warp's longest), over whole warps of consecutive slots."""
    m = len(lengths) // WARP * WARP
    w = np.asarray(lengths[:m]).reshape(-1, WARP)
    longest = w.max(1).sum()
    return w.sum() / (WARP * longest) if longest > 0 else 1.0


def sorted_within(lengths, block):
    """efficiency() after sorting each block of `block` consecutive slots by length, longest first."""
    m = len(lengths) // block * block
    return efficiency(-np.sort(-np.asarray(lengths[:m]).reshape(-1, block), axis=1).ravel())


def report(tag, lengths):
    blocks = ", ".join(f"{b}: {sorted_within(lengths, b):.3f}" for b in BLOCKS if b <= len(lengths))
    return (f"{tag}: mean {np.mean(lengths):.1f} partners, max {np.max(lengths)}; warp efficiency "
            f"{efficiency(lengths):.3f}; sorted within blocks of {blocks}")


def main(argv=None):
    a = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    a.add_argument("state")
    a.add_argument("--cutoff", type=float, required=True)
    a.add_argument("--skin", type=float, required=True)
    a.add_argument("--within", choices=("random", "element"), default="random")
    a.add_argument("--windows", type=int, default=8)
    a.add_argument("--window-slots", type=int, default=65536)
    o = a.parse_args(argv)
    if not (0 < o.cutoff < 1e6 and 0 < o.skin < 1e6) or o.windows < 1 or o.window_slots < WARP or o.window_slots % WARP:
        sys.exit("list_warps.py: --cutoff and --skin finite and > 0, --windows >= 1, --window-slots a multiple of 32")
    try:
        with h5py.File(o.state, "r") as f:
            x = np.asarray(f["elements/position"][:], dtype=float).reshape(-1, 3)
    except (OSError, KeyError) as e:
        sys.exit(f"list_warps.py: {o.state}: {e}")
    if len(x) < WARP:
        sys.exit(f"list_warps.py: {o.state}: {len(x)} elements, fewer than a warp")
    xs = x[slot_order(x, o.cutoff, o.skin, o.within)]
    tree = cKDTree(xs)
    r = o.cutoff + o.skin
    full = tree.query_ball_point(xs, r, return_length=True, workers=-1) - 1
    print(f"{len(x)} elements, cutoff {o.cutoff} + skin {o.skin} um, {o.within} order within a bin")
    print(report("full list", full))
    # windows of whole sorting blocks (BLOCKS[-1] slots), apart: at most as many as fit without overlapping
    size = min(o.window_slots, len(x) // WARP * WARP)
    align = BLOCKS[-1] if size % BLOCKS[-1] == 0 else WARP
    count = max(1, min(o.windows, len(x) // size))
    starts = np.unique(np.linspace(0, len(x) - size, count).astype(int) // align * align)
    halves, fulls = [], []
    for start in starts:
        idx = np.arange(start, start + size)
        lists = tree.query_ball_point(xs[idx], r, workers=-1)
        halves.append(np.array([sum(1 for j in js if j > i) for i, js in zip(idx, lists)]))
        fulls.append(full[idx])
    print(report(f"full list on {len(starts)} windows of {size} slots", np.concatenate(fulls)))
    print(report(f"half list on {len(starts)} windows of {size} slots", np.concatenate(halves)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
