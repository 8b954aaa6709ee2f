#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Monte Carlo sweeps over MPI ranks on this machine (docs/scaling.md): strong scaling (100k
# bricks on 1, 2, 4 ranks), weak scaling (25k bricks per rank), each run checked bit for bit
# against one process; then the halo sizes of a 1M-brick specimen cut for 4 .. 1024 ranks, the
# input of the scaling model. One thread per rank (4 ranks oversubscribe a 2-core machine: an
# overhead and correctness measurement, not a speed-up). Inside the dev root:
#   devenv/nacre-env run perf/run_par_scaling.sh [OUT_DIR]        (default perf/results/par)
set -euo pipefail
out=${1:-perf/results/par}
bin=${NACRE_BUILD:-build/openmp}/perf/nacre_perf_par
[ -x "$bin" ] || { echo "run_par_scaling.sh: $bin not built (cmake --build build/openmp --target nacre_perf_par nacre_perf_par_io)" >&2; exit 2; }
mkdir -p "$out"
rm -f "$out/strong.csv" "$out/weak.csv" "$out/halo.csv"
# Open MPI refuses root without these; shared memory between ranks, no TCP probing
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_btl=self,sm
export OMP_NUM_THREADS=1 OMP_PROC_BIND=false OMP_WAIT_POLICY=passive
for np in 1 2 4; do
  mpiexec -n "$np" --oversubscribe "$bin" --bricks 100000 --cycles 10 --check --csv "$out/strong.csv"
done
for np in 1 2 4; do
  mpiexec -n "$np" --oversubscribe "$bin" --per-rank --bricks 25000 --cycles 10 --check --csv "$out/weak.csv"
done
# the outputs: gathering a 1M-brick run's dump and checkpoint to rank 0 against writing them
io_bin=${NACRE_BUILD:-build/openmp}/perf/nacre_perf_par_io
rm -f "$out/io.csv"
for np in 1 2; do
  mpiexec -n "$np" --oversubscribe "$io_bin" --bricks 1000000 --repeat 3 --csv "$out/io.csv" --dir "$out/io_scratch"
done
"$bin" --model-only --bricks 1000000 --ranks 1,4,16,64,256,1024 --csv "$out/halo.csv"
python3 perf/par_model.py "$out"
{ lscpu | grep -E '^Model name|^CPU\(s\)' ; mpiexec --version | head -1; } > "$out/machine.txt"
echo "run_par_scaling.sh: wrote $out/{strong,weak,halo,io}.csv"
