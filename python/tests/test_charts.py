#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Tests of the chart modules (python3 -m nacre.charts.mc|dyn|sweep|bench DIR [--quiet]) on the
outputs of the nacre program (tiny decks, charts = false, so the modules run here alone):

- each writes its PNGs (energy_force.png, crack.png, r_curve.png; sweep.png; bench.png), real
  PNGs, and nothing else: no CSV (r_curve.csv and sweep.csv are the program's), no temporary;
- without r_curve.csv the mc / dyn modules skip r_curve.png with a one-line warning, exit 0;
  without sweep.csv the sweep module skips sweep.png the same way;
- without matplotlib every module prints `nacre: warning: matplotlib not found; charts skipped`
  on stderr, writes nothing and exits 0;
- a PNG write failing half-way (a full disk) leaves no PNG and no temporary, and fails.

Where the program does not write r_curve.csv / sweep.csv yet, the reference implementation
(nacre.analysis, through support.py) writes them first, as the program would.

    test_charts.py [NACRE_BIN [SCRATCH_DIR]] [unittest options]
"""
import os
import shutil
import subprocess
import sys
import unittest

import support

EXE = SCRATCH = None
PNG = b"\x89PNG\r\n\x1a\n"


def setUpModule():
    global EXE, SCRATCH
    if EXE is None:
        EXE, arg = support.take_args([sys.argv[0]])
        SCRATCH = support.Scratch(arg, "python_charts")
    decks = os.path.join(SCRATCH.path, "decks")
    os.makedirs(decks, exist_ok=True)
    tiny = support.deck_without_charts(os.path.join(support.REPO, "tests/app/tiny.toml"), decks)
    dyn = support.deck_without_charts(os.path.join(support.REPO, "tests/app/tiny_dynamic.toml"), decks)
    SCRATCH.sources = {
        "mc": [EXE, tiny, "-o", "{}", "-q"],
        "dyn": [EXE, dyn, "-o", "{}", "-q"],
        "sweep": [EXE, "sweep", tiny, "--set", "mortar.k=100,200", "-o", "{}", "-q"],
        "bench": [EXE, "bench", tiny, "--steps", "1", "--repeat", "1", "-o", "{}"],
    }
    SCRATCH.made = {}


def tearDownModule():
    SCRATCH.close()


def source(kind):
    """The program's output directory of that kind (made once, copied by each test)."""
    if kind not in SCRATCH.made:
        d = os.path.join(SCRATCH.path, "source_" + kind)
        support.run([a.replace("{}", d) for a in SCRATCH.sources[kind]])
        for name in ("r_curve.png", "energy_force.png", "crack.png", "sweep.png", "bench.png"):
            if os.path.exists(os.path.join(d, name)):
                os.remove(os.path.join(d, name))  # (a bench draws its own chart)
        if kind in ("mc", "dyn"):
            support.ensure_r_curve(d)
        if kind == "sweep":
            support.ensure_sweep_csv(d)
        SCRATCH.made[kind] = d
    return SCRATCH.made[kind]


def copy(kind, name):
    d = os.path.join(SCRATCH.path, name)
    shutil.rmtree(d, ignore_errors=True)
    shutil.copytree(source(kind), d)
    return d


def listing(d):
    return {os.path.relpath(os.path.join(r, f), d) for r, _, fs in os.walk(d) for f in fs}


def chart(module, d, *args, pre=None):
    """python3 -m nacre.charts.MODULE D ARGS (pre: Python run first in the same process)."""
    if pre is None:
        cmd = [sys.executable, "-m", "nacre.charts." + module, d, *args]
    else:
        cmd = [sys.executable, "-c", pre + "\nimport runpy, sys\nsys.argv = sys.argv[1:]\n"
               f"runpy.run_module('nacre.charts.{module}', run_name='__main__', alter_sys=True)",
               "nacre.charts." + module, d, *args]
    return subprocess.run(cmd, env=support.env(), capture_output=True, text=True)


class Charts(unittest.TestCase):
    def draws(self, kind, module, pngs, *args):
        d = copy(kind, f"{module}_draws")
        before = listing(d)
        p = chart(module, d, *args)
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertEqual(listing(d) - before, set(pngs), "the module writes its charts and nothing else")
        self.assertEqual(before - listing(d), set())
        for name in pngs:
            with open(os.path.join(d, name), "rb") as f:
                self.assertEqual(f.read(8), PNG, name)
        return p, d

    def test_mc(self):
        p, _ = self.draws("mc", "mc", ["energy_force.png", "crack.png", "r_curve.png"])
        self.assertIn("toughening ratio", p.stdout)

    def test_dyn(self):
        """(the rasterised crack picture, --raster: tests/app/check_dyn_plot.py)"""
        q, _ = self.draws("dyn", "dyn", ["energy_force.png", "crack.png", "r_curve.png"], "--magnify", "20", "--quiet")
        self.assertEqual(q.stdout, "")

    def test_sweep(self):
        p, _ = self.draws("sweep", "sweep", ["sweep.png"])
        self.assertIn("k=100: peak", p.stdout)

    def test_bench(self):
        self.draws("bench", "bench", ["bench.png"], "--quiet")

    def test_no_r_curve_csv(self):
        for kind in ("mc", "dyn"):
            d = copy(kind, f"{kind}_no_r_curve")
            os.remove(os.path.join(d, "r_curve.csv"))
            p = chart(kind, d, "--quiet")
            self.assertEqual(p.returncode, 0, p.stderr)
            warnings = [line for line in p.stderr.splitlines() if "r_curve" in line]
            self.assertEqual(len(warnings), 1, p.stderr)
            self.assertTrue(warnings[0].startswith("nacre: warning: ") and "r_curve.png skipped" in warnings[0])
            self.assertFalse(os.path.exists(os.path.join(d, "r_curve.png")))
            self.assertTrue(os.path.exists(os.path.join(d, "energy_force.png")))
            self.assertTrue(os.path.exists(os.path.join(d, "crack.png")))
            self.assertFalse(os.path.exists(os.path.join(d, "r_curve.csv")), "a chart module wrote r_curve.csv")

    def test_no_sweep_csv(self):
        d = copy("sweep", "sweep_no_csv")
        os.remove(os.path.join(d, "sweep.csv"))
        p = chart("sweep", d, "--quiet")
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertEqual(len(p.stderr.strip().splitlines()), 1, p.stderr)
        self.assertIn("sweep.png skipped", p.stderr)
        self.assertFalse(os.path.exists(os.path.join(d, "sweep.csv")))
        self.assertFalse(os.path.exists(os.path.join(d, "sweep.png")))

    def test_without_matplotlib(self):
        block = "import sys\nsys.modules['matplotlib'] = None  # import matplotlib now raises ImportError"
        for kind, module in (("mc", "mc"), ("dyn", "dyn"), ("sweep", "sweep"), ("bench", "bench")):
            d = copy(kind, f"{module}_no_matplotlib")
            before = listing(d)
            p = chart(module, d, "--quiet", pre=block)
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertEqual(p.stderr, "nacre: warning: matplotlib not found; charts skipped\n", module)
            self.assertEqual(listing(d), before, module)

    def test_a_failing_write_leaves_nothing(self):
        block = ("import matplotlib.figure\n"
                 "def failing(self, fname, *a, **k):\n"
                 "    open(fname, 'wb').write(b'\\x89PNG\\r\\n\\x1a\\npartial')\n"
                 "    raise OSError(28, 'No space left on device')\n"
                 "matplotlib.figure.Figure.savefig = failing")
        for kind in ("mc",):  # (one module: they share save_png; dyn's: tests/app/run_dyn_faults.sh)
            d = copy(kind, f"{kind}_full_disk")
            p = chart(kind, d, "--quiet", pre=block)
            self.assertNotEqual(p.returncode, 0)
            self.assertIn("No space left on device", p.stderr)
            self.assertEqual([f for f in os.listdir(d) if f.endswith(".png") or ".tmp" in f], [], kind)

    def test_bad_command_lines(self):
        d = source("mc")
        for args in ([], ["--bogus", d], [d, d]):
            p = subprocess.run([sys.executable, "-m", "nacre.charts.mc", *args], env=support.env(),
                               capture_output=True, text=True)
            self.assertNotEqual(p.returncode, 0, args)
            self.assertIn("python3 -m nacre.charts.mc", p.stderr, args)


if __name__ == "__main__":
    EXE, arg = support.take_args(sys.argv)
    SCRATCH = support.Scratch(arg, "python_charts")
    unittest.main()
