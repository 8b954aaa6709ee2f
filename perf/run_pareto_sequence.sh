#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# One sequence of lone runs on the Pareto study's reference path (docs/speed_accuracy.md): this
# build's Newton, FIRE, this build's Newton again, then a base build's Newton, one after another
# on one thread each, so that FIRE / Newton is a ratio of runs that met the same machine. (The
# study itself runs FIRE beside the Newton variants; this is its check with nothing beside.)
#
#   perf/run_pareto_sequence.sh OUT BASE_NACRE BASE_TAG [DECKS]
#
# DECKS: the folder with newton-reference/deck.toml and reference/deck.toml, e.g. the output of
# `NACRE_PARETO_VARIANTS=reference,newton-reference perf/run_pareto.sh DIR`. Default: the decks of
# the study docs/speed_accuracy.md quotes (perf/results/pareto_newton10, run of 2b386fc), taken
# from git history (the tree keeps no per-run folders: perf/README.md, "Kept results").
# NACRE_APP: this build's binary (default build/openmp/src/nacre).
# Writes OUT/<run>/{log.txt,time.txt,run/} and appends "run user_s sys_s wall_s" to
# OUT/sequence.txt; runs from the host through devenv/nacre-env.
set -euo pipefail
[ $# -ge 3 ] || { echo "usage: $0 OUT BASE_NACRE BASE_TAG [DECKS]" >&2; exit 2; }
out="$1" base="$2" tag="$3" decks="${4:-}"
if [ -z "$decks" ]; then
  decks="$(mktemp -d)"
  for r in newton-reference reference; do
    mkdir -p "$decks/$r"
    git show "2b386fc:perf/results/pareto_newton10/$r/deck.toml" > "$decks/$r/deck.toml"
  done
fi
app="${NACRE_APP:-build/openmp/src/nacre}"
for f in "$decks/newton-reference/deck.toml" "$decks/reference/deck.toml" "$app" "$base"; do
  [ -e "$f" ] || { echo "$0: $f: not found" >&2; exit 2; }
done
mkdir -p "$out"
TIMEFORMAT='%U %S %R'
run() {  # name binary deck
  mkdir -p "$out/$1"
  { time devenv/nacre-env run env OMP_NUM_THREADS=1 "$2" "$3" -o "$out/$1/run" --overwrite > "$out/$1/log.txt" 2>&1; } \
    2> "$out/$1/time.txt"
  echo "$1 $(cat "$out/$1/time.txt")" >> "$out/sequence.txt"
}
run newton-reference-1 "$app" "$decks/newton-reference/deck.toml"
run reference "$app" "$decks/reference/deck.toml"
run newton-reference-2 "$app" "$decks/newton-reference/deck.toml"
run "newton-reference-$tag" "$base" "$decks/newton-reference/deck.toml"
