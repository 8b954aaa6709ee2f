#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Chapter 4 experiments (issue 8), one command each:
#   perf/bie/run_bie_bench.sh critical|timing|speedup|speedup_damped|accuracy|accuracy_damped|fail|memory|all [OUTDIR]
# Builds nacre_perf_bie, runs the experiment into OUTDIR (default perf/results/bie), writes the
# CSV, the chart (PNG) and a JSON of the headline numbers (perf/bie/plot_bie.py), and the load
# average during the run (machine.txt). Sizes are modest on purpose (a shared 2-core machine);
# override with BIE_SIZES, BIE_BRICKS.
set -euo pipefail
cd "$(dirname "$0")/../.."
what=${1:-all}
out=${2:-perf/results/bie}
mkdir -p "$out"
run() { devenv/nacre-env run "$@"; }
run cmake --build build/openmp --target nacre_perf_bie -j2 >/dev/null
exe=build/openmp/perf/nacre_perf_bie
env="OMP_PROC_BIND=false OMP_WAIT_POLICY=passive"
note() { echo "$(date -u +%FT%TZ) $1: load average $(cut -d' ' -f1-3 /proc/loadavg), $(nproc) cores" >> "$out/machine.txt"; }

one() {
  case $1 in
  critical)
    note critical
    run env $env $exe critical --bricks "${BIE_BRICKS:-400}" --ratios 1,10,50,100,500 --steps 1000 \
      --out "$out/critical.csv" --kokkos-num-threads=2 ;;
  timing)
    note timing
    for nt in 1 2; do
      run env $env $exe timing --sizes "${BIE_SIZES:-1000,10000,50000}" --ratio 500 --steps 10 \
        --out "$out/timing_${nt}t.csv" --kokkos-num-threads=$nt
    done ;;
  speedup)
    note speedup
    run env $env $exe speedup --bricks "${BIE_BRICKS:-1000}" --ratios 1,100,500 --bie-steps 100 --steps 1000 \
      --out "$out/speedup.csv" --kokkos-num-threads=2 ;;
  speedup_damped)
    note speedup_damped
    run env $env $exe speedup --damped --bricks "${BIE_BRICKS:-1000}" --ratios 500 --bie-steps 1000 --steps 1000 \
      --out "$out/speedup_damped.csv" --kokkos-num-threads=2 ;;
  accuracy)
    note accuracy
    run env $env $exe accuracy --bricks "${BIE_BRICKS:-120}" --ratio 500 --steps 1000 --horizon 20 --levels 3 \
      --out "$out/accuracy.csv" --kokkos-num-threads=2 ;;
  accuracy_damped)
    note accuracy_damped
    run env $env $exe accuracy --damped --bricks "${BIE_BRICKS:-120}" --ratio 500 --steps 1000 --horizon 40 --levels 3 \
      --out "$out/accuracy_damped.csv" --kokkos-num-threads=2 ;;
  fail)
    note fail
    run env $env $exe fail --bricks "${BIE_BRICKS:-200}" --ratios 10,100,500 --steps 1000 --horizon 160 \
      --out "$out/fail.csv" --kokkos-num-threads=2 ;;
  memory)
    note memory
    run env $env $exe memory --sizes "${BIE_SIZES:-1000,10000,50000}" --ratio 500 --out "$out/memory.csv" \
      --kokkos-num-threads=1 ;;
  esac
  run python3 perf/bie/plot_bie.py "$out" "$1"
}

if [ "$what" = all ]; then
  for w in critical memory accuracy accuracy_damped fail speedup speedup_damped timing; do one $w; done
else
  one "$what"
fi
