#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Speed against accuracy at scale: one notched specimen of ~20k bricks (the default
# deck's geometry scaled up, same law, same load path shape), a converged reference, and a sweep
# of solver settings, each run to the same final displacement. Every run is timed in process CPU
# seconds (summary.json's cpu_seconds; one thread per run, so a shared machine does not distort
# it) and compared with the reference by perf/plot_pareto.py: RMS of the energy-displacement and
# force-displacement curves, peak force, and the displacement of the first rupture.
#
#   devenv/nacre-env run perf/run_pareto.sh [OUTDIR]        (default perf/results/pareto)
#   devenv/nacre-env run env NACRE_PARETO_VARIANTS=reference,default perf/run_pareto.sh OUT
#
# Environment: NACRE_PARETO_BRICKS (default 20000), NACRE_PARETO_FINAL (final displacement,
# default 0.16: past the peak, about 45 interfaces ruptured at 20k bricks), NACRE_PARETO_JOBS
# (runs at once, default 2), NACRE_PARETO_VARIANTS (names, default all, in the order below).
# A variant whose summary.json exists is not run again: the study resumes where it stopped.
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-perf/results/pareto}"
bricks="${NACRE_PARETO_BRICKS:-20000}"
final="${NACRE_PARETO_FINAL:-0.16}"
jobs="${NACRE_PARETO_JOBS:-2}"
mkdir -p "$out"
source perf/app_runs.sh
app_build

# the base deck: the study's pinned settings (Monte Carlo + FIRE polish, adaptive increments: the
# default deck's until 2026-12-03), so that every variant below means what it meant then
base="$out/base.toml"
perf/scaled_deck.sh "$bricks" "$final" study > "$base"

