#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Chart and summary of perf/run_dyn_critical.sh: critical step against stiffness ratio for UE and
BE (Fig. 4.6), its slope against the 1/sqrt(r) expectation, and the UE/BE gap against
sqrt(internal joint stiffness / brick stiffness) = sqrt(internal_stiffness_factor).
Usage: plot_dyn_critical.py OUTDIR"""
import csv
import json
import math
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

out = sys.argv[1]
rows = list(csv.DictReader(open(os.path.join(out, "dyn_critical.csv"))))
summary = {"critical_step": {}, "gap_ue_be": {}, "slope": {}}
fig, ax = plt.subplots(1, 2, figsize=(12, 4.5))
factor = float(rows[0]["internal_factor"])
for damp in sorted({r["damping"] for r in rows}):
    for m in ["ue", "be"]:
        sel = sorted((r for r in rows if r["method"] == m and r["damping"] == damp), key=lambda r: float(r["ratio"]))
        if not sel:
            continue
        rr = np.array([float(r["ratio"]) for r in sel])
        h = np.array([float(r["critical_step"]) for r in sel])
        summary["critical_step"][f"{m}_{damp}"] = dict(zip(rr.tolist(), h.tolist()))
        if len(rr) > 1:
            summary["slope"][f"{m}_{damp}"] = float(np.polyfit(np.log(rr), np.log(h), 1)[0])
        ax[0].loglog(rr, h * 1e9, "o-" if damp == "none" else "s--", label=f"{m.upper()}, damping {damp}")
    ue = {float(r["ratio"]): float(r["critical_step"]) for r in rows if r["method"] == "ue" and r["damping"] == damp}
    be = {float(r["ratio"]): float(r["critical_step"]) for r in rows if r["method"] == "be" and r["damping"] == damp}
    common = sorted(set(ue) & set(be))
    if common:
        gap = [be[r] / ue[r] for r in common]
        summary["gap_ue_be"][damp] = dict(zip(common, gap))
        ax[1].semilogx(common, gap, "o-" if damp == "none" else "s--", label=f"BE / UE, damping {damp}")
rr = np.array(sorted({float(r["ratio"]) for r in rows}))
be0 = [v for k, v in summary["critical_step"].items() if k.startswith("be")]
if be0:
    h0 = list(be0[0].values())[0]
    ax[0].loglog(rr, h0 * 1e9 / np.sqrt(rr / rr[0]), ":", color="gray", label="~ 1/sqrt(r)")
ax[0].set_xlabel("stiffness ratio r")
ax[0].set_ylabel("critical step (ns)")
ax[0].legend(fontsize=8)
ax[0].set_title(f"critical step ({rows[0]['bricks']} bricks)")
ax[1].axhline(math.sqrt(factor), color="gray", ls="--", label=f"sqrt(internal/brick) = sqrt({factor:g})")
ax[1].set_xlabel("stiffness ratio r")
ax[1].set_ylabel("critical step BE / UE")
ax[1].legend(fontsize=8)
ax[1].set_ylim(bottom=0)
summary["sqrt_internal_over_brick"] = math.sqrt(factor)
fig.tight_layout()
fig.savefig(os.path.join(out, "dyn_critical.png"), dpi=120)
json.dump(summary, open(os.path.join(out, "dyn_critical.json"), "w"), indent=1)
print(json.dumps(summary, indent=1))
