#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Summarise perf/run_adaptive_study.sh: cycles, time, speed-up and accuracy per variant."""
import json
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "python"))
from nacre import Run  # noqa: E402  (the reader of nacre's outputs, python/nacre)

out = sys.argv[1]
names = ["fixed", "steps", "load", "predictor", "per-brick"]
runs = {}
for n in names:
    run = Run(os.path.join(out, n))
    rows, s = run.rows(), run.summary
    D = np.array([0.0] + [float(r["displacement"]) for r in rows])
    E = np.array([0.0] + [float(r["energy"]) for r in rows])
    runs[n] = {"D": D, "E": E, "cycles": s["cycles"], "seconds": s["seconds"], "steps": len(rows)}
ref = runs["fixed"]
scale = np.sqrt(np.mean(ref["E"] ** 2))
summary = []
for n in names:
    r = runs[n]
    e_at = np.interp(ref["D"], r["D"], r["E"])
    err = float(np.sqrt(np.mean((e_at - ref["E"]) ** 2)) / scale)
    summary.append({"variant": n, "load_steps": r["steps"], "cycles": r["cycles"], "seconds": r["seconds"],
                    "speedup_cycles": ref["cycles"] / r["cycles"], "speedup_time": ref["seconds"] / r["seconds"],
                    "energy_curve_rel_rms_vs_fixed": err})
json.dump(summary, open(os.path.join(out, "adaptive_study.json"), "w"), indent=2)
with open(os.path.join(out, "adaptive_study.csv"), "w") as f:
    f.write(",".join(summary[0].keys()) + "\n")
    for s in summary:
        f.write(",".join(str(v) for v in s.values()) + "\n")
for s in summary:
    print(f"{s['variant']:>10}: {s['load_steps']:3d} steps, {s['cycles']:7d} cycles, {s['seconds']:6.1f} s, "
          f"speed-up x{s['speedup_time']:.2f} (cycles x{s['speedup_cycles']:.2f}), "
          f"energy curve vs fixed {100*s['energy_curve_rel_rms_vs_fixed']:.2f} % RMS")
fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
for n in names:
    ax[0].plot(runs[n]["D"], runs[n]["E"], "o-", ms=2, label=n)
ax[0].set_xlabel("applied displacement D")
ax[0].set_ylabel("total energy")
ax[0].legend()
ax[0].set_title("energy curves")
for s in summary:
    ax[1].scatter(s["speedup_time"], 100 * s["energy_curve_rel_rms_vs_fixed"], s=40)
    ax[1].annotate(s["variant"], (s["speedup_time"], 100 * s["energy_curve_rel_rms_vs_fixed"]))
ax[1].set_xlabel("speed-up over the fixed run (wall time)")
ax[1].set_ylabel("energy-curve difference vs fixed (% RMS)")
ax[1].set_title("speed against accuracy")
fig.tight_layout()
fig.savefig(os.path.join(out, "adaptive_study.png"), dpi=120)
