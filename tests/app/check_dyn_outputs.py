#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""End-to-end check of a dynamic run's output directory: series.csv has the promised columns,
finite values and steps on the csv_interval grid; every XDMF DataItem resolves to an HDF5 dataset
of the stated shape (Xdmf3: every topology has its connectivity item); triangle connectivity
indexes existing nodes; no dump holds a NaN; checkpoint.h5 is at the last dump; charts are PNGs.
Usage: check_dyn_outputs.py OUTDIR [--partial]   (--partial: a run stopped early, no charts)"""
import math
import os
import sys
import xml.etree.ElementTree as ET

import h5py

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
from check_xdmf import check_xdmf  # noqa: E402
from nacre import read_json, read_rows  # noqa: E402  (the reader of nacre's outputs, python/nacre)
import numpy as np

out = sys.argv[1]
partial = "--partial" in sys.argv
charts = not partial
fail = []


def check(cond, msg):
    if not cond:
        fail.append(msg)


cols = ["step", "time", "displacement", "strain_energy", "kinetic_energy", "cohesive_energy",
        "damping_dissipated", "external_work", "balance_residual", "reaction", "ruptured", "crack_interfaces",
        "crack_bed", "crack_head", "crack_tip_x", "crack_tip_y", "crack_extension", "crack_path_length",
        "crack_deflection", "process_zone", "process_zone_extent", "fracture_energy", "crack_speed", "crack_speed_rayleigh", "dt",
        "critical_estimate", "seconds"]
rows = read_rows(os.path.join(out, "series.csv"))
check(len(rows) >= (1 if partial else 2), "series.csv has too few rows")
check(rows and list(rows[0].keys()) == cols, f"series.csv columns {list(rows[0].keys()) if rows else []}")
for r in rows:
    for c in cols:
        v = float(r[c])
        if not math.isfinite(v):
            check(False, f"series.csv step {r['step']}: {c} = {r[c]} is not finite")
steps = [int(r["step"]) for r in rows]
check(steps == sorted(set(steps)), "steps not strictly increasing")
times = [float(r["time"]) for r in rows]
check(all(a < b for a, b in zip(times, times[1:])), "time does not increase")
summary = read_json(os.path.join(out, "summary.json"))
# the crack columns (docs/fracture.md): a part of the ruptured joints, path >= extension, the speed
# the change of extension between rows, over the Rayleigh speed in summary.json
crack = summary.get("crack")
check(crack is not None and crack.get("rayleigh_speed", 0) > 0, "summary.json lacks crack.rayleigh_speed")
prev = None
for r in rows:
    n, ext, path = int(r["crack_interfaces"]), float(r["crack_extension"]), float(r["crack_path_length"])
    check(0 <= n <= int(r["ruptured"]) and n == int(r["crack_bed"]) + int(r["crack_head"]),
          f"step {r['step']}: crack joints {n} vs ruptured {r['ruptured']}, bed + head")
    check(ext >= 0 and path >= ext * (1 - 1e-12), f"step {r['step']}: path {path} shorter than extension {ext}")
    check(abs(float(r["crack_tip_x"]) - crack["notch_tip_x"] - ext) <= 1e-9 or ext == 0,
          f"step {r['step']}: extension is not tip x - notch tip x")
    if prev is not None and crack:
        v = (ext - float(prev["crack_extension"])) / (float(r["time"]) - float(prev["time"]))
        check(abs(float(r["crack_speed"]) - v) <= 1e-6 * max(1.0, abs(v)), f"step {r['step']}: crack_speed {r['crack_speed']} vs {v}")
        check(abs(float(r["crack_speed_rayleigh"]) * crack["rayleigh_speed"] - float(r["crack_speed"])) <=
              1e-9 * max(1.0, abs(v)), f"step {r['step']}: crack_speed_rayleigh inconsistent")
    prev = r
for k in ["method", "status", "bricks", "dt", "steps", "element_types", "device_bytes"]:
    check(k in summary, f"summary.json lacks {k}")
nb = summary["bricks"]

root = ET.parse(os.path.join(out, "nacre.xdmf")).getroot()
fail += check_xdmf(os.path.join(out, "nacre.xdmf"))  # Xdmf3: every topology has its connectivity
count = 0
for grid in root.iter("Grid"):
    if grid.attrib.get("GridType") != "Uniform":
        continue
    topo = grid.find("Topology")
    check(topo is not None and topo.find("DataItem") is not None,
          f"grid {grid.attrib['Name']}: topology without a connectivity DataItem (Xdmf3 needs one)")
for it in root.iter("DataItem"):
    fname, path = it.text.strip().split(":")
    dims = [int(d) for d in it.attrib["Dimensions"].split()]
    p = os.path.join(out, fname)
    check(os.path.exists(p), f"{fname} referenced by nacre.xdmf is missing")
    if not os.path.exists(p):
        continue
    with h5py.File(p, "r") as h:
        check(path in h, f"{fname}:{path} missing")
        if path in h:
            shape = list(h[path].shape)
            check(shape == dims, f"{fname}:{path} has shape {shape}, XDMF says {dims}")
            if h[path].dtype.kind == "f":
                check(bool(np.isfinite(h[path][...]).all()), f"{fname}:{path} holds a non-finite value")
    count += 1
check(count > 0, "no DataItem in nacre.xdmf")

with h5py.File(os.path.join(out, "mesh.h5"), "r") as m:
    conn = m["/triangles/connectivity"][...]
    nn = m["/nodes/reference"].shape[0]
    check(conn.min() >= 0 and conn.max() < nn, "triangle connectivity indexes a missing node")
    check(m["/bricks/area"].shape[0] == nb, "mesh.h5 brick count != summary")
    tb = m["/triangles/brick"][...]
    check(tb.min() >= 0 and tb.max() < nb and len(set(tb.tolist())) == nb, "not every brick has triangles")
dumps = sorted(f for f in os.listdir(out) if f.startswith("dump_") and f.endswith(".h5"))
check(len(dumps) >= (1 if partial else 2), "too few dumps")
for f in dumps:
    with h5py.File(os.path.join(out, f), "r") as d:
        for name in ["/nodes/points", "/nodes/displacement", "/nodes/velocity", "/triangles/syy", "/bricks/syy",
                     "/interfaces/damage"]:
            check(name in d and bool(np.isfinite(d[name][...]).all()), f"{f}:{name} missing or not finite")
        check(d["/bricks/syy"].shape == (nb,), f"{f}: /bricks/syy has {d['/bricks/syy'].shape}, {nb} bricks")
        check(d["/nodes/points"].shape == (nn, 2), f"{f}: /nodes/points shape")
        check(int(f[5:-3]) == int(d.attrs["step"]), f"{f}: step attribute {d.attrs['step']}")
with h5py.File(os.path.join(out, "checkpoint.h5"), "r") as c:
    check(c.attrs["kind"] == b"dynamics" or c.attrs["kind"] == "dynamics", "checkpoint kind")
    check(int(c.attrs["step"]) == int(dumps[-1][5:-3]), "checkpoint is not at the last dump")
    check(len(c["/arrays"].keys()) > 0, "checkpoint holds no state arrays")
    for k in c["/arrays"]:
        check(bool(np.isfinite(c["/arrays/" + k][...]).all()), f"checkpoint /arrays/{k} not finite")
if summary.get("status") == "done":
    check(int(dumps[-1][5:-3]) == steps[-1], "last dump is not at the last step")
if charts:
    for png in ["energy_force.png", "crack.png"]:
        p = os.path.join(out, png)
        check(os.path.exists(p) and open(p, "rb").read(8) == b"\x89PNG\r\n\x1a\n", f"{png} missing or not a PNG")
check(not [f for f in os.listdir(out) if ".tmp" in f], "temporary files left behind")
if fail:
    print("\n".join("FAIL: " + f for f in fail))
    sys.exit(1)
print(f"outputs of {out}: {len(rows)} rows, {len(dumps)} dumps, {count} XDMF data items, all consistent")
