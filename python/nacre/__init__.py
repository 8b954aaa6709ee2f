# SPDX-License-Identifier: BSD-3-Clause
"""nacre's outputs from Python: one reader for runs of both solver families, sweeps and benches
(numpy; h5py where an HDF5 file is read), and the charts the nacre program draws with it
(nacre.charts.mc, .dyn, .sweep, .bench). docs/fracture.md "Reading results from Python".

    import nacre
    run = nacre.Run("out/default")
    run.solver                  # "mc" or "dynamics"
    run.summary["crack"]        # summary.json as a dict
    t = run.table()             # steps.csv / series.csv: {column: numpy array} (text columns str)
    run.rows()                  # the same table as dicts of strings
    run.r_curve()               # r_curve.csv: {column: numpy array} (None where there is none)
    run.toughening_ratio        # summary.json crack.toughening_ratio (None: n/a)
    m = run.mesh()              # mesh.h5: {"/bricks/area": array, ...} (every dataset)
    d = run.dump()              # the last dump: {"/interfaces/state": array, ...}, d.attrs
    d = run.dump(step=10)       # the dump of step 10; run.steps(): the steps that have dumps
    sw = nacre.Sweep("out/default_sweep")   # sw.keys, sw.runs (name, values, exit), sw.table()
    b = nacre.Bench("out/bench")            # b.backends, b.backend("openmp"), b.table()
    nacre.read(directory)       # whichever of Run, Sweep, Bench the directory holds

    python3 -m nacre DIR        # prints what a directory holds
"""
from .results import Bench, Dump, Run, Sweep, SweepEntry, kind, read, read_csv, read_h5, read_json, read_rows

__version__ = "1.0.0"
__all__ = ["Run", "Sweep", "SweepEntry", "Bench", "Dump", "read", "kind", "read_csv", "read_rows", "read_json",
           "read_h5", "__version__"]
