#!/usr/bin/env bash
# The default deck's specimen (80 x 40, 3.5 x 1 bricks, notch 24: 920 bricks) scaled by s in both
# directions to about BRICKS bricks, with the load path's shape and displacements kept, run to
# FINAL, no intermediate dumps. Shared by perf/run_pareto.sh and perf/run_scaling.sh.
#   perf/scaled_deck.sh BRICKS FINAL > deck.toml        (run from the repository root)
set -euo pipefail
bricks="$1"; final="$2"
read -r width height notch < <(python3 -c "
import math; s = math.sqrt($bricks / 920.0); print(f'{80*s:.1f} {40*s:.1f} {24*s:.1f}')")
sed -e "s/^width = .*/width = $width/" -e "s/^height = .*/height = $height/" \
    -e "s/^notch_length = .*/notch_length = $notch/" -e "s/^final_displacement = .*/final_displacement = $final/" \
    -e "s/^DumpInter = .*/DumpInter = 0/" inputs/default.toml
