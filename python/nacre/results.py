# SPDX-License-Identifier: BSD-3-Clause
"""The reader of nacre's output directories (numpy; h5py only where an HDF5 file is read).

    Run(dir)     a run of either solver family: summary.json, steps.csv (Monte Carlo) or
                 series.csv (dynamics), r_curve.csv, mesh.h5, dump_NNNNN.h5
    Sweep(dir)   a `nacre sweep` directory: sweep.json (its runs, their values and exit codes),
                 sweep.csv (one row per run) and each run as a Run
    Bench(dir)   a `nacre bench` directory: bench.json (per backend) and bench.csv (per phase)
    read(dir)    whichever of the three the directory holds

Tables are {column: numpy array}: a column whose every cell is a number (an empty cell: NaN) is
a float array, any other column (steps.csv's `method`, sweep.csv's `name`) an array of str.
"""
import csv
import json
import os
import re

import numpy as np

_DUMP = re.compile(r"^dump_(\d+)\.h5$")


# ---- files ---------------------------------------------------------------------------------------

def _column(values):
    """One CSV column as a float array (every cell a number or empty: NaN) or else an array of str."""
    if not values:
        return np.array([], dtype=float)
    try:
        return np.asarray(values, dtype=str).astype(np.float64)
    except ValueError:
        pass
    out = np.empty(len(values))
    for i, v in enumerate(values):
        if v.strip() == "":
            out[i] = np.nan
            continue
        try:
            out[i] = float(v)
        except ValueError:
            return np.asarray(values, dtype=str)
    if all(v.strip() == "" for v in values):  # no number in it: text (empty cells)
        return np.asarray(values, dtype=str)
    return out


def _read_rows(path):
    """(header, rows as lists of str) of a CSV file; a row whose field count differs from the
    header's is an error (file and line named)."""
    with open(path, newline="") as f:
        r = csv.reader(f)
        header = next(r, None)
        if header is None:
            return None, []
        rows = []
        for row in r:
            if not row:
                continue
            if len(row) != len(header):
                raise ValueError(f"{path}:{r.line_num}: {len(row)} fields, the header has {len(header)}")
            rows.append(row)
    return header, rows


def read_csv(path):
    """A CSV table as {column: numpy array} in the file's column order: numeric columns float
    (empty cells NaN), text columns str. None when the file is missing or empty; a header
    without rows gives empty arrays."""
    if not os.path.exists(path):
        return None
    header, rows = _read_rows(path)
    if header is None:
        return None
    return {k: _column([row[i] for row in rows]) for i, k in enumerate(header)}


def read_rows(path):
    """A CSV table as a list of dicts of strings (as csv.DictReader gives them); [] when missing."""
    if not os.path.exists(path):
        return []
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def read_json(path):
    """A JSON file as a dict; {} when it is missing."""
    if not os.path.exists(path):
        return {}
    with open(path) as f:
        return json.load(f)


def _h5py():
    try:
        import h5py
    except ImportError as e:
        raise ImportError("nacre: reading HDF5 files (mesh.h5, dumps) needs h5py "
                          "(pip install h5py, or the python3-h5py package)") from e
    return h5py


def _plain(v):
    """An HDF5 attribute as a Python value: numpy scalars as numbers, bytes as str."""
    if hasattr(v, "item") and getattr(v, "shape", None) == ():
        v = v.item()
    if isinstance(v, bytes):
        return v.decode("utf-8", "replace")
    return v


def read_h5(path):
    """Every dataset of an HDF5 file by its path ("/bricks/area"), and the root's attributes:
    (data, attrs)."""
    h5py = _h5py()
    out = {}
    with h5py.File(path, "r") as h:
        h.visititems(lambda name, obj: out.__setitem__("/" + name, obj[...]) if isinstance(obj, h5py.Dataset) else None)
        attrs = {k: _plain(v) for k, v in h.attrs.items()}
    return out, attrs


class Dump(dict):
    """The datasets of one dump by their HDF5 path, with its attributes (step, time,
    displacement, ...) in .attrs."""

    def __init__(self, data, attrs):
        super().__init__(data)
        self.attrs = attrs


