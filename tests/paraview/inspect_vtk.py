"""pvpython script: what ParaView itself reads from a run's VTK folder, printed as one JSON line.

Usage: ``pvpython inspect_vtk.py RUN_DIR [RUN_DIR ...]`` (run by tests/test_paraview.py under ``xvfb-run``).
For each folder: the time steps of ``body.pvd`` and ``contact_surface.pvd``, every point array with its
number of components and component names, the field data of the last step, the range of each stress component
and of von Mises at the last step, and the surface's cell types.
"""

import json
import sys

from paraview import servermanager as sm
from paraview.simple import OpenDataFile, UpdatePipeline


def arrays(src, t):
    UpdatePipeline(time=t, proxy=src)
    data = sm.Fetch(src)
    if data.IsA("vtkMultiBlockDataSet"):
        data = data.GetBlock(0)
    pd = data.GetPointData()
    out = {}
    for i in range(pd.GetNumberOfArrays()):
        a = pd.GetArray(i)
        comps = [a.GetComponentName(c) for c in range(a.GetNumberOfComponents())]
        out[a.GetName()] = {"ncomp": a.GetNumberOfComponents(), "names": comps,
                            "range": [list(a.GetRange(c)) for c in range(a.GetNumberOfComponents())]}
    fd = data.GetFieldData()
    field = {}
    for i in range(fd.GetNumberOfArrays()):
        a = fd.GetArray(i)
        if a is not None and a.GetNumberOfTuples() > 0:
            field[a.GetName()] = a.GetTuple1(0)
        else:
            name = fd.GetAbstractArray(i).GetName()
            field[name] = None
    cell_types = sorted({data.GetCellType(i) for i in range(data.GetNumberOfCells())})
    return {"arrays": out, "field": field, "points": data.GetNumberOfPoints(), "cells": data.GetNumberOfCells(),
            "cell_types": cell_types, "bounds": list(data.GetBounds())}


report = {}
for folder in sys.argv[1:]:
    entry = {}
    for name in ("body", "contact_surface"):
        src = OpenDataFile(f"{folder}/{name}.pvd")
        times = list(src.TimestepValues) if src.TimestepValues else []
        entry[name] = {"times": times, "last": arrays(src, times[-1] if times else 0.0),
                       "first": arrays(src, times[0] if times else 0.0)}
    report[folder] = entry
print("JSON" + json.dumps(report))
