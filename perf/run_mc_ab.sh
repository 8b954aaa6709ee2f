#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# A/B throughput of two nacre_perf_mc builds, interleaved in one sitting (old, new, old, new, ...)
# so that both see the same machine load; the ratio is taken per repetition.
# Usage (inside the dev root, from the repository root):
#   devenv/nacre-env run perf/run_mc_ab.sh OLD_BIN NEW_BIN OUTDIR [REPS]
# e.g. OLD_BIN = a copy of build/openmp/perf/nacre_perf_mc built from the base commit.
# Writes OUTDIR/ab_{old,new}.csv (nacre_perf_mc's columns) and prints the per-rep ratios of
# wall-clock trials/s and of trials per CPU-second (the latter robust to a shared machine).
set -euo pipefail
old="$1"; new="$2"; out="$3"; reps="${4:-3}"
sizes="${NACRE_MC_SIZES:-300000}"; cycles="${NACRE_MC_CYCLES:-20}"
mkdir -p "$out"; rm -f "$out/ab_old.csv" "$out/ab_new.csv"
export OMP_PROC_BIND=spread OMP_PLACES=threads
for rep in $(seq "$reps"); do
  for nt in 1 2; do
    "$old" --bricks "$sizes" --cycles "$cycles" --repeats 2 --colouring tiles,natural --csv "$out/ab_old.csv" --kokkos-num-threads=$nt >/dev/null
    "$new" --bricks "$sizes" --cycles "$cycles" --repeats 2 --colouring tiles,natural --csv "$out/ab_new.csv" --kokkos-num-threads=$nt >/dev/null
  done
done
python3 - "$out" <<'PY'
import csv, statistics, sys
out = sys.argv[1]
a = list(csv.DictReader(open(f"{out}/ab_old.csv")))
b = list(csv.DictReader(open(f"{out}/ab_new.csv")))
groups = {}
for ra, rb in zip(a, b):
    key = (ra["bricks"], ra["implementation"], ra["threads"])
    groups.setdefault(key, []).append((float(rb["trials_per_second"]) / float(ra["trials_per_second"]),
                                       float(rb["trials_per_cpu_second"]) / float(ra["trials_per_cpu_second"]),
                                       float(ra["trials_per_cpu_second"]), float(rb["trials_per_cpu_second"]),
                                       ra["energy_after"], rb["energy_after"]))
print("bricks implementation threads | new/old wall (per rep) | new/old per CPU-s (per rep) | M trials/CPU-s old -> new (median) | energy_after old, new")
for (n, impl, nt), v in groups.items():
    w = " ".join(f"{x[0]:.2f}" for x in v); c = " ".join(f"{x[1]:.2f}" for x in v)
    print(f"{n} {impl} {nt} | {w} | {c} | {statistics.median(x[2] for x in v)/1e6:.2f} -> {statistics.median(x[3] for x in v)/1e6:.2f} | {v[0][4]}, {v[0][5]}")
PY