# ---- a run ---------------------------------------------------------------------------------------

class Run:
    """A run directory written by nacre (either solver family).

    run.solver           "mc" or "dynamics"
    run.summary          summary.json as a dict ({} while the run has not written it)
    run.table()          steps.csv / series.csv as {column: array}; run.rows(): as dicts of str
    run.r_curve()        r_curve.csv as {column: array} (None where the run has none)
    run.toughening_ratio summary.json's crack.toughening_ratio (None: absent, or the crack grew at
                         fewer than 2 rows)
    run.log()            log.txt, the run's log, as text (None where the run has none)
    run.steps()          the steps that have dumps, ascending
    run.dump(step)       a dump's datasets with .attrs (None: the last dump)
    run.mesh()           mesh.h5's datasets (the static geometry)
    """

    def __init__(self, directory):
        if not os.path.isdir(directory):
            raise FileNotFoundError(f"no run directory {directory}")
        self.directory = directory
        self.summary = read_json(os.path.join(directory, "summary.json"))
        if self.summary.get("solver"):
            self.solver = self.summary["solver"]
        else:  # a run that has not finished yet: the table's name tells
            self.solver = "dynamics" if os.path.exists(os.path.join(directory, "series.csv")) else "mc"

    def __repr__(self):
        return f"Run({self.directory!r})"

    def path(self, name):
        return os.path.join(self.directory, name)

    @property
    def table_name(self):
        return "series.csv" if self.solver == "dynamics" else "steps.csv"

    def table(self):
        """steps.csv (Monte Carlo) or series.csv (dynamics) as {column: array}; None when missing."""
        return read_csv(self.path(self.table_name))

    def rows(self):
        """The same table as a list of dicts of strings (as csv.DictReader gives them)."""
        return read_rows(self.path(self.table_name))

    def r_curve(self):
        """r_curve.csv (extension, fracture_energy, G_R, toughening) as {column: array}; None
        when the run has none."""
        return read_csv(self.path("r_curve.csv"))

    def log(self):
        """log.txt (what the run printed) as text; None when the run has none."""
        try:
            with open(self.path("log.txt"), encoding="utf-8", errors="replace") as f:
                return f.read()
        except FileNotFoundError:
            return None

    @property
    def crack(self):
        """summary.json's crack reading ({} when there is none)."""
        return self.summary.get("crack") or {}

    @property
    def toughening_ratio(self):
        """The R-curve's toughening ratio (summary.json crack.toughening_ratio); None when absent
        or null (the crack grew at fewer than 2 rows)."""
        v = self.crack.get("toughening_ratio")
        return None if v is None else float(v)

    def _dumps(self):
        return {int(m.group(1)): f for f in os.listdir(self.directory) if (m := _DUMP.match(f))}

    def steps(self):
        """Steps that have a dump, ascending."""
        return sorted(self._dumps())

    def dump_path(self, step=None):
        """The dump file of `step` (None: the last), or None when there is none."""
        files = self._dumps()
        if not files:
            return None
        s = max(files) if step is None else step
        return self.path(files[s]) if s in files else None

    def dump(self, step=None):
        """A dump's datasets {"/bricks/energy": array, ...} with .attrs; None when there is none."""
        p = self.dump_path(step)
        return Dump(*read_h5(p)) if p else None

    def mesh(self):
        """mesh.h5's datasets (the static geometry: bricks, interfaces, triangles of dynamic runs)."""
        p = self.path("mesh.h5")
        return read_h5(p)[0] if os.path.exists(p) else None


# ---- a sweep -------------------------------------------------------------------------------------

def _directory_json(directory, kind):
    """KIND.json of a sweep or bench directory as a dict; FileNotFoundError naming the directory
    when it has none."""
    p = os.path.join(directory, kind + ".json")
    if not os.path.exists(p):
        raise FileNotFoundError(f"{directory} holds no {kind}.json (not a {kind} directory)")
    return read_json(p)


