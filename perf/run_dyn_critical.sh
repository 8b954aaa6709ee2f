#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Critical step vs stiffness ratio (1, 10, 50, 100, 500) for UE and BE, with and without the
# Table 4.2 damping (Fig. 4.6); the UE/BE gap against sqrt(internal / brick stiffness).
# Usage (from the repository root, on the host):
#   devenv/nacre-env run perf/run_dyn_critical.sh [OUTDIR]   (default perf/results/dyn_critical)
# Specimen size NACRE_DYN_CRIT_BRICKS (1000), steps per bisection trial NACRE_DYN_CRIT_STEPS (2000),
# NACRE_DYN_CRIT_DAMPING (none,table).
# Writes OUTDIR/{dyn_critical.csv, dyn_critical.json, dyn_critical.png}.
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-perf/results/dyn_critical}"
mkdir -p "$out"
echo "[perf] building (preset openmp)"
cmake --preset openmp >/dev/null && cmake --build build/openmp -j2 --target nacre_perf_dyn_critical >/dev/null
export OMP_PROC_BIND=spread OMP_PLACES=threads
build/openmp/perf/nacre_perf_dyn_critical --bricks "${NACRE_DYN_CRIT_BRICKS:-1000}" --steps "${NACRE_DYN_CRIT_STEPS:-2000}" \
  --damping "${NACRE_DYN_CRIT_DAMPING:-none,table}" --csv "$out/dyn_critical.csv" \
  --kokkos-num-threads=2
python3 perf/plot_dyn_critical.py "$out"
