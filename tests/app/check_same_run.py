#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Two nacre output directories hold the same run, bit for bit: every HDF5 dataset and attribute
(checkpoint, dumps, mesh), every CSV value and every summary.json entry, except what measures the
machine (wall and CPU seconds, phase times, threads, ranks, placement) and the chart images. Used for a run
spread over MPI ranks against the one-process run, and for a restart on another rank count.

usage: check_same_run.py A B [--steps-from K]   (--steps-from: B restarted at step K: its dumps start there)
"""
import os
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
from nacre import read_json, read_rows  # noqa: E402  (the reader of nacre's outputs, python/nacre)

argv = sys.argv[1:]
steps_from = 0
if "--steps-from" in argv:  # (the table: a restart into another directory copies the earlier rows)
    k = argv.index("--steps-from")
    steps_from = int(argv[k + 1])
    del argv[k:k + 2]
a, b = argv
fail = []
MACHINE = {"seconds", "cpu_seconds", "phase_seconds", "threads", "ranks", "halo_messages",
           "seconds_per_step", "device_bytes",  # (dynamics: device_bytes is one rank's memory)
           "halo_bytes_per_exchange", "halo_exchanges_per_step", "placement"}


def same_csv(name, drop=("seconds",)):
    ra, rb = read_rows(os.path.join(a, name)), read_rows(os.path.join(b, name))
    if len(ra) != len(rb):
        fail.append(f"{name}: {len(ra)} rows against {len(rb)}")
        return
    if ra and set(ra[0]) != set(rb[0]):
        fail.append(f"{name}: columns {sorted(set(ra[0]) ^ set(rb[0]))} in one only")
    for i, (x, y) in enumerate(zip(ra, rb)):
        for k in x:
            if k not in drop and x[k] != y.get(k):
                fail.append(f"{name} row {i + 1} {k}: {x[k]} against {y.get(k)}")


def same_bits(x, y):
    """Bit for bit: -0.0 differs from 0.0, a NaN equals the same NaN."""
    x, y = np.asarray(x), np.asarray(y)
    if x.dtype != y.dtype or x.shape != y.shape:
        return False
    if x.dtype.kind in "OSU":  # strings
        return bool(np.all(x == y))
    return x.tobytes() == y.tobytes()


def same_h5(name):
    pa, pb = os.path.join(a, name), os.path.join(b, name)
    if not os.path.exists(pb):
        fail.append(f"{name} missing in {b}")
        return
    with h5py.File(pa, "r") as fa, h5py.File(pb, "r") as fb:
        seen = []
        fa.visit(seen.append)
        seen_b = []
        fb.visit(seen_b.append)
        if sorted(seen) != sorted(seen_b):
            fail.append(f"{name}: objects {sorted(set(seen) ^ set(seen_b))} differ")
        for obj in ["/"] + seen:
            if obj not in fb:
                continue
            xa, xb = fa[obj], fb[obj]
            if set(xa.attrs) != set(xb.attrs):
                fail.append(f"{name}:{obj}: attributes {sorted(set(xa.attrs) ^ set(xb.attrs))} in one only")
            for k in xa.attrs:
                va, vb = xa.attrs[k], xb.attrs.get(k)
                if k in ("backend",) or vb is None:
                    continue
                if not same_bits(va, vb):
                    fail.append(f"{name}:{obj} attribute {k}: {va} against {vb}")
            if isinstance(xa, h5py.Dataset):
                da, db = xa[()], xb[()]
                if not same_bits(da, db):
                    diff = "shapes differ" if np.shape(da) != np.shape(db) else \
                        f"largest difference {np.max(np.abs(np.asarray(da, float) - np.asarray(db, float)))}"
                    fail.append(f"{name}:{obj}: {diff}")


table = "steps.csv" if os.path.exists(os.path.join(a, "steps.csv")) else "series.csv"  # Monte Carlo / dynamics
same_csv(table)
if os.path.exists(os.path.join(a, "r_curve.csv")):
    same_csv("r_curve.csv", drop=())
sa, sb = read_json(os.path.join(a, "summary.json")), read_json(os.path.join(b, "summary.json"))
for k in sorted(set(sa) | set(sb)):
    if k not in MACHINE and sa.get(k) != sb.get(k):
        fail.append(f"summary.json {k}: {sa.get(k)} against {sb.get(k)}")
names = sorted(n for n in os.listdir(a) if n.endswith(".h5"))
names_b = sorted(n for n in os.listdir(b) if n.endswith(".h5"))
if steps_from:  # a restarted run's dumps start where it restarted
    names = [n for n in names if not n.startswith("dump_") or int(n[5:-3]) >= steps_from]
if steps_from:
    names_b = [n for n in names_b if not n.startswith("dump_") or int(n[5:-3]) >= steps_from]
if names != names_b:
    fail.append(f"HDF5 files {sorted(set(names) ^ set(names_b))} in one only")
for n in names:
    same_h5(n)
if len(names) < 3:
    fail.append(f"only {names} to compare")
if fail:
    print(f"check_same_run: {a} and {b} differ:\n  " + "\n  ".join(fail[:40]))
    sys.exit(1)
print(f"check_same_run: {a} and {b}: the same run ({len(names)} HDF5 files, {table}, summary.json)")
