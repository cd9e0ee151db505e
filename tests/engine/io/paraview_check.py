#!/usr/bin/env python3
"""Opens a semlb XDMF index with ParaView's default reader and checks what it shows against the state files.

Usage: paraview_check.py INDEX.xmf STATE.h5 [STATE.h5 ...]  (the states the index must hold, in time order).
Asserts, per state: the reader is Xdmf3, one time step per state at the state's time, n points at the
positions of /elements/position, n cells (one poly-vertex each, cell i = point i), and point arrays cell,
type and slot equal to the cell id, type and index within the cell that /cells places each element at,
ranges included. Prints one line per state; exits 1 on the first mismatch.
"""
import os
import sys

import h5py
import numpy as np
from paraview import servermanager as sm
from paraview.simple import OpenDataFile
from vtkmodules.util.numpy_support import vtk_to_numpy

VTK_POLY_VERTEX = 2


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def expected(path):
    """Positions, per-element cell id, type and slot, and the time of a state file, from /cells alone."""
    with h5py.File(path, "r") as f:
        counts = f["/cells/count"][()]
        return {
            "position": f["/elements/position"][()],
            "cell": np.repeat(f["/cells/id"][()], counts),
            "type": np.repeat(f["/cells/type"][()], counts),
            "slot": np.concatenate([np.arange(c) for c in counts]),
            "time": float(f.attrs["time"]),
        }


def main():
    index, states = os.path.abspath(sys.argv[1]), sys.argv[2:]
    want = [expected(s) for s in states]
    reader = OpenDataFile(index)  # Xdmf3 needs a path with a directory: relative names resolve wrongly
    if reader is None or not reader.GetXMLName().startswith("Xdmf3Reader"):
        fail(f"{index}: ParaView's default reader is {reader and reader.GetXMLName()}, expected Xdmf3")
    times = reader.TimestepValues
    times = [times] if isinstance(times, float) else list(times)
    if times != [w["time"] for w in want]:
        fail(f"{index}: time steps {times}, expected {[w['time'] for w in want]}")
    for state, w, t in zip(states, want, times):
        reader.UpdatePipeline(t)
        grid = sm.Fetch(reader)
        n = len(w["cell"])
        at = f"{index} at t = {t} ({os.path.basename(state)})"
        if grid.GetNumberOfPoints() != n or grid.GetNumberOfCells() != n:
            fail(f"{at}: {grid.GetNumberOfPoints()} points and {grid.GetNumberOfCells()} cells, expected {n} and {n}")
        if not np.array_equal(vtk_to_numpy(grid.GetPoints().GetData()), w["position"]):
            fail(f"{at}: point positions differ from /elements/position")
        types = vtk_to_numpy(grid.GetCellTypesArray())
        if not np.all(types == VTK_POLY_VERTEX):
            fail(f"{at}: cell types {sorted(set(types.tolist()))}, expected {VTK_POLY_VERTEX} (poly-vertex)")
        conn = vtk_to_numpy(grid.GetCells().GetConnectivityArray())
        offsets = vtk_to_numpy(grid.GetCells().GetOffsetsArray())
        if not (np.array_equal(conn, np.arange(n)) and np.array_equal(offsets, np.arange(n + 1))):
            fail(f"{at}: cell i is not exactly point i")
        for name in ("cell", "type", "slot"):
            array = grid.GetPointData().GetArray(name)
            if array is None:
                fail(f"{at}: no point array '{name}'")
            if not np.array_equal(vtk_to_numpy(array), w[name]):
                fail(f"{at}: point array '{name}' differs from the state's cells")
            if reader.PointData[name].GetRange() != (float(w[name].min()), float(w[name].max())):
                fail(f"{at}: '{name}' range {reader.PointData[name].GetRange()}, expected {w[name].min()}..{w[name].max()}")
        print(f"ok {at}: {n} points, {n} cells, cell ids {w['cell'].min()}..{w['cell'].max()}, "
              f"types {w['type'].min()}..{w['type'].max()}, slots 0..{w['slot'].max()}")


if __name__ == "__main__":
    main()
