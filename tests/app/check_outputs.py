#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""End-to-end check of a nacre output directory: every file the README promises exists and is
consistent (CSV columns, XDMF references resolve to HDF5 datasets of the stated shapes, charts
are PNGs, summary.json parses, the checkpoint holds one pose per brick)."""
import os
import sys
import xml.etree.ElementTree as ET

import h5py

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
from check_xdmf import check_xdmf  # noqa: E402
from nacre import read_json, read_rows  # noqa: E402  (the reader of nacre's outputs, python/nacre)

out = sys.argv[1]
fail = []


def check(cond, msg):
    if not cond:
        fail.append(msg)


rows = read_rows(os.path.join(out, "steps.csv"))
check(len(rows) >= 3, "steps.csv has fewer than 3 rows")
for col in ["step", "displacement", "energy", "reaction", "cycles", "acceptance", "ruptured", "converged",
            "residual", "polish_iterations"]:
    check(col in rows[0], f"steps.csv lacks column {col}")
check([int(r["step"]) for r in rows] == list(range(1, len(rows) + 1)), "steps are not 1..n")
# the crack reading (docs/fracture.md): joints connected to the notch, a part of the ruptured ones
for r in rows:
    n, ext, path = int(r["crack_interfaces"]), float(r["crack_extension"]), float(r["crack_path_length"])
    check(0 <= n <= int(r["ruptured"]) and n == int(r["crack_bed"]) + int(r["crack_head"]),
          f"step {r['step']}: crack joints {n} vs ruptured {r['ruptured']}, bed + head")
    check(ext >= 0 and path >= ext * (1 - 1e-9), f"step {r['step']}: crack path {path} shorter than extension {ext}")
check(all(float(a["displacement"]) < float(b["displacement"]) for a, b in zip(rows, rows[1:])),
      "displacement does not increase")
summary = read_json(os.path.join(out, "summary.json"))
check(summary["steps"] == len(rows), "summary.json steps != rows")
check(summary["crack"]["interfaces"] == int(rows[-1]["crack_interfaces"]), "summary.json crack != the last row's")
if summary.get("convergence") == "residual":  # converged means the residual says so
    tol = summary["residual_tolerance"]
    check(all(float(r["residual"]) < tol and r["converged"] == "1" for r in rows), "a step above the residual tolerance")
    # the CSV holds 10 significant digits, summary.json every digit
    mx = max(float(r["residual"]) for r in rows)
    check(abs(summary["max_step_residual"] - mx) <= 1e-9 * abs(mx), "max_step_residual != max of the column")
n = summary["bricks"]
root = ET.parse(os.path.join(out, "nacre.xdmf")).getroot()
fail += check_xdmf(os.path.join(out, "nacre.xdmf"))  # Xdmf3: every topology has its connectivity
items = root.iter("DataItem")
count = 0
for it in items:
    fname, path = it.text.strip().split(":")
    dims = [int(d) for d in it.attrib["Dimensions"].split()]
    with h5py.File(os.path.join(out, fname), "r") as h:
        check(path in h, f"{fname}:{path} missing")
        if path in h:
            shape = list(h[path].shape)
            check(shape == dims, f"{fname}:{path} has shape {shape}, XDMF says {dims}")
    count += 1
check(count > 0, "no DataItem in nacre.xdmf")
with h5py.File(os.path.join(out, "mesh.h5"), "r") as m:
    check(m["/bricks/area"].shape[0] == n, "mesh.h5 brick count != summary")
with h5py.File(os.path.join(out, "checkpoint.h5"), "r") as c:
    check(c["/arrays/pose"].shape == (3 * n,), "checkpoint pose shape")
    check(int(c.attrs["step"]) == len(rows), "checkpoint is not at the last step")
    check(c.attrs["format"] in (b"nacre-checkpoint-1", "nacre-checkpoint-1"), "checkpoint format tag")
for png in ["energy_force.png", "crack.png"]:
    p = os.path.join(out, png)
    check(os.path.exists(p) and open(p, "rb").read(8) == b"\x89PNG\r\n\x1a\n", f"{png} missing or not a PNG")
check(not [f for f in os.listdir(out) if ".tmp" in f], "temporary files left behind")
if fail:
    print("\n".join("FAIL: " + f for f in fail))
    sys.exit(1)
print(f"outputs of {out}: {len(rows)} steps, {count} XDMF data items, all consistent")
