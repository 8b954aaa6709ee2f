#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Time split of a Monte Carlo run by phase (sweep, energy, random numbers), once per generator
# (philox, aes-ctr, mt-aes), from nacre's fenced phase timers (the same phases are Kokkos Tools
# regions nacre::mc::sweep / energy / rng). Run in the dev root:
#   devenv/nacre-env run perf/run_time_split.sh [OUTDIR]     (default perf/results/timesplit)
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-perf/results/timesplit}"
mkdir -p "$out"
cmake --preset openmp >/dev/null && cmake --build --preset openmp --target nacre >/dev/null
for g in philox aes-ctr mt-aes; do
  sed "s/^generator = .*/generator = \"$g\"/" inputs/timesplit.toml > "$out/deck_$g.toml"
  echo "[perf] time split with generator $g"
  build/openmp/src/nacre "$out/deck_$g.toml" -o "$out/$g" -q
done
python3 perf/plot_time_split.py "$out"
