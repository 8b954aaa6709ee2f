#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Chart and JSON summary of perf/run_mc_bench.sh results (ratios from the same run)."""
import csv
import json
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

out = sys.argv[1]
rows = list(csv.DictReader(open(os.path.join(out, "mc_throughput.csv"))))
init = list(csv.DictReader(open(os.path.join(out, "init_scaling.csv"))))
tp = {}
for r in rows:
    tp[(int(r["bricks"]), r["implementation"], int(r["threads"]))] = float(r["trials_per_second"])
sizes = sorted({k[0] for k in tp})
impls = sorted({k[1] for k in tp if k[1] != "reference"})
summary = {"throughput_trials_per_second": [], "init_seconds": []}
for n in sizes:
    ref = tp.get((n, "reference", 1))
    row = {"bricks": n, "reference_1t": ref}
    for im in impls:
        k1, k2 = tp.get((n, im, 1)), tp.get((n, im, 2))
        row[im] = {"1t": k1, "2t": k2,
                   "speedup_2t_over_1t": k2 / k1 if k1 and k2 else None,
                   "1t_over_reference": k1 / ref if k1 and ref else None}
    summary["throughput_trials_per_second"].append(row)
for r in init:
    summary["init_seconds"].append({"bricks": int(r["bricks"]), "interfaces": int(r["interfaces"]),
                                    "seconds": float(r["total_s"])})
json.dump(summary, open(os.path.join(out, "mc_bench.json"), "w"), indent=2)
for row in summary["throughput_trials_per_second"]:
    line = f"{row['bricks']:>8} bricks: reference {row['reference_1t']/1e6:.2f} M/s"
    for im in impls:
        r = row[im]
        line += (f"; {im} 1t {r['1t']/1e6:.2f}, 2t {r['2t']/1e6:.2f} M/s (2t/1t x{r['speedup_2t_over_1t']:.2f},"
                 f" 1t/ref x{r['1t_over_reference']:.2f})")
    print(line)
for s_ in summary["init_seconds"]:
    print(f"init {s_['bricks']:>8} bricks: {s_['seconds']:.2f} s")

fig, ax = plt.subplots(1, 2, figsize=(12, 4.4))
series = [("reference (serial AoS), 1 thread", ("reference", 1))]
for im in impls:
    series += [(f"{im}, 1 thread", (im, 1)), (f"{im}, 2 threads", (im, 2))]
w = 0.8 / len(series)
xs = list(range(len(sizes)))
for j, (label, key) in enumerate(series):
    ax[0].bar([x + (j - (len(series) - 1) / 2) * w for x in xs], [tp.get((n,) + key, 0) / 1e6 for n in sizes], w,
              label=label)
ax[0].set_xticks(xs, [f"{n//1000}k" for n in sizes])
ax[0].set_xlabel("bricks")
ax[0].set_ylabel("million brick trials / s")
ax[0].legend(fontsize=8)
ax[0].set_title("Monte Carlo sweep throughput")
nb = [s_["bricks"] for s_ in summary["init_seconds"]]
ts = [s_["seconds"] for s_ in summary["init_seconds"]]
ax[1].loglog(nb, ts, "o-", label="measured")
if nb:
    ax[1].loglog(nb, [ts[-1] * n / nb[-1] for n in nb], "--", color="gray", label="O(N)")
ax[1].set_xlabel("bricks")
ax[1].set_ylabel("initialisation time (s)")
ax[1].legend()
ax[1].set_title("specimen + interfaces + colouring + upload")
fig.tight_layout()
fig.savefig(os.path.join(out, "mc_bench.png"), dpi=120)
