#!/bin/bash
# interleaved A/B of the reference path: new (HEAD build) and old (877d3f6), kp_timer on
mkdir -p ${OUT:-out/ab}; DECK=perf/results/pareto_newton10/newton-reference/deck.toml
TIMEFORMAT='%U %S %R'
for r in "$@"; do for b in new old; do
  if [ $b = new ]; then BIN=build/openmp/src/nacre; else BIN=out/bin/nacre-877d3f6; fi
  { time devenv/nacre-env run env OMP_NUM_THREADS=1 KOKKOS_TOOLS_LIBS=build/openmp/perf/libnacre_kp_timer.so $BIN $DECK -o ${OUT:-out/ab}/ab_$b$r --overwrite > ${OUT:-out/ab}/ab_$b$r.log 2>&1; } 2> ${OUT:-out/ab}/ab_$b$r.time
done; done
echo done > ${OUT:-out/ab}/ab.done
