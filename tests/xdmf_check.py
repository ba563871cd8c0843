#!/usr/bin/env python3
"""The XDMF files grainlab writes (a run's particles.xdmf, plot's localisation.xdmf) as a reader takes them.

Each argument is an .xdmf file. For every time step of every temporal collection: the times increase; every DataItem
names an HDF5 dataset that exists beside the file, with as many values as its Dimensions and the number type and
precision it declares; the geometry is XYZ; the topology carries its connectivity (NumberOfElements x NodesPerElement
indices, each a point of the geometry) -- a Polyvertex without one is what VTK's Xdmf3 reader (ParaView 5.11) turned
into points without cells, which ParaView's default representations do not draw (found with pvbatch, session 40) --
and a Polyvertex topology makes every point a vertex cell once; each attribute has a value per point (Center Node) or
per cell (Center Cell), three for a Vector. With ParaView's pvbatch on the PATH the files are also opened in it and
every particle grid must come back with as many cells as points (skipped without it: the structural checks are what
CI runs).
"""
import os
import shutil
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET

import h5py
import numpy as np

DTYPES = {("Float", "8"): np.float64, ("Float", "4"): np.float32, ("Int", "4"): np.int32, ("Int", "8"): np.int64}


def dataset(xdmf, item):
    """The DataItem's values (an HDF5 dataset, file:/path relative to the .xdmf), checked against its declaration."""
    if item.get("Format") != "HDF":
        raise AssertionError(f"DataItem {item.text!r}: Format {item.get('Format')!r}, expected HDF")
    fname, path = item.text.strip().split(":", 1)
    full = os.path.join(os.path.dirname(os.path.abspath(xdmf)), fname)
    with h5py.File(full, "r") as f:
        if path not in f:
            raise AssertionError(f"{full}: no dataset {path}")
        a = f[path][...]
    dims = [int(d) for d in item.get("Dimensions").split()]
    if a.size != int(np.prod(dims)):
        raise AssertionError(f"{item.text}: {a.size} values, Dimensions {dims}")
    want = DTYPES.get((item.get("NumberType", "Float"), item.get("Precision", "4")))
    if want is None or a.dtype != want:
        raise AssertionError(f"{item.text}: dtype {a.dtype}, declared {item.get('NumberType')} {item.get('Precision')}")
    return a.reshape(dims)


def check_grid(xdmf, g):
    geo = g.find("Geometry")
    if geo is None or geo.get("GeometryType") != "XYZ":
        raise AssertionError(f"grid {g.get('Name')}: no XYZ geometry")
    x = dataset(xdmf, geo.find("DataItem"))
    npts = x.shape[0]
    if x.shape != (npts, 3):
        raise AssertionError(f"grid {g.get('Name')}: geometry of shape {x.shape}")
    topo = g.find("Topology")
    kind, ncells = topo.get("TopologyType"), int(topo.get("NumberOfElements"))
    per = topo.get("NodesPerElement")
    conn_item = topo.find("DataItem")
    if per is None or conn_item is None:
        raise AssertionError(f"grid {g.get('Name')}: {kind} topology without NodesPerElement and connectivity "
                             "(VTK's Xdmf3 reader makes no cells of it)")
    conn = dataset(xdmf, conn_item)
    if conn.size != ncells * int(per) or conn.dtype.kind != "i":
        raise AssertionError(f"grid {g.get('Name')}: {conn.size} connectivity entries for {ncells} x {per}")
    if conn.size and (conn.min() < 0 or conn.max() >= npts):
        raise AssertionError(f"grid {g.get('Name')}: connectivity outside the {npts} points")
    if kind == "Polyvertex" and not (int(per) == 1 and np.array_equal(np.sort(conn.ravel()), np.arange(npts))):
        raise AssertionError(f"grid {g.get('Name')}: the vertex cells are not every point once")
    for att in g.findall("Attribute"):
        a = dataset(xdmf, att.find("DataItem"))
        n = npts if att.get("Center") == "Node" else ncells if att.get("Center") == "Cell" else None
        comps = 3 if att.get("AttributeType") == "Vector" else 1
        if n is None or a.shape[0] != n or a.size != n * comps:
            raise AssertionError(f"grid {g.get('Name')}, attribute {att.get('Name')}: shape {a.shape} for "
                                 f"{n} {att.get('Center')} values of {comps}")
    return kind, npts, ncells


def check(xdmf):
    root = ET.parse(xdmf).getroot()
    summary = []
    for coll in root.find("Domain").findall("Grid"):
        if coll.get("CollectionType") != "Temporal":
            raise AssertionError(f"{xdmf}: grid {coll.get('Name')} is not a temporal collection")
        times = [float(g.find("Time").get("Value")) for g in coll.findall("Grid")]
        if not times or any(b <= a for a, b in zip(times, times[1:])):
            raise AssertionError(f"{xdmf}: {coll.get('Name')}'s times {times} do not increase")
        steps = [check_grid(xdmf, g) for g in coll.findall("Grid")]
        summary.append(f"{coll.get('Name')}: {len(steps)} step(s), {steps[-1][0]} {steps[-1][2]} cells on "
                       f"{steps[-1][1]} points")
    return summary


PVBATCH = """
import sys
from paraview.simple import OpenDataFile
from paraview import servermanager as sm
r = OpenDataFile(sys.argv[1])
r.UpdatePipelineInformation()
times = r.TimestepValues  # a float where the file has one time step
for t in (times if hasattr(times, "__len__") else [times]):
    r.UpdatePipeline(t)
    d = sm.Fetch(r)
    blocks = []  # one grid comes back as itself, several as a multiblock set
    if d.IsA("vtkCompositeDataSet"):
        it = d.NewIterator()
        it.InitTraversal()
        while not it.IsDoneWithTraversal():
            blocks.append(it.GetCurrentDataObject())
            it.GoToNextItem()
    else:
        blocks.append(d)
    for b in blocks:
        if b.GetPointData().GetNumberOfArrays():  # the particle grids (the contacts' attributes are per cell)
            print("points", b.GetNumberOfPoints(), "cells", b.GetNumberOfCells())
"""


def check_in_paraview(xdmf):
    with tempfile.NamedTemporaryFile("w", suffix=".py") as script:
        script.write(PVBATCH)
        script.flush()
        out = subprocess.run(["pvbatch", script.name, xdmf], capture_output=True, text=True, timeout=300)
    grids = [line.split() for line in out.stdout.splitlines() if line.startswith("points ")]
    if not grids or any(g[1] != g[3] for g in grids):
        raise AssertionError(f"ParaView read {xdmf} as {grids or out.stdout + out.stderr}: a cell per point expected")
    return len(grids)


fails = []
for path in sys.argv[1:]:
    try:
        print(f"{path}: " + "; ".join(check(path)))
        if shutil.which("pvbatch"):
            print(f"  ParaView (pvbatch): {check_in_paraview(path)} particle grid(s), a vertex cell per point")
        else:
            print("  (pvbatch not on the PATH: structural checks only)")
    except (AssertionError, OSError, KeyError, ValueError) as e:
        fails.append(f"{path}: {e}")
if fails or len(sys.argv) < 2:
    sys.exit("\n".join(fails) or "usage: xdmf_check.py FILE.xdmf ...")
print("xdmf ok")
