#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Dynamics time per step vs bricks (UE, BE; 1 and 2 threads) against a Kokkos triad measured in
# the same process, bytes per step and per brick (shared / unshared element matrices).
# Usage (from the repository root, on the host):
#   devenv/nacre-env run perf/run_dyn_bench.sh [OUTDIR]      (default perf/results/dyn_step)
# Sizes: NACRE_DYN_SIZES (default 10000,50000,100000,200000), steps per block NACRE_DYN_STEPS, blocks
# NACRE_DYN_BLOCKS (best kept), methods NACRE_DYN_METHODS (default ue,be,bie; bie_dense = BIE with the dense
# J^-1 apply and full last iteration, the comparison for the undamped reduced form); pass them with env:
# devenv/nacre-env run env NACRE_DYN_SIZES=... perf/...
# Damping NACRE_DYN_DAMPING (default none; table42 = Rayleigh C from Table 4.2 by brick count, table42_mass = its alpha_d only; each
# method's step then found with that damping). Thread counts NACRE_DYN_THREADS (default "1 2"). NACRE_DYN_NATIVE=1 builds and runs the
# -march=native build of the kernels instead (build/native, CMake option NACRE_DYN_NATIVE=ON;
# numbers not bit-for-bit those of the default build; report it as a separate row).
# Writes OUTDIR/{dyn_step.csv, dyn_step_profile.csv (ms per step per kernel, one extra block per
# run with the Kokkos tool callbacks), dyn_step.json, dyn_step.png, machine.txt}.
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-perf/results/dyn_step}"
mkdir -p "$out"
echo "[perf] building (preset openmp)"
bdir=build/openmp
if [ "${NACRE_DYN_NATIVE:-0}" = 1 ]; then
  bdir=build/native
  cmake --preset openmp -B "$bdir" -DNACRE_DYN_NATIVE=ON -DNACRE_ENABLE_TESTS=OFF >/dev/null
else
  cmake --preset openmp >/dev/null
fi
cmake --build "$bdir" -j2 --target nacre_perf_dyn_step >/dev/null
export OMP_PROC_BIND=spread OMP_PLACES=threads
rm -f "$out/dyn_step.csv" "$out/dyn_step_profile.csv"
echo "$(date -u +%FT%TZ) start: load average $(cut -d' ' -f1-3 /proc/loadavg), $(nproc) cores, build $bdir" > "$out/machine.txt"
for nt in ${NACRE_DYN_THREADS:-1 2}; do
  echo "[perf] time per step, $nt thread(s)"
  "$bdir"/perf/nacre_perf_dyn_step --bricks "${NACRE_DYN_SIZES:-10000,50000,100000,200000}" \
    --methods "${NACRE_DYN_METHODS:-ue,be,bie}" --steps "${NACRE_DYN_STEPS:-100}" --blocks "${NACRE_DYN_BLOCKS:-3}" \
    --damping "${NACRE_DYN_DAMPING:-none}" \
    --csv "$out/dyn_step.csv" --profile-csv "$out/dyn_step_profile.csv" --kokkos-num-threads=$nt
done
echo "$(date -u +%FT%TZ) end: load average $(cut -d' ' -f1-3 /proc/loadavg)" >> "$out/machine.txt"
python3 perf/plot_dyn_bench.py "$out"
