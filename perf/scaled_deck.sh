#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# The default deck's specimen (80 x 40, 3.5 x 1 bricks, notch 24: 920 bricks) scaled by s in both
# directions to about BRICKS bricks, with the load path's shape and displacements kept, run to
# FINAL, no intermediate dumps. Shared by perf/run_pareto.sh, perf/run_scaling.sh, perf/bench_all.sh.
#   perf/scaled_deck.sh BRICKS FINAL [study] > deck.toml        (run from the repository root)
# With "study": the settings the Pareto and scaling studies are measured on, pinned so that their
# tables stay comparable whatever the default deck sets (it was this deck's until 2026-12-03):
# relaxation = "monte-carlo", the adaptive load increments 0.01 (0.004 to 0.01) and predictor = true
# (the predictor suited to the relaxation).
set -euo pipefail
bricks="$1"; final="$2"; study="${3:-}"
read -r width height notch < <(python3 -c "
import math; s = math.sqrt($bricks / 920.0); print(f'{80*s:.1f} {40*s:.1f} {24*s:.1f}')")
pin=()
if [ "$study" = study ]; then
  pin=(-e 's/^relaxation = .*/relaxation = "monte-carlo"/' -e 's/^adaptive = .*/adaptive = true/'
       -e 's/^InitialLoadStepSize = .*/InitialLoadStepSize = 0.01/' -e 's/^MinLoadStepSize = .*/MinLoadStepSize = 0.004/'
       -e 's/^MaxLoadStepSize = .*/MaxLoadStepSize = 0.01/' -e 's/^predictor = .*/predictor = true/')
  grep -q '^relaxation = ' inputs/default.toml || pin+=(-e 's/^\[solver\]/[solver]\nrelaxation = "monte-carlo"/')
elif [ -n "$study" ]; then
  echo "scaled_deck.sh: the third argument is \"study\" or nothing, not \"$study\"" >&2; exit 2
fi
sed -e "s/^width = .*/width = $width/" -e "s/^height = .*/height = $height/" \
    -e "s/^notch_length = .*/notch_length = $notch/" -e "s/^final_displacement = .*/final_displacement = $final/" \
    -e "s/^DumpInter = .*/DumpInter = 0/" "${pin[@]}" inputs/default.toml
