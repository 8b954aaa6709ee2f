#!/usr/bin/env python3
"""Read a nacre run directory from Python (h5py + numpy): the one reader the chart scripts use
(nacre_plot.py, nacre_dyn_plot.py, nacre_sweep_plot.py). Both solver families, same layout
(docs/fracture.md "Reading results from Python"):

    from nacre_results import Run
    run = Run("out/default")
    run.solver                  # "mc" or "dynamics"
    run.summary["crack"]        # summary.json as a dict
    t = run.table()             # steps.csv / series.csv: {column: numpy array}
    m = run.mesh()              # mesh.h5: {"/bricks/area": array, ...} (every dataset)
    d = run.dump()              # the last dump: {"/interfaces/state": array, ...}, d.attrs
    d = run.dump(step=10)       # the dump of step 10
    run.steps()                 # the steps that have dumps, ascending
    run.r_curve()               # r_curve.csv: {column: numpy array} (None before the charts)

  nacre_results.py RUN_DIR      # prints what the directory holds
"""
import csv
import json
import os
import re
import sys

import numpy as np

_DUMP = re.compile(r"^dump_(\d+)\.h5$")


class Dump(dict):
    """The datasets of one dump by their HDF5 path, with its attributes (step, time,
    displacement, ...) in .attrs."""

    def __init__(self, data, attrs):
        super().__init__(data)
        self.attrs = attrs


def read_h5(path):
    """Every dataset of an HDF5 file by its path, and the root's attributes: (data, attrs)."""
    import h5py
    out = {}
    with h5py.File(path, "r") as h:
        h.visititems(lambda name, obj: out.__setitem__("/" + name, obj[...]) if isinstance(obj, h5py.Dataset) else None)
        attrs = {k: (v.item() if hasattr(v, "item") else v) for k, v in h.attrs.items()}
    return out, attrs


def read_csv(path):
    """A CSV table as {column: numpy array} (floats; None when the file is missing or empty)."""
    if not os.path.exists(path):
        return None
    rows = list(csv.DictReader(open(path)))
    if not rows:
        return None
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


class Run:
    """A run directory written by nacre (either solver family)."""

    def __init__(self, directory):
        self.directory = directory
        p = os.path.join(directory, "summary.json")
        self.summary = json.load(open(p)) if os.path.exists(p) else {}
        if self.summary.get("solver"):
            self.solver = self.summary["solver"]
        else:  # a run that has not finished yet: the table's name tells
            self.solver = "dynamics" if os.path.exists(os.path.join(directory, "series.csv")) else "mc"

    @property
    def table_name(self):
        return "series.csv" if self.solver == "dynamics" else "steps.csv"

    def table(self):
        """steps.csv (Monte Carlo) or series.csv (dynamics) as {column: array}."""
        return read_csv(os.path.join(self.directory, self.table_name))

    def rows(self):
        """The same table as a list of dicts of strings (as csv.DictReader gives them)."""
        p = os.path.join(self.directory, self.table_name)
        return list(csv.DictReader(open(p))) if os.path.exists(p) else []

    def r_curve(self):
        return read_csv(os.path.join(self.directory, "r_curve.csv"))

    def steps(self):
        """Steps that have a dump, ascending."""
        return sorted(int(m.group(1)) for f in os.listdir(self.directory) if (m := _DUMP.match(f)))

    def dump_path(self, step=None):
        """The dump file of `step` (None: the last), or None when there is none."""
        files = {int(m.group(1)): f for f in os.listdir(self.directory) if (m := _DUMP.match(f))}
        if not files:
            return None
        s = max(files) if step is None else step
        return os.path.join(self.directory, files[s]) if s in files else None

    def dump(self, step=None):
        """A dump's datasets {"/bricks/energy": array, ...} with .attrs; None when there is none."""
        p = self.dump_path(step)
        return Dump(*read_h5(p)) if p else None

    def mesh(self):
        """mesh.h5's datasets (the static geometry: bricks, interfaces, triangles of dynamic runs)."""
        p = os.path.join(self.directory, "mesh.h5")
        return read_h5(p)[0] if os.path.exists(p) else None


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    run = Run(sys.argv[1])
    t = run.table()
    print(f"{run.directory}: solver {run.solver}, status {run.summary.get('status', 'done' if run.summary else '?')}, "
          f"{0 if t is None else len(next(iter(t.values())))} rows of {run.table_name}, dumps at steps {run.steps()}")
    if t is not None:
        print("columns:", ", ".join(t))
    m = run.mesh()
    if m:
        print("mesh.h5:", ", ".join(f"{k} {v.shape}" for k, v in m.items()))
    d = run.dump()
    if d:
        print(f"last dump (attributes {d.attrs}):", ", ".join(f"{k} {v.shape}" for k, v in d.items()))
