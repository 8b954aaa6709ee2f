#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Polish methods against each other: from one Monte Carlo state of the default deck's
# specimen (same seed, same state for each method), FIRE, colour-swept block Newton and annealing
# (Monte Carlo cooled to T = 0) run to 1e-3 ... 1e-8; cumulative time and iterations to each
# tolerance. Two states: elastic (D = 0.03,
# 2000 cycles from rest) and after the peak (D = 0.12, 3000 cycles from rest: cracked).
# Usage (from the repository root, on the host):
#   devenv/nacre-env run perf/run_polish_compare.sh [OUTDIR]   (default perf/results/polish)
# Writes OUTDIR/polish_compare.csv. Newton is capped at NACRE_NEWTON_MAX (20000) sweeps, annealing
# at NACRE_ANNEAL_MAX (300000) cycles; NACRE_POLISH_THREADS threads (default 1: robust on a shared
# machine).
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-perf/results/polish}"
mkdir -p "$out"
echo "[perf] building (preset openmp)"
cmake --preset openmp >/dev/null && cmake --build build/openmp -j2 --target nacre_perf_polish >/dev/null
export OMP_PROC_BIND=spread OMP_PLACES=threads
bin=build/openmp/perf/nacre_perf_polish
tmp="$out/.polish_compare.csv.tmp"
: > "$tmp"
th="--kokkos-num-threads=${NACRE_POLISH_THREADS:-1}"
first=1
for state in "0.03 2000" "0.12 3000"; do
  set -- $state
  for m in "fire,newton ${NACRE_NEWTON_MAX:-20000}" "anneal ${NACRE_ANNEAL_MAX:-300000}"; do
    read -r methods cap <<< "$m"
    "$bin" inputs/default.toml --load "$1" --cycles "$2" --methods "$methods" --max-iterations "$cap" "$th" \
      | if [ "$first" = 1 ]; then cat; else tail -n +2; fi >> "$tmp"
    first=0
  done
done
mv "$tmp" "$out/polish_compare.csv"
cat "$out/polish_compare.csv"
