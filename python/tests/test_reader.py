#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Tests of the reader (nacre.Run, nacre.Sweep, nacre.Bench, python3 -m nacre) on the outputs of
the nacre program: a Monte Carlo run (tests/app/tiny.toml), a dynamic run
(tests/app/tiny_dynamic.toml), a sweep (2 runs of tiny.toml), a tiny bench, and the R-curve of
the default deck (inputs/default.toml, a crack that grows) against nacre.analysis, the
reference implementation. Each case takes seconds; the decks run with charts = false.

    test_reader.py [NACRE_BIN [SCRATCH_DIR]] [unittest options]
    (or NACRE_BIN / NACRE_TEST_DIR in the environment; default build/openmp/src/nacre and a
    temporary directory)

r_curve.csv and sweep.csv are the program's (an older program did not write them): where they
are present they are checked against the reference; where absent the reader's None is checked
and the reference's file is written and read back.
"""
import csv
import io
import math
import os
import shutil
import subprocess
import sys
import tempfile
import unittest
from contextlib import redirect_stderr

import numpy as np

import support
import nacre
import nacre.__main__
from nacre import analysis

EXE = SCRATCH = None


def setUpModule():
    global EXE, SCRATCH
    if EXE is None:
        EXE, arg = support.take_args([sys.argv[0]])
        SCRATCH = support.Scratch(arg, "python_reader")
    SCRATCH.decks = os.path.join(SCRATCH.path, "decks")
    os.makedirs(SCRATCH.decks, exist_ok=True)


def tearDownModule():
    SCRATCH.close()


def deck(rel):
    return support.deck_without_charts(os.path.join(support.REPO, rel), SCRATCH.decks)


def out(name):
    return os.path.join(SCRATCH.path, name)


def cells(path):
    """header, columns of raw strings of a CSV file, read with the csv module alone."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header, body = rows[0], [r for r in rows[1:] if r]
    return header, {k: [r[i] for r in body] for i, k in enumerate(header)}


def is_number(s):
    try:
        float(s)
        return True
    except ValueError:
        return s.strip() == ""


class TableChecks:
    """Checks of a typed table against its file."""

    def check_table(self, t, path):
        self.assertIsNotNone(t, path)
        n = support.csv_line_count(path)
        header, raw = cells(path)
        self.assertEqual(list(t), header, f"{path}: columns in the file's order")
        for k, v in t.items():
            self.assertIsInstance(v, np.ndarray, k)
            self.assertEqual(len(v), n, f"{path}: column {k} has {len(v)} values, the file {n} rows")
            if not raw[k]:  # a header without rows: empty float arrays
                self.assertEqual(v.dtype, np.float64, f"{path}: column {k} of no rows is {v.dtype}")
            elif all(is_number(s) for s in raw[k]) and any(s.strip() for s in raw[k]):
                self.assertEqual(v.dtype, np.float64, f"{path}: numeric column {k} is {v.dtype}")
                want = np.array([float(s) if s.strip() else math.nan for s in raw[k]])
                np.testing.assert_array_equal(v, want, err_msg=f"{path}: column {k}")
            else:
                self.assertEqual(v.dtype.kind, "U", f"{path}: text column {k} is {v.dtype}")
                self.assertTrue(all(isinstance(x, str) for x in v), k)
                self.assertEqual(list(v), raw[k], f"{path}: column {k}")
        return n


