#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Speed-ups to the same simulated time from nacre_perf_dyn_step CSVs (one run per file).

speed-up of BIE over X = (h_BIE / h_X) x (t_X / t_BIE), t = CPU seconds per step; every ratio is
taken within one file (one run). Prints and writes DIR/summary.csv:
    python3 perf/dyn_speedup_summary.py DIR FILE.csv...
"""
import csv
import os
import sys


def main():
    out_dir, files = sys.argv[1], sys.argv[2:]
    lines = ["file,bricks,variant,ue_ms,be_ms,bie_ms,h_bie_over_h_be,bie_be_cost,bie_vs_be,bie_vs_ue"]
    for f in files:
        rows = list(csv.DictReader(open(f)))
        by = {(r["method"], r["bricks"]): r for r in rows}
        t = lambda r: float(r["cpu_seconds_per_step"])
        h = lambda r: float(r["dt"])
        for n in sorted({r["bricks"] for r in rows}, key=int):
            ue, be = by.get(("ue", n)), by[("be", n)]
            for var in ("bie", "bie_dense", "bie_split"):
                if (var, n) not in by:
                    continue
                b = by[(var, n)]
                sue = f"{h(b) / h(ue) * t(ue) / t(b):.1f}" if ue else ""
                ue_ms = f"{t(ue) * 1e3:.2f}" if ue else ""
                lines.append(f"{os.path.basename(f)},{n},{var},{ue_ms},{t(be) * 1e3:.2f},{t(b) * 1e3:.2f},"
                             f"{h(b) / h(be):.1f},{t(b) / t(be):.2f},{h(b) / h(be) * t(be) / t(b):.2f},{sue}")
    open(os.path.join(out_dir, "summary.csv"), "w").write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
