#!/bin/bash
# one sequence, each run alone: Newton reference path, FIRE reference path, Newton again (same decks as the study)
D=perf/results/pareto_newton11; mkdir -p $D
TIMEFORMAT='%U %S %R'
run() { # tag binary deck
  mkdir -p $D/$1; { time devenv/nacre-env run env OMP_NUM_THREADS=1 $2 $3 -o $D/$1/run --overwrite > $D/$1/log.txt 2>&1; } 2> $D/$1/time.txt; echo "$1 $(cat $D/$1/time.txt)" >> $D/sequence.txt
}
S=perf/results/pareto_newton10
run newton-reference-1 build/openmp/src/nacre $S/newton-reference/deck.toml
run reference build/openmp/src/nacre $S/reference/deck.toml
run newton-reference-2 build/openmp/src/nacre $S/newton-reference/deck.toml
run newton-reference-877d3f6 out/bin/nacre-877d3f6 $S/newton-reference/deck.toml
echo done > out/s17/seq.done