class RunChecks(TableChecks):
    DECK = OUT = SOLVER = TABLE = None
    TEXT = ()

    @classmethod
    def setUpClass(cls):
        cls.dir = out(cls.OUT)
        support.run([EXE, deck(cls.DECK), "-o", cls.dir, "-q"])
        cls.run_ = nacre.Run(cls.dir)

    def test_solver_and_table_name(self):
        self.assertEqual(self.run_.solver, self.SOLVER)
        self.assertEqual(self.run_.table_name, self.TABLE)
        self.assertEqual(self.run_.summary["solver"], self.SOLVER)

    def test_table_types_and_lengths(self):
        t = self.run_.table()
        n = self.check_table(t, os.path.join(self.dir, self.TABLE))
        self.assertGreaterEqual(n, 2)
        for k in self.TEXT:
            self.assertEqual(t[k].dtype.kind, "U", k)
            self.assertIsInstance(t[k][0], str)
        for k in ("step", "displacement", "reaction", "ruptured", "crack_extension", "fracture_energy"):
            self.assertEqual(t[k].dtype, np.float64, k)
        self.assertTrue(np.all(np.diff(t["step"]) > 0), "steps increase")

    def test_rows_are_the_table_as_strings(self):
        rows, t = self.run_.rows(), self.run_.table()
        self.assertEqual(len(rows), len(t["step"]))
        self.assertEqual(list(rows[0]), list(t))
        self.assertTrue(all(isinstance(v, str) for v in rows[-1].values()))
        self.assertEqual(float(rows[-1]["displacement"]), t["displacement"][-1])

    def test_summary_fields(self):
        s = self.run_.summary
        for k in ("solver", "bricks", "interfaces", "steps", "crack", "seconds", "nacre"):
            self.assertIn(k, s)
        for k in ("extension", "path_length", "deflection", "fracture_energy", "tip_x", "notch_tip_x"):
            self.assertIn(k, s["crack"])
        self.assertEqual(self.run_.crack, s["crack"])
        r = self.run_.toughening_ratio
        self.assertTrue(r is None or isinstance(r, float))

    def test_dumps_and_mesh(self):
        run, s = self.run_, self.run_.summary
        steps = run.steps()
        self.assertGreaterEqual(len(steps), 2)
        self.assertEqual(steps, sorted(steps))
        last = run.dump()
        self.assertEqual(int(last.attrs["step"]), steps[-1])
        self.assertIn("displacement", last.attrs)
        first = run.dump(step=steps[0])
        self.assertEqual(int(first.attrs["step"]), steps[0])
        self.assertIsNone(run.dump(step=steps[-1] + 1))
        self.assertEqual(int(os.path.basename(run.dump_path())[5:-3]), steps[-1])
        m = run.mesh()
        nb, ni = s["bricks"], s["interfaces"]
        self.assertEqual(m["/bricks/area"].shape, (nb,))
        self.assertEqual(m["/interfaces/length"].shape, (ni,))
        self.assertEqual(m["/interfaces/reference_points"].shape, (2 * ni, 2))
        for d in (first, last):
            self.assertEqual(d["/interfaces/state"].shape, (ni,))
            self.assertEqual(d["/interfaces/crack"].shape, (ni,))
            self.assertEqual(d["/interfaces/points"].shape, (2 * ni, 2))
        self.check_family_shapes(m, last, nb)

    def test_r_curve(self):
        """The program's r_curve.csv against the reference where present; absent: None."""
        check_r_curve(self, self.run_)

    def test_log(self):
        """log.txt: the run's log, from its start line to its results line."""
        log = self.run_.log()
        self.assertIsNotNone(log)
        self.assertTrue(log.startswith("nacre: "), log[:200])
        self.assertIn("bricks", log.splitlines()[0])

    def test_main_describes_it(self):
        p = subprocess.run([sys.executable, "-m", "nacre", self.dir], env=support.env(), capture_output=True, text=True)
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertIn(f"solver {self.SOLVER}", p.stdout)
        self.assertIn(f"{len(self.run_.table()['step'])} rows of {self.TABLE}", p.stdout)
        self.assertIn("mesh.h5:", p.stdout)
        self.assertIsInstance(nacre.read(self.dir), nacre.Run)


def check_r_curve(case, run):
    got = run.r_curve()
    ref = analysis.run_r_curve(run)
    path = run.path("r_curve.csv")
    if got is None:
        case.assertFalse(os.path.exists(path))
        if ref is None:
            return
        # an older program: the reference's file, read back
        support.ensure_r_curve(run.directory)
        got = run.r_curve()
        try:
            case.check_table(got, path)
        finally:
            os.remove(path)
    else:
        case.check_table(got, path)
        case.assertIsNotNone(ref, "r_curve.csv for a run without a crack reading")
    case.assertEqual(list(got), ["extension", "fracture_energy", "G_R", "toughening"])
    pts, ratio = ref
    case.assertEqual(len(got["extension"]), len(pts))
    for k in got:
        np.testing.assert_allclose(got[k], [p[k] for p in pts], rtol=1e-12, atol=0, err_msg=k)
    if "toughening_ratio" in run.crack:  # the program's ratio (null: fewer than 2 points)
        if math.isnan(ratio):
            case.assertIsNone(run.toughening_ratio)
        else:
            case.assertAlmostEqual(run.toughening_ratio, ratio, delta=1e-12 * abs(ratio))
    return got


class MonteCarloRun(RunChecks, unittest.TestCase):
    DECK, OUT, SOLVER, TABLE, TEXT = "tests/app/tiny.toml", "mc", "mc", "steps.csv", ("method",)

    def check_family_shapes(self, m, d, nb):
        self.assertEqual(d["/bricks/energy"].shape, (nb,))
        self.assertEqual(d["/bricks/points"].shape, m["/bricks/reference_points"].shape)
        topo = m["/bricks/topology"]
        count, i = 0, 0
        while i < len(topo):  # the mixed topology walks to exactly one polygon per brick
            i += 2 + topo[i + 1]
            count += 1
        self.assertEqual((i, count), (len(topo), nb))
        self.assertEqual(self.run_.summary["steps"], len(self.run_.table()["step"]))


