#!/usr/bin/env python3
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
summary = {"throughput_trials_per_second": [], "init_seconds": []}
for n in sizes:
    k1, k2, ref = tp.get((n, "kokkos", 1)), tp.get((n, "kokkos", 2)), tp.get((n, "reference", 1))
    summary["throughput_trials_per_second"].append({
        "bricks": n, "kokkos_1t": k1, "kokkos_2t": k2, "reference_1t": ref,
        "speedup_2t_over_1t": k2 / k1 if k1 and k2 else None,
        "kokkos_1t_over_reference": k1 / ref if k1 and ref else None})
for r in init:
    summary["init_seconds"].append({"bricks": int(r["bricks"]), "interfaces": int(r["interfaces"]),
                                    "seconds": float(r["total_s"])})
json.dump(summary, open(os.path.join(out, "mc_bench.json"), "w"), indent=2)
for s in summary["throughput_trials_per_second"]:
    print(f"{s['bricks']:>8} bricks: kokkos 1t {s['kokkos_1t']/1e6:.2f} M/s, 2t {s['kokkos_2t']/1e6:.2f} M/s "
          f"(x{s['speedup_2t_over_1t']:.2f}), reference {s['reference_1t']/1e6:.2f} M/s "
          f"(kokkos 1t / reference = {s['kokkos_1t_over_reference']:.2f})")
for s in summary["init_seconds"]:
    print(f"init {s['bricks']:>8} bricks: {s['seconds']:.2f} s")

fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
w = 0.27
xs = range(len(sizes))
for j, (label, key) in enumerate([("reference (serial AoS)", ("reference", 1)),
                                  ("nacre, 1 thread", ("kokkos", 1)), ("nacre, 2 threads", ("kokkos", 2))]):
    ax[0].bar([x + (j - 1) * w for x in xs], [tp.get((n,) + key, 0) / 1e6 for n in sizes], w, label=label)
ax[0].set_xticks(list(xs), [f"{n//1000}k" for n in sizes])
ax[0].set_xlabel("bricks")
ax[0].set_ylabel("million brick trials / s")
ax[0].legend()
ax[0].set_title("Monte Carlo sweep throughput")
nb = [s["bricks"] for s in summary["init_seconds"]]
ts = [s["seconds"] for s in summary["init_seconds"]]
ax[1].loglog(nb, ts, "o-", label="measured")
if nb:
    ax[1].loglog(nb, [ts[-1] * n / nb[-1] for n in nb], "--", color="gray", label="O(N)")
ax[1].set_xlabel("bricks")
ax[1].set_ylabel("initialisation time (s)")
ax[1].legend()
ax[1].set_title("specimen + interfaces + colouring + upload")
fig.tight_layout()
fig.savefig(os.path.join(out, "mc_bench.png"), dpi=120)
