#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Speed against accuracy of the adaptive methods (§2.2; the dissertation: ~5x, the predictor
# the largest part). One deck, four variants, each run to the same final displacement:
#   fixed       fixed trial steps, fixed load increment, no predictor (the paper's non-adaptive)
#   +steps      adaptive trial step sizes (eq. 2.7, AdaptInter 50)
#   +load       and adaptive load increments (eq. 2.8, 2.9)
#   +predictor  and the position predictor (eq. 2.10, 2.11): everything on
#   per-brick   everything on, with one adaptive step size per brick
# Accuracy: the energy-displacement curve of each variant against the fixed run's (relative RMS
# difference at the fixed run's displacements). Run in the dev root:
#   devenv/nacre-env run perf/run_adaptive_study.sh [OUTDIR]     (default perf/results/adaptive)
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-perf/results/adaptive}"
mkdir -p "$out"
cmake --preset openmp >/dev/null && cmake --build --preset openmp --target nacre >/dev/null
base=inputs/adaptive_study.toml
variant() {  # name, then sed expressions
  local name="$1"; shift
  sed "$@" "$base" > "$out/deck_$name.toml"
  echo "[perf] adaptive study: $name"
  build/openmp/src/nacre "$out/deck_$name.toml" -o "$out/$name" -q
}
steps=(-e 's/^MinStepSize = .*/MinStepSize = 1e-6/' -e 's/^MaxStepSize = .*/MaxStepSize = 1e-3/'
       -e 's/^MinRotSize = .*/MinRotSize = 1e-7/' -e 's/^MaxRotSize = .*/MaxRotSize = 1e-3/'
       -e 's/^AdaptInter = .*/AdaptInter = 50/')
load=(-e 's/^MinLoadStepSize = .*/MinLoadStepSize = 0.001/' -e 's/^MaxLoadStepSize = .*/MaxLoadStepSize = 0.016/'
      -e 's/^adaptive = .*/adaptive = true/')
variant fixed -e ''
variant steps "${steps[@]}"
variant load "${steps[@]}" "${load[@]}"
variant predictor "${steps[@]}" "${load[@]}" -e 's/^predictor = .*/predictor = true/'
variant per-brick "${steps[@]}" "${load[@]}" -e 's/^predictor = .*/predictor = true/' \
  -e 's/^AdaptInter = .*/AdaptInter = 50\nstep_mode = "per-brick"/'
python3 perf/plot_adaptive_study.py "$out"