# name | what it changes (sed expressions on the base deck, which has the default deck's settings)
# (a variant setting solver keys drops the base's relaxation line: the built-in default is
# "monte-carlo", the base's, and a variant that names another relaxation must not name two)
solver_key() { echo "/^relaxation = /d;s/^\\[solver\\]/[solver]\\n$1/"; }
declare -A V
# The reference: fixed increments of 0.002 (the adaptive increments of 0.004-0.01 step over the
# peak), each converged to 1e-9 by FIRE alone, which ends every step it shares with the Monte
# Carlo path at 1e-9 (mc-1e-9) in the same state; checked by halving the increment and
# tightening the residual to 1e-10 (reference-check).
V[reference]="$(solver_key 'relaxation = "gradient"\nresidual_tolerance = 1e-9\npolish_iterations = 500000');s/^adaptive = .*/adaptive = false/;s/^MinLoadStepSize = .*/MinLoadStepSize = 0.002/;s/^MaxLoadStepSize = .*/MaxLoadStepSize = 0.002/;s/^InitialLoadStepSize = .*/InitialLoadStepSize = 0.002/"
V[reference-check]="$(solver_key 'relaxation = "gradient"\nresidual_tolerance = 1e-10\npolish_iterations = 500000');s/^adaptive = .*/adaptive = false/;s/^MinLoadStepSize = .*/MinLoadStepSize = 0.001/;s/^MaxLoadStepSize = .*/MaxLoadStepSize = 0.001/;s/^InitialLoadStepSize = .*/InitialLoadStepSize = 0.001/"
V[mc-1e-9]="$(solver_key 'residual_tolerance = 1e-9')"
V[monte-carlo]=""   # the base: Monte Carlo + FIRE polish, the default deck's settings until 2026-12-03
V[default]="@deck"  # the default deck's settings as they are now (relaxation = "auto", increments 0.002)
V[gradient-fire]="$(solver_key 'relaxation = "gradient"\npolish_iterations = 200000')"
V[gradient-fire-fixed]="$(solver_key 'relaxation = "gradient"\npolish_iterations = 200000');s/^adaptive = .*/adaptive = false/;s/^MinLoadStepSize = .*/MinLoadStepSize = 0.004/;s/^MaxLoadStepSize = .*/MaxLoadStepSize = 0.004/;s/^InitialLoadStepSize = .*/InitialLoadStepSize = 0.004/"
V[gradient-fire-fine]="$(solver_key 'relaxation = "gradient"\npolish_iterations = 200000');s/^adaptive = .*/adaptive = false/;s/^MinLoadStepSize = .*/MinLoadStepSize = 0.002/;s/^MaxLoadStepSize = .*/MaxLoadStepSize = 0.002/;s/^InitialLoadStepSize = .*/InitialLoadStepSize = 0.002/"
V[residual-1e-4]="$(solver_key 'residual_tolerance = 1e-4')"
V[residual-1e-8]="$(solver_key 'residual_tolerance = 1e-8')"
V[window]="$(solver_key 'convergence = "window"\npolish = "none"')"
V[window-loose]="$(solver_key 'convergence = "window"\npolish = "none"');s/^STOL = .*/STOL = 0.01/;s/^RTOL = .*/RTOL = 0.1/;s/^WindowSize = .*/WindowSize = 100/"
V[window-tight]="$(solver_key 'convergence = "window"\npolish = "none"');s/^STOL = .*/STOL = 0.0005/;s/^RTOL = .*/RTOL = 0.01/;s/^WindowSize = .*/WindowSize = 400/"
V[window-T1e-6]="$(solver_key 'convergence = "window"\npolish = "none"');s/^TEMP = .*/TEMP = 1e-6/"
V[T1e-6]="s/^TEMP = .*/TEMP = 1e-6/"
V[T1e-8]="s/^TEMP = .*/TEMP = 1e-8/"
V[fixed-load]="s/^adaptive = .*/adaptive = false/;s/^MinLoadStepSize = .*/MinLoadStepSize = 0.004/;s/^MaxLoadStepSize = .*/MaxLoadStepSize = 0.004/;s/^InitialLoadStepSize = .*/InitialLoadStepSize = 0.004/"
V[no-predictor]="s/^predictor = .*/predictor = false/"
V[fixed-trial-steps]="s/^AdaptInter = .*/AdaptInter = 0/"
V[per-brick]="$(solver_key 'step_mode = "per-brick"')"
# trust-region Newton (relaxation = "newton"), and Newton with Monte Carlo bursts ("auto")
V[newton-reference]="$(solver_key 'relaxation = "newton"\nresidual_tolerance = 1e-9');s/^adaptive = .*/adaptive = false/;s/^MinLoadStepSize = .*/MinLoadStepSize = 0.002/;s/^MaxLoadStepSize = .*/MaxLoadStepSize = 0.002/;s/^InitialLoadStepSize = .*/InitialLoadStepSize = 0.002/"
V[newton-reference-double]="$(solver_key 'relaxation = "newton"\nresidual_tolerance = 1e-9\nfactor_precision = "double"');s/^adaptive = .*/adaptive = false/;s/^MinLoadStepSize = .*/MinLoadStepSize = 0.002/;s/^MaxLoadStepSize = .*/MaxLoadStepSize = 0.002/;s/^InitialLoadStepSize = .*/InitialLoadStepSize = 0.002/"
V[newton]="$(solver_key 'relaxation = "newton"')"
V[newton-fixed]="$(solver_key 'relaxation = "newton"');s/^adaptive = .*/adaptive = false/;s/^MinLoadStepSize = .*/MinLoadStepSize = 0.004/;s/^MaxLoadStepSize = .*/MaxLoadStepSize = 0.004/;s/^InitialLoadStepSize = .*/InitialLoadStepSize = 0.004/"
V[newton-fine]="$(solver_key 'relaxation = "newton"');s/^adaptive = .*/adaptive = false/;s/^MinLoadStepSize = .*/MinLoadStepSize = 0.002/;s/^MaxLoadStepSize = .*/MaxLoadStepSize = 0.002/;s/^InitialLoadStepSize = .*/InitialLoadStepSize = 0.002/"
V[auto]="$(solver_key 'relaxation = "auto"')"
V[auto-fine]="$(solver_key 'relaxation = "auto"');s/^adaptive = .*/adaptive = false/;s/^MinLoadStepSize = .*/MinLoadStepSize = 0.002/;s/^MaxLoadStepSize = .*/MaxLoadStepSize = 0.002/;s/^InitialLoadStepSize = .*/InitialLoadStepSize = 0.002/"
order=(reference reference-check mc-1e-9 monte-carlo default gradient-fire gradient-fire-fixed gradient-fire-fine window residual-1e-4 fixed-load no-predictor T1e-6 T1e-8
       window-loose window-tight window-T1e-6 residual-1e-8 fixed-trial-steps per-brick
       newton-reference newton-reference-double newton newton-fixed newton-fine auto auto-fine)
[ -n "${NACRE_PARETO_VARIANTS:-}" ] && read -r -a order <<< "${NACRE_PARETO_VARIANTS//,/ }"

run_variant() {
  local name="$1" dir="$out/$1"
  [ -f "$dir/summary.json" ] && { echo "[pareto] $name: done already"; return 0; }
  [ -n "${V[$name]+x}" ] || { echo "[pareto] unknown variant $name" >&2; return 2; }
  mkdir -p "$dir"
  if [ "${V[$name]}" = "@deck" ]; then
    perf/scaled_deck.sh "$bricks" "$final" > "$dir/deck.toml"
  else
    sed -e "${V[$name]:-s/^//}" "$base" > "$dir/deck.toml"
  fi
  echo "[pareto] $name: start $(date +%T)"
  app_timed_run "$dir" -q
  # a run that ends without a summary (not converged: exit 4) still counts, with its rows
  [ -f "$dir/summary.json" ] || echo "{\"failed\": true, \"exit_code\": $(cat "$dir/exit_code")}" > "$dir/summary.json"
  echo "[pareto] $name: exit $(cat "$dir/exit_code") $(date +%T)"
}

app_pool "$jobs" run_variant "${order[@]}"
python3 perf/plot_pareto.py "$out"
