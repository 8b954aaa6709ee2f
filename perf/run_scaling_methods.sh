#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Time to the same converged load path against the number of bricks, one study per relaxation
# (perf/run_scaling.sh on the studies' pinned path, each step converged to residual 1e-6), and the
# exponents side by side (perf/plot_scaling.py --compare): which method scales how, and whether
# Newton's CG iteration count grows with N (it would call for a better preconditioner).
#
#   devenv/nacre-env run perf/run_scaling_methods.sh [OUTDIR]   (default perf/results/scaling_methods)
#
# Environment: NACRE_SCALING_METHODS (default monte-carlo,gradient,newton), NACRE_SCALING_SIZES
# (default 10000,30000,100000; the study of a method resumes: a size done is not run again, so a
# larger size can be added to one method later), NACRE_APP_THREADS (threads a run, default 1: a
# study on T > 1 threads goes to OUTDIR/METHOD-Tt and is timed in wall seconds, for sizes one
# thread cannot finish in a session), and run_scaling.sh's others.
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-perf/results/scaling_methods}"
methods="${NACRE_SCALING_METHODS:-monte-carlo,gradient,newton}"
export NACRE_SCALING_SIZES="${NACRE_SCALING_SIZES:-10000,30000,100000}"
threads="${NACRE_APP_THREADS:-1}"
suffix=""
[ "$threads" = 1 ] || suffix="-${threads}t"
for m in ${methods//,/ }; do
  NACRE_SCALING_RELAXATION="$m" perf/run_scaling.sh "$out/$m$suffix"
done
dirs=()
for d in "$out"/*/; do [ -f "$d/scaling.csv" ] && dirs+=("${d%/}"); done
python3 perf/plot_scaling.py --compare "$out" "${dirs[@]}"
