#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Chart and summary of perf/run_dyn_bench.sh: time per step vs bricks (UE, BE, 1 and 2 threads)
and each run's effective bandwidth (bytes moved per step / time per step) against the triad
bandwidth measured in the same process, by wall time and by CPU time (process CPU time / threads,
robust to other processes on a shared machine; the triad timed the same way).
Usage: plot_dyn_bench.py OUTDIR"""
import csv
import json
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

out = sys.argv[1]
rows = list(csv.DictReader(open(os.path.join(out, "dyn_step.csv"))))
for r in rows:
    for k in r:
        if k != "method":
            r[k] = float(r[k])
summary = {"rows": rows, "bound_ratio_be": {}, "bound_ratio_be_cpu": {}, "two_thread_speedup": {}}
fig, ax = plt.subplots(1, 3, figsize=(16, 4.5))
for m in sorted({r["method"] for r in rows}):
    for nt in sorted({r["threads"] for r in rows}):
        sel = sorted((r for r in rows if r["method"] == m and r["threads"] == nt), key=lambda r: r["bricks"])
        if not sel:
            continue
        b = [r["bricks"] for r in sel]
        ax[0].loglog(b, [r["seconds_per_step"] * 1e3 for r in sel], "o-", label=f"{m.upper()} {int(nt)} thread(s)")
        ax[1].semilogx(b, [r["bound_ratio_cpu"] for r in sel], "o-", label=f"{m.upper()} {int(nt)} thread(s)")
        if m == "be":
            summary["bound_ratio_be"][f"{int(nt)}t"] = {int(r["bricks"]): r["bound_ratio"] for r in sel}
            summary["bound_ratio_be_cpu"][f"{int(nt)}t"] = {int(r["bricks"]): r["bound_ratio_cpu"] for r in sel}
    for r1 in (r for r in rows if r["method"] == m and r["threads"] == 1):
        r2 = [r for r in rows if r["method"] == m and r["threads"] == 2 and r["bricks"] == r1["bricks"]]
        if r2:
            summary["two_thread_speedup"].setdefault(m, {})[int(r1["bricks"])] = \
                r1["seconds_per_step"] / r2[0]["seconds_per_step"]
ax[0].set_xlabel("bricks")
ax[0].set_ylabel("time per step (ms)")
ax[0].legend(fontsize=8)
ax[0].set_title("time per step")
ax[1].axhline(2.0, color="gray", ls="--", label="target: 2x the bound")
ax[1].axhline(1.0, color="black", lw=0.6)
ax[1].set_xlabel("bricks")
ax[1].set_ylabel("CPU time per step / (bytes per step / triad bandwidth)")
ax[1].set_title("distance from the memory-bandwidth bound")
ax[1].legend(fontsize=8)
ms = sorted({r["method"] for r in rows})
for i, m in enumerate(ms):
    sel = [r for r in rows if r["method"] == m and r["threads"] == max(x["threads"] for x in rows)]
    if sel:
        r = max(sel, key=lambda r: r["bricks"])
        ax[2].bar([2 * i, 2 * i + 0.8], [r["bytes_per_brick"], r["bytes_per_brick_unshared"]], width=0.8,
                  color=["C0", "C3"])
        ax[2].text(2 * i + 0.4, r["bytes_per_brick_unshared"], f"{m.upper()}", ha="center", va="bottom")
# BIE vs BE to the same simulated time: (dt_bie / t_bie) / (dt_be / t_be), same size and threads
for rb in (r for r in rows if r["method"] in ("bie", "bie_dense")):
    re_ = [r for r in rows if r["method"] == "be" and r["threads"] == rb["threads"] and r["bricks"] == rb["bricks"]]
    if re_:
        summary.setdefault(f"{rb['method']}_over_be_speed", {}).setdefault(f"{int(rb['threads'])}t", {})[int(rb["bricks"])] = {
            "step_ratio": rb["dt"] / re_[0]["dt"], "cost_ratio": rb["seconds_per_step"] / re_[0]["seconds_per_step"],
            "speedup": (rb["dt"] / rb["seconds_per_step"]) / (re_[0]["dt"] / re_[0]["seconds_per_step"]),
            "cost_ratio_cpu": rb["cpu_seconds_per_step"] / re_[0]["cpu_seconds_per_step"],
            "speedup_cpu": (rb["dt"] / rb["cpu_seconds_per_step"]) / (re_[0]["dt"] / re_[0]["cpu_seconds_per_step"])}
prof = os.path.join(out, "dyn_step_profile.csv")
if os.path.exists(prof):
    kern = {}
    for r in csv.DictReader(open(prof)):
        kern.setdefault(f"{r['method']} {r['bricks']} {r['threads']}t", {})[r["kernel"]] = float(r["ms_per_step"])
    summary["kernels_ms_per_step"] = kern
summary["bytes_per_brick"] = {m: {"shared": max((r for r in rows if r["method"] == m), key=lambda r: r["bricks"])["bytes_per_brick"],
                                  "unshared": max((r for r in rows if r["method"] == m), key=lambda r: r["bricks"])["bytes_per_brick_unshared"]}
                              for m in ms}
ax[2].set_xticks([2 * i + 0.4 for i in range(len(ms))], [m.upper() for m in ms])
ax[2].set_ylabel("device bytes per brick (blue shared, red per element)")
ax[2].set_title("memory per brick")
fig.tight_layout()
fig.savefig(os.path.join(out, "dyn_step.png"), dpi=120)
json.dump(summary, open(os.path.join(out, "dyn_step.json"), "w"), indent=1)
print(json.dumps({k: v for k, v in summary.items() if k != "rows"}, indent=1))
