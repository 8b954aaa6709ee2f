#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Tests of the package as it installs (no nacre program needed):

- every .py file under python/ starts (after a shebang) with the SPDX licence line;
- the build backend (_backend/nacre_build.py, standard library only: pip needs no download)
  reads pyproject.toml as tomllib does (its own reader, for Pythons without tomllib, too), and
  builds a wheel (the package, METADATA with version 1.0.0 and the licence, a RECORD whose
  hashes hold), an sdist and an editable wheel;
- where pip is installed: `pip install --no-index ./python` into a throwaway virtual environment
  (with the system's site packages, for numpy) and the installed package imports from there.
  The dev root has no pip: that step is then skipped (it says so).

    test_packaging.py [unittest options]
"""
import base64
import hashlib
import os
import subprocess
import sys
import tarfile
import tempfile
import unittest
import zipfile

import support

SPDX = "# SPDX-License-Identifier: BSD-3-Clause"
BACKEND = os.path.join(support.PYTHON_DIR, "_backend")


def hook(name, *args):
    """A PEP 517 hook of the backend, run as a front end runs it: a fresh interpreter in python/."""
    code = (f"import sys; sys.path.insert(0, {BACKEND!r}); import nacre_build; "
            f"print(nacre_build.{name}(*{list(args)!r}))")
    p = subprocess.run([sys.executable, "-c", code], cwd=support.PYTHON_DIR, capture_output=True, text=True)
    if p.returncode:
        raise AssertionError(f"{name}: {p.stderr}")
    return p.stdout.strip().splitlines()[-1]


class Packaging(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="nacre_pkg_")

    def tearDown(self):
        import shutil
        shutil.rmtree(self.tmp)

    def test_every_py_file_has_the_spdx_line(self):
        bad = []
        for d, dirs, files in os.walk(support.PYTHON_DIR):
            dirs[:] = [x for x in dirs if x != "__pycache__"]
            for f in files:
                if f.endswith(".py"):
                    with open(os.path.join(d, f)) as fh:
                        lines = fh.read().splitlines()
                    first = lines[1] if lines and lines[0].startswith("#!") else (lines[0] if lines else "")
                    if first != SPDX:
                        bad.append(os.path.relpath(os.path.join(d, f), support.PYTHON_DIR))
        self.assertEqual(bad, [], "files without the SPDX line first")

    def test_pyproject_as_tomllib_reads_it(self):
        sys.path.insert(0, BACKEND)
        try:
            import nacre_build
        finally:
            sys.path.remove(BACKEND)
        with open(os.path.join(support.PYTHON_DIR, "pyproject.toml")) as f:
            text = f.read()
        ours = nacre_build.parse_toml_subset(text)
        try:
            import tomllib
        except ImportError:
            self.skipTest("no tomllib (Python < 3.11) to compare with")
        self.assertEqual(ours, tomllib.loads(text))
        p = ours["project"]
        self.assertEqual((p["name"], p["version"], p["license"]), ("nacre", "1.0.0", "BSD-3-Clause"))
        self.assertEqual(ours["build-system"]["requires"], [])
        for bad in ('a = """x"""\n', "[[t]]\n", "a = 1.5\n"):
            with self.assertRaises(ValueError):
                nacre_build.parse_toml_subset(bad)

    def test_wheel(self):
        self.assertEqual(hook("get_requires_for_build_wheel"), "[]")
        name = hook("build_wheel", self.tmp)
        self.assertEqual(name, "nacre-1.0.0-py3-none-any.whl")
        with zipfile.ZipFile(os.path.join(self.tmp, name)) as z:
            names = set(z.namelist())
            for f in ("nacre/__init__.py", "nacre/__main__.py", "nacre/results.py", "nacre/analysis.py",
                      "nacre/charts/__init__.py", "nacre/charts/mc.py", "nacre/charts/dyn.py",
                      "nacre/charts/sweep.py", "nacre/charts/bench.py", "nacre-1.0.0.dist-info/METADATA",
                      "nacre-1.0.0.dist-info/WHEEL", "nacre-1.0.0.dist-info/RECORD"):
                self.assertIn(f, names)
            self.assertFalse([n for n in names if "__pycache__" in n or n.endswith(".pyc")])
            self.assertFalse([n for n in names if n.startswith(("tests/", "_backend/"))])
            meta = z.read("nacre-1.0.0.dist-info/METADATA").decode()
            for line in ("Name: nacre", "Version: 1.0.0", "License: BSD-3-Clause", "Requires-Dist: numpy",
                         'Requires-Dist: h5py; extra == "hdf5"'):
                self.assertIn(line + "\n", meta)
            if os.path.exists(os.path.join(support.REPO, "LICENSE")):
                self.assertIn("BSD 3-Clause", z.read("nacre-1.0.0.dist-info/LICENSE").decode())
            for row in z.read("nacre-1.0.0.dist-info/RECORD").decode().splitlines():
                path, digest, size = row.split(",")
                if path.endswith("RECORD"):
                    continue
                data = z.read(path)
                want = "sha256=" + base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
                self.assertEqual((digest, int(size)), (want, len(data)), path)
            self.assertEqual(len(z.read("nacre-1.0.0.dist-info/RECORD").decode().splitlines()), len(names))

    def test_sdist_and_editable(self):
        name = hook("build_sdist", self.tmp)
        self.assertEqual(name, "nacre-1.0.0.tar.gz")
        with tarfile.open(os.path.join(self.tmp, name)) as t:
            names = set(t.getnames())
        for f in ("pyproject.toml", "PKG-INFO", "_backend/nacre_build.py", "nacre/__init__.py",
                  "nacre/charts/mc.py", "tests/test_reader.py"):
            self.assertIn("nacre-1.0.0/" + f, names)
        wheel = hook("build_editable", self.tmp)
        with zipfile.ZipFile(os.path.join(self.tmp, wheel)) as z:
            pth = z.read("__editable__.nacre.pth").decode().strip()
        self.assertEqual(os.path.realpath(pth), os.path.realpath(support.PYTHON_DIR))

    def test_pip_install_offline(self):
        if subprocess.run([sys.executable, "-m", "pip", "--version"], capture_output=True).returncode:
            self.skipTest("no pip in this Python (the dev root has none)")
        venv = os.path.join(self.tmp, "venv")
        p = subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", "--without-pip", venv],
                           capture_output=True, text=True)
        if p.returncode:
            self.skipTest(f"no venv: {p.stderr.strip()[-200:]}")
        py = os.path.join(venv, "bin", "python")
        deps = [] if subprocess.run([py, "-c", "import numpy"], capture_output=True).returncode == 0 else ["--no-deps"]
        p = subprocess.run([sys.executable, "-m", "pip", "--python", py, "install", "--no-index", *deps,
                            support.PYTHON_DIR], capture_output=True, text=True)
        if p.returncode and "no such option: --python" in p.stderr:
            self.skipTest("pip older than 22.3 (no --python)")
        self.assertEqual(p.returncode, 0, p.stdout[-2000:] + p.stderr[-2000:])
        env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
        # found in the venv, with its metadata (without importing it: numpy may be missing here)
        p = subprocess.run([py, "-c", "import importlib.metadata as m, importlib.util as u; "
                            "print(m.version('nacre'), u.find_spec('nacre').origin)"],
                           cwd=self.tmp, env=env, capture_output=True, text=True)
        self.assertEqual(p.returncode, 0, p.stderr)
        version, where = p.stdout.split()
        self.assertEqual(version, "1.0.0")
        self.assertTrue(os.path.realpath(where).startswith(os.path.realpath(venv)), where)
        self.assertTrue(os.path.isfile(os.path.join(os.path.dirname(where), "charts", "mc.py")))
        if not deps:  # numpy there: the package imports
            p = subprocess.run([py, "-c", "import nacre; print(nacre.__version__)"], cwd=self.tmp, env=env,
                               capture_output=True, text=True)
            self.assertEqual((p.returncode, p.stdout.strip()), (0, "1.0.0"), p.stderr)


if __name__ == "__main__":
    unittest.main()
