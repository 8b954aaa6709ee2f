#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Sweep schedules compared (docs/design.md, "Which colouring"): nacre's colourings and Kokkos
# Kernels' distance-1 colouring (kokkos-d1). Colours, balance and time to colour 10k .. 1M bricks
# (nacre_perf_colouring; also Kokkos Kernels' default, non-deterministic algorithm,
# kokkos-d1-default), then MC sweep speed with each schedule (nacre_perf_mc), all in one run.
# Usage (from the repository root, a build with Kokkos Kernels):
#   devenv/nacre-env run perf/run_colouring_bench.sh [OUTDIR]      (default perf/results/colouring)
# Writes OUTDIR/{colouring.csv, mc_throughput.csv, colouring_bench.json, colouring_bench.png}.
# Sizes: NACRE_COL_SIZES, NACRE_MC_SIZES; cycles: NACRE_MC_CYCLES; threads: NACRE_THREADS (2).
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-perf/results/colouring}"
build="${NACRE_BUILD:-build/openmp}"
mkdir -p "$out"
bin="$build/perf"
[ -x "$bin/nacre_perf_colouring" ] || { echo "no $bin/nacre_perf_colouring: build with Kokkos Kernels (devenv/nacre-env build)" >&2; exit 1; }
export OMP_PROC_BIND=spread OMP_PLACES=threads
nt="${NACRE_THREADS:-2}"
all=tiles,natural,largest-first,balanced,random,kokkos-d1
rm -f "$out/colouring.csv" "$out/mc_throughput.csv"
echo "[perf] colourings: colours, balance, time to colour"
"$bin/nacre_perf_colouring" --bricks "${NACRE_COL_SIZES:-10000,100000,300000,1000000}" --colouring "$all,kokkos-d1-default" \
  --csv "$out/colouring.csv" --kokkos-num-threads="$nt"
echo "[perf] sweep speed per schedule, 1 thread and $nt threads"
# trials per CPU-second (1 thread: no barriers, so CPU time is the sweep's own work) is the
# number that survives a loaded machine; wall-clock trials/s is recorded beside it
for t in 1 "$nt"; do
  OMP_WAIT_POLICY=passive "$bin/nacre_perf_mc" --bricks "${NACRE_MC_SIZES:-100000,300000}" --cycles "${NACRE_MC_CYCLES:-10}" \
    --colouring "$all" --csv "$out/mc_throughput.csv" --kokkos-num-threads="$t"
done
python3 perf/plot_colouring_bench.py "$out"