class DynamicRun(RunChecks, unittest.TestCase):
    DECK, OUT, SOLVER, TABLE = "tests/app/tiny_dynamic.toml", "dyn", "dynamics", "series.csv"

    def check_family_shapes(self, m, d, nb):
        nn = m["/nodes/reference"].shape[0]
        self.assertEqual(d["/nodes/displacement"].shape[0], nn)
        self.assertEqual(d["/nodes/points"].shape, (nn, 2))
        self.assertEqual(d["/bricks/syy"].shape, (nb,))
        conn = m["/triangles/connectivity"]
        self.assertEqual(conn.shape[1], 3)
        self.assertTrue(conn.min() >= 0 and conn.max() < nn)
        self.assertEqual(m["/triangles/brick"].shape, (conn.shape[0],))
        for k in ("status", "method", "dt", "time"):
            self.assertIn(k, self.run_.summary)


class GrowingCrack(TableChecks, unittest.TestCase):
    """The default deck: a crack that grows, so the R-curve has points and a toughening ratio."""

    @classmethod
    def setUpClass(cls):
        cls.dir = out("default")
        support.run([EXE, deck("inputs/default.toml"), "-o", cls.dir, "-q"])
        cls.run_ = nacre.Run(cls.dir)

    def test_r_curve_against_reference(self):
        got = check_r_curve(self, self.run_)
        self.assertGreaterEqual(len(got["extension"]), 2)
        self.assertTrue(np.all(np.diff(got["extension"]) > 0))

    def test_text_column(self):
        """The bug this package fixed: steps.csv's method column (newton, ...) read as text."""
        t = self.run_.table()
        self.assertEqual(t["method"].dtype.kind, "U")
        self.assertTrue(all(isinstance(m, str) and m for m in t["method"]))
        self.check_table(t, self.run_.path("steps.csv"))


