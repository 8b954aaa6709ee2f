#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Chart the per-phase time of perf/run_time_split.sh runs (one stacked bar per generator)."""
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "python"))
from nacre import read_json  # noqa: E402  (the reader of nacre's outputs, python/nacre)

out = sys.argv[1]
gens = ["philox", "aes-ctr", "mt-aes"]
rows = []
for g in gens:
    s = read_json(os.path.join(out, g, "summary.json"))
    p = s["phase_seconds"]
    other = max(s["seconds"] - p["sweep"] - p["energy"] - p["rng"], 0.0)
    rows.append({"generator": g, "bricks": s["bricks"], "cycles": s["cycles"], "total_s": s["seconds"],
                 "sweep_s": p["sweep"], "energy_s": p["energy"], "rng_s": p["rng"], "other_s": other})
with open(os.path.join(out, "time_split.csv"), "w") as f:
    f.write("generator,bricks,cycles,total_s,sweep_s,energy_s,rng_s,other_s\n")
    for r in rows:
        f.write(",".join(str(r[k]) for k in ["generator", "bricks", "cycles", "total_s", "sweep_s", "energy_s",
                                               "rng_s", "other_s"]) + "\n")
for r in rows:
    t = r["total_s"]
    print(f"{r['generator']:>8}: {t:.2f} s, {r['cycles']} cycles; sweep {100*r['sweep_s']/t:.1f} %, "
          f"energy {100*r['energy_s']/t:.1f} %, rng {100*r['rng_s']/t:.1f} %, other {100*r['other_s']/t:.1f} %")
fig, ax = plt.subplots(figsize=(7, 4.2))
bottom = [0.0] * len(rows)
for key, label in [("sweep_s", "Monte Carlo sweep"), ("energy_s", "energy"), ("rng_s", "random numbers"),
                   ("other_s", "other (set-up, output)")]:
    vals = [r[key] for r in rows]
    ax.bar(gens, vals, bottom=bottom, label=label)
    bottom = [b + v for b, v in zip(bottom, vals)]
ax.set_ylabel("seconds")
ax.set_title(f"Time split of a Monte Carlo run ({rows[0]['bricks']} bricks, {rows[0]['cycles']} cycles)")
ax.legend()
fig.tight_layout()
fig.savefig(os.path.join(out, "time_split.png"), dpi=120)
