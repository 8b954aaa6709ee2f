#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Chart and JSON summary of perf/run_colouring_bench.sh (ratios from the same run)."""
import csv
import json
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

out = sys.argv[1]
col = list(csv.DictReader(open(os.path.join(out, "colouring.csv"))))
mc = list(csv.DictReader(open(os.path.join(out, "mc_throughput.csv"))))
strategies = list(dict.fromkeys(r["strategy"] for r in col))
summary = {"colouring": [], "sweep": []}
for r in col:
    summary["colouring"].append({"bricks": int(r["bricks"]), "strategy": r["strategy"], "threads": int(r["threads"]),
                                 "colours": int(r["colours"]), "balance_largest_over_mean": float(r["balance"]),
                                 "seconds": float(r["seconds"]), "cpu_seconds": float(r["cpu_seconds"])})
for r in mc:
    summary["sweep"].append({"bricks": int(r["bricks"]), "schedule": r["implementation"].removeprefix("nacre-"),
                             "threads": int(r["threads"]), "trials_per_second": float(r["trials_per_second"]),
                             "trials_per_cpu_second": float(r["trials_per_cpu_second"])})
# ratios against the natural colouring at each size and thread count (same run)
for key, rows, name, val in (("colour_time_over_natural", summary["colouring"], "strategy", "seconds"),
                             ("colour_cpu_over_natural", summary["colouring"], "strategy", "cpu_seconds"),
                             ("sweep_speed_over_natural", summary["sweep"], "schedule", "trials_per_second"),
                             ("sweep_cpu_speed_over_natural", summary["sweep"], "schedule", "trials_per_cpu_second")):
    for r in rows:
        nat = [x[val] for x in rows if x["bricks"] == r["bricks"] and x[name] == "natural" and x["threads"] == r["threads"]]
        r[key] = r[val] / nat[0] if nat and nat[0] > 0 else None
json.dump(summary, open(os.path.join(out, "colouring_bench.json"), "w"), indent=2)

fig, ax = plt.subplots(1, 3, figsize=(15, 4.2))
sizes = sorted({r["bricks"] for r in summary["colouring"]})
for s in strategies:
    rs = sorted((r for r in summary["colouring"] if r["strategy"] == s), key=lambda r: r["bricks"])
    ax[0].loglog([r["bricks"] for r in rs], [r["cpu_seconds"] for r in rs], "o-", label=s)
    ax[1].semilogx([r["bricks"] for r in rs], [r["colours"] + 0.02 * strategies.index(s) for r in rs], "o-", label=s)
ax[0].set(xlabel="bricks", ylabel="CPU seconds to colour", title="colouring cost (best of 3)")
ax[1].set(xlabel="bricks", ylabel="colours", title="colours (work items per cycle: launches)")
sweeps = [s for s in strategies if any(r["schedule"] == s for r in summary["sweep"])]
sw_sizes = sorted({r["bricks"] for r in summary["sweep"] if r["threads"] == 1})
w = 0.8 / max(1, len(sw_sizes))
for k, n in enumerate(sw_sizes):
    rs = {r["schedule"]: r["trials_per_cpu_second"] for r in summary["sweep"] if r["bricks"] == n and r["threads"] == 1}
    ax[2].bar([i + k * w for i in range(len(sweeps))], [rs.get(s, 0) / 1e6 for s in sweeps], w, label=f"{n} bricks")
ax[2].set_xticks([i + w * (len(sw_sizes) - 1) / 2 for i in range(len(sweeps))], sweeps, rotation=30)
ax[2].set(ylabel="M trials per CPU-second", title="sweep speed, 1 thread")
for a in ax:
    a.legend(fontsize=7)
fig.tight_layout()
fig.savefig(os.path.join(out, "colouring_bench.png"), dpi=110)
for r in summary["colouring"]:
    print(f"{r['bricks']:>8} {r['strategy']:>17}: {r['colours']} colours, balance {r['balance_largest_over_mean']:.3f}, "
          f"{r['seconds']*1e3:.1f} ms wall, {r['cpu_seconds']*1e3:.1f} ms CPU (x{r['colour_cpu_over_natural']:.1f} natural)")
for r in summary["sweep"]:
    print(f"{r['bricks']:>8} {r['schedule']:>17} {r['threads']}t: {r['trials_per_second']/1e6:.2f} M trials/s wall, "
          f"{r['trials_per_cpu_second']/1e6:.2f} M per CPU-s (x{r['sweep_cpu_speed_over_natural']:.2f} natural)")