class SweepDirectory(TableChecks, unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = out("sweep")
        support.run([EXE, "sweep", deck("tests/app/tiny.toml"), "--set", "mortar.k=100,200", "-o", cls.dir, "-q"])
        cls.sweep = nacre.Sweep(cls.dir)

    def test_lists_the_runs_with_their_values(self):
        sw = self.sweep
        self.assertEqual(sw.keys, ["mortar.k"])
        self.assertTrue(sw.deck.endswith("tiny.toml"))
        self.assertEqual(len(sw), 2)
        self.assertEqual(sw.names(), ["k=100", "k=200"])
        self.assertEqual([e.values for e in sw.runs], [{"mortar.k": "100"}, {"mortar.k": "200"}])
        self.assertEqual([e.exit for e in sw], [0, 0])
        for e in sw.runs:
            self.assertEqual(os.path.realpath(e.directory), os.path.realpath(os.path.join(self.dir, e.name)))
            run = e.run()
            self.assertIsInstance(run, nacre.Run)
            self.assertEqual(run.solver, "mc")
            self.check_table(run.table(), run.path("steps.csv"))
        self.assertEqual(sw.run("k=200").directory, sw.runs[1].directory)
        with self.assertRaises(KeyError):
            sw.run("k=300")
        self.assertIsInstance(nacre.read(self.dir), nacre.Sweep)

    def test_a_moved_sweep_reads_its_own_runs(self):
        moved = out("sweep_moved")
        shutil.rmtree(moved, ignore_errors=True)
        shutil.copytree(self.dir, moved)
        sw = nacre.Sweep(moved)
        self.assertEqual([os.path.dirname(e.directory) for e in sw.runs], [moved, moved])
        self.assertTrue(all(e.has_outputs() for e in sw.runs))
        shutil.rmtree(moved)

    def test_sweep_csv(self):
        """The program's sweep.csv against the reference where present; absent: None, and the
        reference's file reads back."""
        path = os.path.join(self.dir, "sweep.csv")
        t = self.sweep.table()
        wrote = False
        if t is None:
            self.assertFalse(os.path.exists(path))
            wrote = support.ensure_sweep_csv(self.dir)
            t = self.sweep.table()
        try:
            self.check_table(t, path)
            ref, columns = analysis.sweep_rows(self.dir)
            self.assertEqual(list(t), columns)
            self.assertEqual(list(t["name"]), ["k=100", "k=200"])
            self.assertEqual(t["name"].dtype.kind, "U")
            self.assertEqual(t["status"].dtype.kind, "U")
            np.testing.assert_array_equal(t["mortar.k"], [100.0, 200.0])
            for k in columns:
                want = [r.get(k) for r in ref]
                if t[k].dtype.kind == "f":
                    np.testing.assert_allclose(t[k], [math.nan if w is None else float(w) for w in want],
                                               rtol=1e-12, equal_nan=True, err_msg=k)
                else:
                    self.assertEqual(list(t[k]), ["" if w is None else str(w) for w in want], k)
        finally:
            if wrote:
                os.remove(path)

    def test_main_describes_it(self):
        p = subprocess.run([sys.executable, "-m", "nacre", self.dir], env=support.env(), capture_output=True, text=True)
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertIn("sweep of", p.stdout)
        self.assertIn("k=100: mortar.k=100; exit 0", p.stdout)
        self.assertIn("k=200: mortar.k=200; exit 0", p.stdout)


class BenchDirectory(TableChecks, unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = out("bench")
        support.run([EXE, "bench", deck("tests/app/tiny.toml"), "--steps", "1", "--repeat", "1",
                     "-o", cls.dir])
        cls.bench = nacre.Bench(cls.dir)

    def test_lists_the_backends(self):
        b = self.bench
        self.assertGreaterEqual(len(b.backends), 1)
        self.assertEqual(b.backends, list(b.json["backends"]))
        # the reference of the agreement: Serial where the build has it, else the first backend
        self.assertEqual(b.json["reference_backend"], "serial" if "serial" in b.backends else b.backends[0])
        self.assertEqual(b.solver, b.json["solver"])
        self.assertEqual(b.unit, b.json["unit"])
        for name in b.backends:
            e = b.backend(name)
            self.assertGreater(e["seconds_per_unit"], 0)
            self.assertIn("phases", e)
        self.assertIsInstance(nacre.read(self.dir), nacre.Bench)

    def test_table(self):
        t = self.bench.table()
        self.check_table(t, os.path.join(self.dir, "bench.csv"))
        for k in ("backend", "phase"):
            self.assertEqual(t[k].dtype.kind, "U", k)
        for k in ("repeat", "seconds", "share"):
            self.assertEqual(t[k].dtype, np.float64, k)
        self.assertEqual(set(t["backend"]), set(self.bench.backends))
        self.assertIn("total", set(t["phase"]))

    def test_main_describes_it(self):
        p = subprocess.run([sys.executable, "-m", "nacre", self.dir], env=support.env(), capture_output=True, text=True)
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertIn("bench of", p.stdout)
        for name in self.bench.backends:
            self.assertIn(f"  {name}: ", p.stdout)


class CsvTyping(unittest.TestCase):
    """The table reader on small files (no program needed)."""

    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="nacre_csv_")

    def tearDown(self):
        shutil.rmtree(self.tmp)

    def write(self, text):
        p = os.path.join(self.tmp, "t.csv")
        with open(p, "w") as f:
            f.write(text)
        return p

    def test_numbers_text_and_empty_cells(self):
        t = nacre.read_csv(self.write("a,b,c,d\n1,newton,,x\n2.5,fire,3,\nnan,newton,inf,\n"))
        self.assertEqual(t["a"].dtype, np.float64)
        self.assertTrue(math.isnan(t["a"][2]))
        self.assertEqual(list(t["b"]), ["newton", "fire", "newton"])
        self.assertEqual(t["b"].dtype.kind, "U")
        self.assertTrue(math.isnan(t["c"][0]) and t["c"][1] == 3 and math.isinf(t["c"][2]))
        self.assertEqual(list(t["d"]), ["x", "", ""])

    def test_header_only_missing_and_empty(self):
        t = nacre.read_csv(self.write("a,b\n"))
        self.assertEqual({k: len(v) for k, v in t.items()}, {"a": 0, "b": 0})
        self.assertIsNone(nacre.read_csv(self.write("")))
        self.assertIsNone(nacre.read_csv(os.path.join(self.tmp, "none.csv")))
        self.assertEqual(nacre.read_rows(os.path.join(self.tmp, "none.csv")), [])

    def test_a_short_row_is_an_error(self):
        with self.assertRaisesRegex(ValueError, r"t\.csv:3: 1 fields, the header has 2"):
            nacre.read_csv(self.write("a,b\n1,2\n3\n"))

    def test_not_a_directory(self):
        with self.assertRaises(FileNotFoundError):
            nacre.Run(os.path.join(self.tmp, "nothing"))
        with self.assertRaises(FileNotFoundError):
            nacre.Sweep(self.tmp)
        with self.assertRaises(FileNotFoundError):
            nacre.Bench(self.tmp)
        buf = io.StringIO()
        with redirect_stderr(buf):
            self.assertEqual(nacre.__main__.main([]), 2)


if __name__ == "__main__":
    EXE, arg = support.take_args(sys.argv)
    SCRATCH = support.Scratch(arg, "python_reader")
    unittest.main()
