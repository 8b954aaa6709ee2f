#!/usr/bin/env bash
# Polish methods against each other (issue 9 §0): from one Monte Carlo state of the default deck's
# specimen (same seed, same state for each method), FIRE and colour-swept block Newton run to
# 1e-3 ... 1e-8; cumulative time and iterations to each tolerance. Two states: elastic (D = 0.03,
# 2000 cycles from rest) and after the peak (D = 0.12, 3000 cycles from rest: cracked).
# Usage (from the repository root, on the host):
#   devenv/nacre-env run perf/run_polish_compare.sh [OUTDIR]   (default perf/results/polish)
# Writes OUTDIR/polish_compare.csv. Newton is capped at NACRE_NEWTON_MAX (20000) sweeps.
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-perf/results/polish}"
mkdir -p "$out"
echo "[perf] building (preset openmp)"
cmake --preset openmp >/dev/null && cmake --build build/openmp -j2 --target nacre_perf_polish >/dev/null
export OMP_PROC_BIND=spread OMP_PLACES=threads
bin=build/openmp/perf/nacre_perf_polish
tmp="$out/.polish_compare.csv.tmp"
"$bin" inputs/default.toml --load 0.03 --cycles 2000 --max-iterations "${NACRE_NEWTON_MAX:-20000}" --kokkos-num-threads=2 > "$tmp"
"$bin" inputs/default.toml --load 0.12 --cycles 3000 --max-iterations "${NACRE_NEWTON_MAX:-20000}" --kokkos-num-threads=2 | tail -n +2 >> "$tmp"
mv "$tmp" "$out/polish_compare.csv"
cat "$out/polish_compare.csv"
