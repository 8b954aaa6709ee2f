#!/bin/bash
# one sequence, each run alone: Newton reference path, FIRE reference path, Newton again (same decks as the study)
# (out/bin/nacre-cc0b92c-env: cc0b92c built with environment switches for the trial runs; without them set, cc0b92c's code path)
D=perf/results/pareto_newton12/sequence; mkdir -p $D
TIMEFORMAT='%U %S %R'
run() { # tag binary deck
  mkdir -p $D/$1; { time devenv/nacre-env run env OMP_NUM_THREADS=1 $2 $3 -o $D/$1/run --overwrite > $D/$1/log.txt 2>&1; } 2> $D/$1/time.txt; echo "$1 $(cat $D/$1/time.txt)" >> $D/sequence.txt
}
S=perf/results/pareto_newton10
run newton-reference-1 build/openmp/src/nacre $S/newton-reference/deck.toml
run reference build/openmp/src/nacre $S/reference/deck.toml
run newton-reference-2 build/openmp/src/nacre $S/newton-reference/deck.toml
run newton-reference-cc0b92c out/bin/nacre-cc0b92c-env $S/newton-reference/deck.toml
echo done > out/s18/seq.done
