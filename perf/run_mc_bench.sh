#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Rigid-brick MC benchmarks in one run: initialisation scaling (10k .. 1M bricks) and sweep
# throughput for 10k/100k/300k bricks on 1 and 2 threads against the serial reference.
# Usage (from the repository root, on the host):
#   devenv/nacre-env run perf/run_mc_bench.sh [OUTDIR]      (default perf/results/mc)
# Writes OUTDIR/{init_scaling.csv, mc_throughput.csv, mc_bench.json, mc_bench.png}.
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-perf/results/mc}"
mkdir -p "$out"
echo "[perf] building (preset openmp)"
cmake --preset openmp >/dev/null && cmake --build --preset openmp --target nacre_perf_mc nacre_perf_init >/dev/null
bin=build/openmp/perf
export OMP_PROC_BIND=spread OMP_PLACES=threads
echo "[perf] initialisation scaling"
"$bin/nacre_perf_init" --bricks "${NACRE_INIT_SIZES:-10000,30000,100000,300000,1000000}" --csv "$out/init_scaling.csv" --kokkos-num-threads=2
rm -f "$out/mc_throughput.csv"
sizes="${NACRE_MC_SIZES:-10000,100000,300000}"
cycles="${NACRE_MC_CYCLES:-30}"
echo "[perf] sweep throughput, 1 thread + serial reference"
"$bin/nacre_perf_mc" --bricks "$sizes" --cycles "$cycles" --reference --csv "$out/mc_throughput.csv" --kokkos-num-threads=1
echo "[perf] sweep throughput, 2 threads"
"$bin/nacre_perf_mc" --bricks "$sizes" --cycles "$cycles" --csv "$out/mc_throughput.csv" --kokkos-num-threads=2
python3 perf/plot_mc_bench.py "$out"
