#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Runs every ```python block of README.md and docs/**/*.md, as a reader would: each block in
a fresh python3 whose current directory is a scratch copy of the repository root (every
top-level entry of the repository linked in, but out/, which is the block's own) and whose
PYTHONPATH names python/, so `import nacre`, `inputs/default.toml` and `out/default` resolve.

What a block reads under out/ is made first, once per test run, by the nacre program:

  1. Declared, in comment lines at the top of the block (before its first statement):

         # needs: out/default from inputs/default.toml
         # needs: out/dyn from tests/app/tiny_dynamic.toml; out/s from sweep tests/app/tiny.toml --set mortar.k=100,200
         # needs: out/b from bench tests/app/tiny.toml --steps 1
         # needs: nothing

     "DIR from DECK [ARGS]" runs `nacre DECK -o DIR -q [ARGS]`; "DIR from sweep DECK ARGS" and
     "DIR from bench DECK ARGS" run `nacre sweep|bench DECK ARGS -o DIR`; several needs are
     separated by ";" or given on several lines; DIR lies under out/ (the scratch directory's
     own), DECK is relative to the repository root. "nothing": the block needs no outputs.

  2. Inferred, for a block without a `# needs:` line: every string literal of the block that
     names a path under out/ ("out/default", "out/default/steps.csv") is made by the shipped
     deck (inputs/*.toml, tests/app/*.toml) whose [output] directory is that out/NAME.

The program draws the charts (the deck's [output] charts) only for a block that names a .png
file; for the others it runs a copy of the deck with charts = false (seconds saved per deck).

A block that reads a path under out/ that neither gives a way to make fails (as does one that
raises, exits non-zero, or runs over 300 s). `# doc-test: skip REASON` as a top comment line
skips a block, saying so.

    test_doc_examples.py [NACRE_BIN [SCRATCH_DIR]] [unittest options]
"""
import ast
import glob
import io
import os
import re
import shlex
import shutil
import subprocess
import sys
import tokenize
import unittest

import support

EXE = SCRATCH = None
FENCE = re.compile(r"^(\s*)```python\s*$")
NEEDS = re.compile(r"^#\s*needs:\s*(.*)$")
SKIP = re.compile(r"^#\s*doc-test:\s*skip\b(.*)$")


def blocks():
    """(file relative to the repository, line of the fence, code) of every ```python block."""
    files = [os.path.join(support.REPO, "README.md")] + sorted(
        glob.glob(os.path.join(support.REPO, "docs", "**", "*.md"), recursive=True))
    out = []
    for path in files:
        if not os.path.exists(path):
            continue
        with open(path) as f:
            lines = f.read().splitlines()
        i = 0
        while i < len(lines):
            m = FENCE.match(lines[i])
            if not m:
                i += 1
                continue
            indent, start, body = len(m.group(1)), i + 1, []
            i += 1
            while i < len(lines) and not lines[i].strip().startswith("```"):
                body.append(lines[i][indent:] if lines[i][:indent].strip() == "" else lines[i])
                i += 1
            out.append((os.path.relpath(path, support.REPO), start, "\n".join(body) + "\n"))
            i += 1
    return out


def header_comments(code):
    """The comment lines before the block's first statement."""
    out = []
    for line in code.splitlines():
        s = line.strip()
        if not s:
            continue
        if not s.startswith("#"):
            break
        out.append(s)
    return out


def deck_outputs():
    """{out/NAME: deck} of the shipped decks ([output] directory = "out/NAME")."""
    found = {}
    for deck in sorted(glob.glob(os.path.join(support.REPO, "inputs", "*.toml")) +
                       glob.glob(os.path.join(support.REPO, "tests", "app", "*.toml"))):
        section = None
        with open(deck) as f:
            for line in f:
                s = line.split("#", 1)[0].strip()
                if s.startswith("["):
                    section = s.strip("[]").strip()
                elif section == "output" and (m := re.match(r'directory\s*=\s*"([^"]+)"', s)):
                    d = os.path.normpath(m.group(1))
                    if d.startswith("out" + os.sep):
                        found.setdefault(d, os.path.relpath(deck, support.REPO))
    return found


def out_paths(code):
    """The out/NAME directories the block's string literals name (comments are not read)."""
    names = set()
    try:
        toks = list(tokenize.generate_tokens(io.StringIO(code).readline))
    except (tokenize.TokenError, SyntaxError):
        return names
    for t in toks:
        if t.type != tokenize.STRING:
            continue
        try:
            v = ast.literal_eval(t.string)
        except (ValueError, SyntaxError):
            continue
        if isinstance(v, str) and (m := re.match(r"^(?:\./)?out/([^/\s]+)", v)):
            names.add("out/" + m.group(1))
    return names


def needs_of(code):
    """(list of (out dir, command kind, deck, extra args), skip reason or None); raises
    ValueError for a path under out/ that nothing makes."""
    head = header_comments(code)
    for c in head:
        if m := SKIP.match(c):
            return [], (m.group(1).strip(" :-—") or "no reason given")
    declared = [m.group(1) for c in head if (m := NEEDS.match(c))]
    if declared:
        needs = []
        for spec in ";".join(declared).split(";"):
            spec = spec.strip()
            if not spec or spec == "nothing":
                continue
            words = shlex.split(spec)
            if len(words) < 3 or words[1] != "from":
                raise ValueError(f"'# needs: {spec}': expected 'DIR from [sweep|bench] DECK [ARGS]'")
            d, rest = os.path.normpath(words[0]), words[2:]
            if not d.startswith("out" + os.sep):
                raise ValueError(f"'# needs: {spec}': the outputs go under out/ (the block's own directory)")
            kind = rest.pop(0) if rest[0] in ("sweep", "bench") else "run"
            if not rest:
                raise ValueError(f"'# needs: {spec}': no deck")
            needs.append((d, kind, rest[0], rest[1:]))
        return needs, None
    decks = deck_outputs()
    needs, missing = [], []
    for d in sorted(out_paths(code)):
        if d in decks:
            needs.append((d, "run", decks[d], []))
        else:
            missing.append(d)
    if missing:
        raise ValueError(f"the block reads {', '.join(missing)}, which no shipped deck writes and no "
                         "'# needs: DIR from DECK' line makes")
    return needs, None


def setUpModule():
    global EXE, SCRATCH
    if EXE is None:
        EXE, arg = support.take_args([sys.argv[0]])
        SCRATCH = support.Scratch(arg, "python_doc_examples")
    root = os.path.join(SCRATCH.path, "root")
    os.makedirs(os.path.join(root, "out"))
    for name in os.listdir(support.REPO):  # the repository's layout, with out/ of its own
        if name not in ("out", ".git"):
            os.symlink(os.path.join(support.REPO, name), os.path.join(root, name))
    SCRATCH.root, SCRATCH.made = root, {}


def tearDownModule():
    SCRATCH.close()


def make(need, charts):
    """Run the program for one need, once per test run (again, with charts, where a later block
    needs the charts of outputs made without); raises with its output on failure."""
    d, kind, deck, extra = need
    key = (d, kind, deck, tuple(extra))
    if d in SCRATCH.made:
        made_key, made_charts = SCRATCH.made[d]
        if made_key != key:
            raise ValueError(f"{d} is made by two different needs: {made_key[1:]} and {key[1:]}")
        if made_charts or not charts:
            return
    deck_path = os.path.join(support.REPO, deck)
    if not os.path.exists(deck_path):
        raise ValueError(f"needs {d} from {deck}: no such deck")
    if not charts:
        decks = os.path.join(SCRATCH.path, "decks", d.replace(os.sep, "_"))
        os.makedirs(decks, exist_ok=True)
        deck_path = support.deck_without_charts(deck_path, decks)
    target = os.path.join(SCRATCH.root, d)
    shutil.rmtree(target, ignore_errors=True)
    if kind == "run":
        cmd = [EXE, deck_path, "-o", target, "-q", *extra]
    else:
        cmd = [EXE, kind, deck_path, *extra, "-o", target]
    support.run(cmd, cwd=SCRATCH.root)
    SCRATCH.made[d] = (key, charts)


class DocExamples(unittest.TestCase):
    def test_blocks(self):
        found = blocks()
        if not found:
            print("test_doc_examples: no ```python block in README.md or docs/", file=sys.stderr)
        for path, line, code in found:
            with self.subTest(block=f"{path}:{line}"):
                try:
                    needs, skip = needs_of(code)
                except ValueError as e:
                    self.fail(f"{path}:{line}: {e}")
                if skip:
                    print(f"test_doc_examples: {path}:{line} skipped: {skip}", file=sys.stderr)
                    continue
                charts = ".png" in code
                for n in needs:
                    make(n, charts)
                p = subprocess.run([sys.executable, "-"], input=code, cwd=SCRATCH.root, env=support.env(),
                                   capture_output=True, text=True, timeout=300)
                self.assertEqual(p.returncode, 0, f"{path}:{line}: the example failed:\n{p.stderr[-3000:]}")


class Convention(unittest.TestCase):
    """The needs convention on made-up blocks (no program run)."""

    def test_declared(self):
        needs, skip = needs_of("# needs: out/a from inputs/default.toml; out/s from sweep tests/app/tiny.toml "
                               "--set mortar.k=1,2\n# needs: out/b from bench tests/app/tiny.toml --steps 1\nx = 1\n")
        self.assertIsNone(skip)
        self.assertEqual(needs, [("out/a", "run", "inputs/default.toml", []),
                                 ("out/s", "sweep", "tests/app/tiny.toml", ["--set", "mortar.k=1,2"]),
                                 ("out/b", "bench", "tests/app/tiny.toml", ["--steps", "1"])])
        self.assertEqual(needs_of("# needs: nothing\nprint(open('out/x').read())\n"), ([], None))

    def test_inferred(self):
        needs, _ = needs_of('import nacre\nrun = nacre.Run("out/default")  # "out/dynamic" reads the same way\n'
                            'print(open("out/default/steps.csv").read()[:10])\n')
        self.assertEqual(needs, [("out/default", "run", "inputs/default.toml", [])])

    def test_no_way_to_make_fails(self):
        with self.assertRaisesRegex(ValueError, "out/nowhere"):
            needs_of('import nacre\nnacre.Run("out/nowhere")\n')
        with self.assertRaisesRegex(ValueError, "expected 'DIR from"):
            needs_of("# needs: out/a inputs/default.toml\n")
        with self.assertRaisesRegex(ValueError, "under out/"):
            needs_of("# needs: inputs/x from inputs/default.toml\n")

    def test_skip(self):
        self.assertEqual(needs_of("# doc-test: skip needs a GPU\nimport x\n"), ([], "needs a GPU"))


if __name__ == "__main__":
    EXE, arg = support.take_args(sys.argv)
    SCRATCH = support.Scratch(arg, "python_doc_examples")
    unittest.main()
