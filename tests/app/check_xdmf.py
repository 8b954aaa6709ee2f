#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Structural check of nacre.xdmf files as ParaView's default reader (Xdmf3) needs them: every
Topology has its connectivity DataItem, whose dimensions match NumberOfElements x nodes per
element (Triangle 3, Polyline NodesPerElement; Mixed: the flat array walks to exactly
NumberOfElements cells), the referenced HDF5 dataset exists with that shape, and every index it
holds is a point of the grid's Geometry. Every DataItem of the file resolves to a dataset of
the stated shape.
Usage: check_xdmf.py FILE.xdmf [...]   (exit 1 and one FAIL line per problem)
Also imported by check_outputs.py / check_dyn_outputs.py (check_xdmf(path) -> list of problems).
No python Xdmf/VTK/meshio module is in the dev root, so the file is not loaded by a reader here."""
import os
import sys
import xml.etree.ElementTree as ET

import h5py
import numpy as np

# XDMF Mixed topology cell codes: nodes per cell, or None when a node count follows the code
MIXED = {1: None, 2: None, 3: None, 4: 3, 5: 4, 6: 4, 9: 8}
FIXED = {"Triangle": 3, "Quadrilateral": 4, "Tetrahedron": 4, "Hexahedron": 8}


def dataset(base, item, fail):
    """The array a Format="HDF" DataItem references, or None (with a FAIL) if it does not resolve."""
    fname, path = item.text.strip().split(":")
    full = os.path.join(base, fname)
    if not os.path.exists(full):
        fail.append(f"{fname} (referenced) is missing")
        return None
    with h5py.File(full, "r") as h:
        if path not in h:
            fail.append(f"{fname}:{path} missing")
            return None
        data = h[path][()]
    dims = [int(d) for d in item.attrib["Dimensions"].split()]
    if list(data.shape) != dims:
        fail.append(f"{fname}:{path} has shape {list(data.shape)}, XDMF says {dims}")
    return data


def check_grid(base, grid, name, fail):
    topo, geom = grid.find("Topology"), grid.find("Geometry")
    if topo is None or geom is None:
        fail.append(f"{name}: no Topology or Geometry")
        return
    kind = topo.attrib.get("TopologyType")
    n = int(topo.attrib["NumberOfElements"])
    items = topo.findall("DataItem")
    if len(items) != 1:
        fail.append(f"{name}: {kind} topology has {len(items)} connectivity DataItems (Xdmf3 needs one)")
        return
    dims = [int(d) for d in items[0].attrib["Dimensions"].split()]
    conn = dataset(base, items[0], fail)
    g = geom.find("DataItem")
    npoints = int(g.attrib["Dimensions"].split()[0]) if g is not None else 0
    if kind == "Mixed":
        if conn is None:
            return
        flat, pos, cells = conn.reshape(-1), 0, 0
        while pos < flat.size:
            code = int(flat[pos])
            if code not in MIXED:
                fail.append(f"{name}: unknown Mixed cell code {code} at {pos}")
                return
            nodes = MIXED[code]
            if nodes is None:
                nodes = int(flat[pos + 1])
                pos += 1
            ids = flat[pos + 1:pos + 1 + nodes]
            if ids.size != nodes or (ids.size and (ids.min() < 0 or ids.max() >= npoints)):
                fail.append(f"{name}: Mixed cell {cells} indexes outside the {npoints} points")
                return
            pos += 1 + nodes
            cells += 1
        if cells != n:
            fail.append(f"{name}: Mixed connectivity holds {cells} cells, NumberOfElements = {n}")
        return
    if kind == "Polyline":
        if "NodesPerElement" not in topo.attrib:
            fail.append(f"{name}: Polyline without NodesPerElement")
            return
        per = int(topo.attrib["NodesPerElement"])
    elif kind in FIXED:
        per = FIXED[kind]
    else:
        fail.append(f"{name}: topology type {kind} not checked")
        return
    if dims != [n, per] and dims != [n * per]:
        fail.append(f"{name}: {kind} connectivity {dims}, expected [{n}, {per}]")
    if conn is not None and conn.size and (conn.min() < 0 or conn.max() >= npoints):
        fail.append(f"{name}: {kind} connectivity indexes outside the {npoints} points")


def check_xdmf(path):
    """Problems found in one nacre.xdmf (empty list: consistent)."""
    fail = []
    base = os.path.dirname(os.path.abspath(path))
    root = ET.parse(path).getroot()
    grids = [g for g in root.iter("Grid") if g.attrib.get("GridType", "Uniform") == "Uniform"]
    if not grids:
        fail.append("no uniform grid")
    for g in grids:
        check_grid(base, g, f"{os.path.basename(path)} grid {g.attrib.get('Name')}", fail)
    for it in root.iter("DataItem"):  # attributes and geometry too
        dataset(base, it, fail)
    return fail


if __name__ == "__main__":
    problems = []
    for p in sys.argv[1:]:
        problems += [f"{p}: {f}" for f in check_xdmf(p)]
    if not sys.argv[1:]:
        problems.append("no nacre.xdmf given")
    if problems:
        print("\n".join("FAIL: " + f for f in problems))
        sys.exit(1)
    print(f"{len(sys.argv) - 1} XDMF file(s): every topology has its connectivity, every DataItem resolves")
