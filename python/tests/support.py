# SPDX-License-Identifier: BSD-3-Clause
"""What the tests of the nacre package share: where the repository, the package and the nacre
program are, running the program on small decks, and the reference data products
(r_curve.csv, sweep.csv) written from nacre.analysis for a program that does not write them yet.

The program: the first command-line argument of a test, else $NACRE_BIN, else
build/openmp/src/nacre. The scratch directory: the second argument, else $NACRE_TEST_DIR, else a
temporary directory removed at the end.
"""
import csv
import importlib.util
import os
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
PYTHON_DIR = os.path.dirname(HERE)           # python/: the directory that holds the package
REPO = os.path.dirname(PYTHON_DIR)           # the repository root

if importlib.util.find_spec("nacre") is None:  # not installed nor on PYTHONPATH: the source tree beside these tests
    sys.path.insert(0, PYTHON_DIR)


def take_args(argv):
    """(program, scratch directory or None) from a test's command line and the environment; the
    arguments are removed from argv (unittest parses the rest)."""
    pos = [a for a in argv[1:] if not a.startswith("-")]
    for a in pos[:2]:
        argv.remove(a)
    exe = pos[0] if pos else os.environ.get("NACRE_BIN") or os.path.join(REPO, "build", "openmp", "src", "nacre")
    scratch = pos[1] if len(pos) > 1 else os.environ.get("NACRE_TEST_DIR") or None
    exe = os.path.abspath(exe)
    if not os.access(exe, os.X_OK):
        sys.exit(f"nacre program {exe} not found: pass it as the first argument or in NACRE_BIN")
    return exe, scratch


class Scratch:
    """The scratch directory of a test module: the given one (emptied of what the test writes) or a
    temporary one removed at the end."""

    def __init__(self, path, name):
        if path:
            self.path = os.path.abspath(os.path.join(path, name))
            shutil.rmtree(self.path, ignore_errors=True)
            os.makedirs(self.path)
            self.temporary = False
        else:
            self.path = tempfile.mkdtemp(prefix=f"nacre_{name}_")
            self.temporary = True

    def close(self):
        if self.temporary:
            shutil.rmtree(self.path, ignore_errors=True)


def env():
    """The environment of the program and of the chart modules: the package on PYTHONPATH."""
    e = dict(os.environ)
    e["PYTHONPATH"] = PYTHON_DIR + (os.pathsep + e["PYTHONPATH"] if e.get("PYTHONPATH") else "")
    return e


def deck_without_charts(deck, directory):
    """A copy of `deck` with [output] charts = false (the reader's tests need no pictures), in
    `directory`; returns its path."""
    with open(deck) as f:
        text = f.read()
    if "\n[output]\n" in "\n" + text:
        text = ("\n" + text).replace("\n[output]\n", "\n[output]\ncharts = false\n", 1)[1:]
    else:
        text += "\n[output]\ncharts = false\n"
    path = os.path.join(directory, os.path.basename(deck))
    with open(path, "w") as f:
        f.write(text)
    return path


def run(cmd, cwd=None, ok=(0,)):
    """Run a command (the program's), its output captured; raises with its output when its exit
    code is not in ok."""
    p = subprocess.run(cmd, cwd=cwd, env=env(), capture_output=True, text=True)
    if p.returncode not in ok:
        raise RuntimeError(f"{' '.join(cmd)}: exit {p.returncode}\n{p.stdout[-2000:]}\n{p.stderr[-2000:]}")
    return p


def csv_line_count(path):
    """Data rows of a CSV file: its non-empty lines but the header."""
    with open(path) as f:
        return sum(1 for line in f if line.strip()) - 1


def write_csv(path, rows, columns):
    """A CSV written as nacre's Python wrote it before the program did (temporary + rename)."""
    from nacre import analysis
    tmp = os.path.join(os.path.dirname(path), "." + os.path.basename(path) + ".tmp%d" % os.getpid())
    with open(tmp, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=columns)
        w.writeheader()
        for r in rows:
            w.writerow({k: analysis.csv_value(v) for k, v in r.items()})
    os.replace(tmp, path)


def ensure_r_curve(directory):
    """r_curve.csv from the reference implementation where the program did not write one (an
    older program); returns True when it wrote one."""
    from nacre import analysis
    path = os.path.join(directory, "r_curve.csv")
    if os.path.exists(path):
        return False
    got = analysis.run_r_curve(directory)
    if got is None:
        return False
    write_csv(path, got[0], ["extension", "fracture_energy", "G_R", "toughening"])
    return True


def ensure_sweep_csv(directory):
    """sweep.csv from the reference implementation where the program did not write one."""
    from nacre import analysis
    path = os.path.join(directory, "sweep.csv")
    if os.path.exists(path):
        return False
    rows, columns = analysis.sweep_rows(directory)
    write_csv(path, rows, columns)
    return True
