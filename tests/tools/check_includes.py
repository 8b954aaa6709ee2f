# SPDX-License-Identifier: BSD-3-Clause
"""Dependencies point one way: the folder include graph of nacre's library against its layers.

Each folder of src/ and include/nacre/ has a layer; a file may include <nacre/F/...> only for a
folder F of a lower layer (the same folder is always fine). On top of the order: io depends on no
solver (io includes neither mc nor dyn). So no folder loop can form, the library never reads the
deck (only deck and app sit above it), and the solvers never write files.

KNOWN lists the edges that break the rule today, each with where it comes from; they are the debt
the rigid family's rebuild pays off. The check fails on any other violation, and on a KNOWN edge
that no longer occurs (take it off the list, so the debt can only shrink).

  check_includes.py ROOT            check the tree at ROOT (the repository)
  check_includes.py --self-test     the checker on a small planted tree: a violation must fail it
"""
import collections
import os
import re
import sys
import tempfile

# lowest first; a folder may include only folders before it
LAYERS = ["core", "aes", "rng", "geometry", "cohesive", "kinematics", "loading", "fracture", "par", "dyn",
          "mc", "io", "perf", "deck", "app"]
FORBIDDEN = {("io", "mc"), ("io", "dyn")}  # io depends on no solver
KNOWN = {
    ("core", "par"): "core/build_info.cpp asks par which MPI library the build has",
    ("geometry", "deck"): "geometry::build_specimen takes deck::Geometry (WallSpec still in deck)",
    ("fracture", "deck"): "fracture::CrackTracker reads deck::Geometry",
    ("mc", "deck"): "mc::Solver(const deck::Deck&)",
    ("mc", "io"): "mc/output.cpp writes the Monte Carlo run's files (its adapter belongs in app)",
}
INCLUDE = re.compile(r'^\s*#\s*include\s*<nacre/([a-z_0-9]+)/')


def folder_of(rel):
    parts = rel.split(os.sep)
    if parts[0] == "include" and len(parts) > 3:
        return parts[2]
    if parts[0] == "src" and len(parts) > 2:
        return parts[1]
    return None


def edges(root):
    """{(from, to): [file:line, ...]} over every C++ source and header of src/ and include/nacre/."""
    found = collections.defaultdict(list)
    for top in ("src", "include"):
        for d, _, names in os.walk(os.path.join(root, top)):
            for n in names:
                if not n.endswith((".hpp", ".cpp", ".h")):
                    continue
                path = os.path.join(d, n)
                rel = os.path.relpath(path, root)
                a = folder_of(rel)
                if a is None:
                    continue
                with open(path, errors="replace") as f:
                    for k, line in enumerate(f, 1):
                        m = INCLUDE.match(line)
                        if m and m.group(1) != a:
                            found[(a, m.group(1))].append(f"{rel}:{k}")
    return found


def violations(found):
    bad = {}
    for (a, b), where in found.items():
        if a not in LAYERS or b not in LAYERS:
            bad[(a, b)] = (where, f"folder {a if a not in LAYERS else b} has no layer (add it to LAYERS)")
        elif (a, b) in FORBIDDEN:
            bad[(a, b)] = (where, f"{a} depends on no solver")
        elif LAYERS.index(b) >= LAYERS.index(a):
            bad[(a, b)] = (where, f"{a} is below {b}")
    return bad


def check(root, known=KNOWN):
    bad = violations(edges(root))
    fails = 0
    for (a, b), (where, why) in sorted(bad.items()):
        if (a, b) in known:
            continue
        fails += 1
        print(f"FAIL: {a} -> {b} ({why}): {', '.join(where[:5])}")
    for (a, b) in sorted(set(known) - set(bad)):
        fails += 1
        print(f"FAIL: {a} -> {b} no longer occurs: take it off KNOWN ({known[(a, b)]})")
    n = sum(len(v) for v in edges(root).values())
    print(f"include graph: {n} includes across folders, {len(set(bad) & set(known))} known violations left, "
          f"{fails} failure(s)")
    return fails


def self_test():
    with tempfile.TemporaryDirectory() as t:
        def put(rel, text):
            os.makedirs(os.path.dirname(os.path.join(t, rel)), exist_ok=True)
            with open(os.path.join(t, rel), "w") as f:
                f.write(text)
        put("include/nacre/geometry/a.hpp", "#include <nacre/core/b.hpp>\n")
        put("src/io/c.cpp", "#include <nacre/geometry/a.hpp>\n")
        assert check(t, known={}) == 0, "a clean planted tree failed"
        put("src/geometry/d.cpp", "#include <nacre/app/e.hpp>\n")  # upward
        put("src/io/f.cpp", "  #  include <nacre/mc/g.hpp>\n")  # io -> solver
        assert check(t, known={}) == 2, "the planted violations were not both found"
        assert check(t, known={("geometry", "app"): "", ("io", "mc"): "", ("core", "deck"): ""}) == 1, \
            "a known violation that no longer occurs was not reported"
    print("self-test: a clean tree passes, planted violations and a stale known edge fail")
    return 0


if __name__ == "__main__":
    if sys.argv[1:] == ["--self-test"]:
        sys.exit(self_test())
    sys.exit(1 if check(sys.argv[1]) else 0)