class SweepEntry:
    """One run of a sweep as sweep.json lists it: name, values ({key: value as given to --set}),
    exit (its exit code), how ("run", "kept", ...), directory (where its files are)."""

    def __init__(self, entry, sweep_directory):
        self.name = entry["name"]
        self.values = dict(entry.get("values", {}))
        self.exit = entry.get("exit")
        self.how = entry.get("how")
        self.recorded_directory = entry.get("directory")
        # the directory as the sweep wrote it; a sweep moved (or read from elsewhere) holds its
        # runs beside sweep.json under their names
        d = self.recorded_directory
        beside = os.path.join(sweep_directory, self.name)
        self.directory = d if d and os.path.isdir(d) and not os.path.isdir(beside) else beside

    def __repr__(self):
        return f"SweepEntry({self.name!r}, values={self.values}, exit={self.exit})"

    def has_outputs(self):
        return os.path.exists(os.path.join(self.directory, "summary.json"))

    def run(self):
        """The run as a Run (None when its directory does not exist)."""
        return Run(self.directory) if os.path.isdir(self.directory) else None


class Sweep:
    """A `nacre sweep` directory.

    sweep.deck, sweep.keys   the deck and the swept keys (sweep.json)
    sweep.runs               [SweepEntry]: name, values, exit, how, directory; .run() a Run
    sweep.run(name)          the run of that name as a Run
    sweep.table()            sweep.csv as {column: array} (None where the sweep has none)
    """

    def __init__(self, directory):
        self.directory = directory
        self.json = _directory_json(directory, "sweep")
        self.deck = self.json.get("deck")
        self.keys = list(self.json.get("keys", []))
        self.runs = [SweepEntry(e, directory) for e in self.json.get("runs", [])]

    def __repr__(self):
        return f"Sweep({self.directory!r})"

    def __len__(self):
        return len(self.runs)

    def __iter__(self):
        return iter(self.runs)

    def names(self):
        return [e.name for e in self.runs]

    def entry(self, name):
        for e in self.runs:
            if e.name == name:
                return e
        raise KeyError(f"no run {name!r} in the sweep {self.directory} (runs: {', '.join(self.names())})")

    def run(self, name):
        return self.entry(name).run()

    def table(self):
        """sweep.csv (one row per run, in sweep.json's order) as {column: array}; None when missing."""
        return read_csv(os.path.join(self.directory, "sweep.csv"))

    def rows(self):
        """sweep.csv as a list of dicts of strings."""
        return read_rows(os.path.join(self.directory, "sweep.csv"))


# ---- a bench -------------------------------------------------------------------------------------

class Bench:
    """A `nacre bench` directory.

    bench.json               bench.json as a dict (deck, solver, bricks, unit, machine, ...)
    bench.backends           the backends timed, in bench.json's order (bench.json's reference_backend,
                             Serial where the build has it, is the one the others are compared with)
    bench.backend(name)      that backend's entry (seconds_per_unit, phases, agreement, ...)
    bench.table()            bench.csv (backend, repeat, phase, seconds, ...) as {column: array}
    """

    def __init__(self, directory):
        self.directory = directory
        self.json = _directory_json(directory, "bench")
        self.backends = list(self.json.get("backends", {}))

    def __repr__(self):
        return f"Bench({self.directory!r})"

    @property
    def solver(self):
        return self.json.get("solver")

    @property
    def unit(self):
        return self.json.get("unit")

    def backend(self, name):
        return self.json["backends"][name]

    def table(self):
        return read_csv(os.path.join(self.directory, "bench.csv"))

    def rows(self):
        return read_rows(os.path.join(self.directory, "bench.csv"))


def kind(directory):
    """"sweep", "bench" or "run": what a nacre output directory holds."""
    if os.path.exists(os.path.join(directory, "sweep.json")):
        return "sweep"
    if os.path.exists(os.path.join(directory, "bench.json")):
        return "bench"
    return "run"


def read(directory):
    """A Sweep, a Bench or a Run, by what the directory holds."""
    return {"sweep": Sweep, "bench": Bench, "run": Run}[kind(directory)](directory)
