#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Scaling of the rigid-brick solver (the dissertation: ~N^1.5): total time to the
# same final displacement against the number of bricks, with the studies' pinned settings
# (perf/scaled_deck.sh ... study: adaptive increments, Monte Carlo unless
# NACRE_SCALING_RELAXATION says otherwise), on the default deck's specimen scaled up. Each run on one
# thread, timed in CPU seconds (robust on a shared machine; with perf/app_runs.sh's
# NACRE_APP_THREADS > 1, in wall seconds, and the study should go to its own OUTDIR: plot_scaling
# refuses one that mixes thread counts); initialisation (specimen,
# interfaces, colouring) is the first log line's time and is reported separately.
# perf/plot_scaling.py fits time = a N^p on the runs and draws the log-log chart.
#
#   devenv/nacre-env run perf/run_scaling.sh [OUTDIR]        (default perf/results/scaling)
#
# Environment: NACRE_SCALING_SIZES (default 5000,10000,20000,40000,80000), NACRE_SCALING_FINAL
# (default 0.06: six load steps, before the first rupture, so every size does the same work per
# brick), NACRE_SCALING_JOBS (runs at once, default 1), NACRE_SCALING_RELAXATION (the
# relaxation: monte-carlo (the study's), gradient, newton, auto; summary.json's cg_iterations gives
# the CG work against N). A size whose time.txt exists is skipped.
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-perf/results/scaling}"
sizes="${NACRE_SCALING_SIZES:-5000,10000,20000,40000,80000}"
final="${NACRE_SCALING_FINAL:-0.06}"
jobs="${NACRE_SCALING_JOBS:-1}"
mkdir -p "$out"
source perf/app_runs.sh
app_build

run_size() {
  local n="$1" dir="$out/n$1"
  [ -f "$dir/time.txt" ] && { echo "[scaling] $n: done already"; return 0; }
  mkdir -p "$dir"
  perf/scaled_deck.sh "$n" "$final" study > "$dir/deck.toml"
  if [ -n "${NACRE_SCALING_RELAXATION:-}" ]; then
    sed -i "s/^relaxation = .*/relaxation = \"$NACRE_SCALING_RELAXATION\"/" "$dir/deck.toml"
  fi
  echo "[scaling] $n bricks: start $(date +%T)"
  app_timed_run "$dir"
  echo "[scaling] $n bricks: exit $(cat "$dir/exit_code") $(date +%T)"
}

app_pool "$jobs" run_size ${sizes//,/ }
python3 perf/plot_scaling.py "$out"
