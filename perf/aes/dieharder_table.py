#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Tabulate dieharder reports: dieharder_table.py OUTDIR GEN... -> OUTDIR/dieharder.{csv,md}."""
import csv
import re
import sys
from pathlib import Path

ROW = re.compile(r"^\s*(\S+)\|\s*(\d+)\|\s*(\d+)\|\s*(\d+)\|\s*([0-9.eE+-]+)\|\s*(\w+)")


def parse(path):
    rows = []
    for line in Path(path).read_text(errors="replace").splitlines():
        m = ROW.match(line)
        if m:
            name, ntup, tsamples, psamples, p, verdict = m.groups()
            rows.append((f"{name} (ntup {ntup})" if ntup != "0" else name, float(p), verdict))
    return rows


def main():
    out = Path(sys.argv[1])
    gens = sys.argv[2:]
    results = {g: parse(out / f"dieharder_{g}.txt") for g in gens}
    # Test order: first appearance; a test that occurs several times (dieharder repeats a
    # line for each sub-test, e.g. sts_serial) keeps an index.
    order, cells = [], {}
    for g in gens:
        seen = {}
        for name, p, v in results[g]:
            seen[name] = seen.get(name, 0) + 1
            key = name if seen[name] == 1 else f"{name} #{seen[name]}"
            if key not in order:
                order.append(key)
            cells[(key, g)] = (p, v)
    with open(out / "dieharder.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["test"] + [f"{g} p" for g in gens] + [f"{g} assessment" for g in gens])
        for key in order:
            w.writerow([key] + [f"{cells[(key, g)][0]:.8f}" if (key, g) in cells else "" for g in gens]
                       + [cells[(key, g)][1] if (key, g) in cells else "" for g in gens])
    lines = ["| test | " + " | ".join(gens) + " |", "|---|" + "---|" * len(gens)]
    for key in order:
        row = []
        for g in gens:
            if (key, g) in cells:
                p, v = cells[(key, g)]
                row.append(f"{p:.4f}" + ("" if v == "PASSED" else f" **{v}**"))
            else:
                row.append("")
        lines.append(f"| {key} | " + " | ".join(row) + " |")
    summary = []
    for g in gens:
        vs = [v for _, _, v in results[g]]
        summary.append(f"{g}: {vs.count('PASSED')} passed, {vs.count('WEAK')} weak, "
                       f"{vs.count('FAILED')} failed of {len(vs)}")
    lines += ["", "Summary: " + "; ".join(summary) + "."]
    (out / "dieharder.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
