#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# runbook.sh — build nacre's benchmarks (MC, AES, dynamics) from the carried sources and run them, on a bare GPU
# machine (nvcc, CMake >= 3.22, Ninja and a host compiler; no HDF5, Eigen, toml++, CLI11, Catch2
# and no network). Everything lands in OUTDIR: CSV/JSON of each benchmark, the build and run
# logs, and env.txt (GPU, driver, compilers, revision). See docs/gpu.md.
#
#   runbook.sh [--cpu] [--quick] OUTDIR
#     --cpu    rehearsal without a GPU: Kokkos 4.6.01 OpenMP+Serial instead of CUDA
#     --quick  small sizes (rehearsal; minutes on 2 cores)
# Environment: NACRE_BUNDLE (default: two levels above this script's nacre/ checkout),
#   NACRE_CUDA_HOME (default /usr/local/cuda), NACRE_CUDA_ARCH (Kokkos arch, default HOPPER90),
#   NACRE_JOBS (default: all cores), NACRE_WORK (build folder, default OUTDIR/../nacre-gpu-work)
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd -P)"
SRC="$(cd "$HERE/../.." && pwd -P)"
BUNDLE="${NACRE_BUNDLE:-$(dirname "$SRC")}"
cpu=0; quick=0
while [ $# -gt 1 ]; do
  case "$1" in --cpu) cpu=1; shift ;; --quick) quick=1; shift ;; *) echo "unknown option $1" >&2; exit 2 ;; esac
done
[ $# -eq 1 ] || { sed -n '2,14p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
OUT="$(realpath -m "$1")"; mkdir -p "$OUT"
WORK="$(realpath -m "${NACRE_WORK:-$OUT/../nacre-gpu-work}")"; mkdir -p "$WORK"
export NACRE_JOBS="${NACRE_JOBS:-$(nproc)}"
export NACRE_CUDA_HOME="${NACRE_CUDA_HOME:-/usr/local/cuda}"
export NACRE_DEPS="$BUNDLE/deps" NACRE_OPT="$WORK/opt"
LOG="$OUT/runbook.log"; : > "$LOG"
say() { printf '[runbook %s] %s\n' "$(date -u +%T)" "$*" | tee -a "$LOG" >&2; }
timed() { local t0; t0=$(date +%s); "$@"; say "  ($(( $(date +%s) - t0 )) s)"; }

for t in cmake ninja c++; do command -v $t >/dev/null || { say "error: $t not found"; exit 1; }; done
[ -f "$NACRE_DEPS/kokkos-4.6.01.tar.gz" ] || { say "error: no $NACRE_DEPS/kokkos-4.6.01.tar.gz (unpack the bundle made by perf/gpu/pack.sh)"; exit 1; }
if [ $cpu = 0 ]; then
  [ -x "$NACRE_CUDA_HOME/bin/nvcc" ] || { say "error: no nvcc in $NACRE_CUDA_HOME/bin (or use --cpu)"; exit 1; }
  export PATH="$NACRE_CUDA_HOME/bin:$PATH"
  kokkos=kokkos-cuda; kk=kk-cuda
else
  kokkos=kokkos-host; kk=kk-host
fi
{
  echo "date: $(date -u +%FT%TZ)"; echo "host: $(hostname)"; echo "revision: $(cat "$SRC/REVISION" 2>/dev/null || git -C "$SRC" rev-parse HEAD 2>/dev/null || echo unknown)"
  echo "cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //'), $(nproc) cores"
  echo "c++: $(c++ --version | head -n1)"; echo "cmake: $(cmake --version | head -n1)"
  [ $cpu = 0 ] && { echo "nvcc: $(nvcc --version | tail -n2 | tr '\n' ' ')"; nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader 2>&1 | sed 's/^/gpu: /'; }
  echo "backend: $([ $cpu = 0 ] && echo "CUDA ($NACRE_CUDA_ARCH${NACRE_CUDA_ARCH:+}) + OpenMP" || echo "OpenMP (rehearsal, no GPU)")"
} > "$OUT/env.txt" 2>&1
cat "$OUT/env.txt" >> "$LOG"

say "1/3 Kokkos 4.6.01 + Kokkos Kernels 4.7.00 ($kokkos, $kk) into $NACRE_OPT"
timed bash "$SRC/devenv/build-deps.sh" "$kokkos" "$kk" 2>&1 | tee -a "$LOG"
K="$(bash "$SRC/devenv/build-deps.sh" prefix "$kokkos")"; KK="$(bash "$SRC/devenv/build-deps.sh" prefix "$kk")"

say "2/3 nacre benchmarks (NACRE_BENCHMARKS_ONLY: no HDF5, toml++, Catch2; Eigen from the bundle)"
cxx=(); [ $cpu = 0 ] && cxx=(-DCMAKE_CXX_COMPILER="$K/bin/nvcc_wrapper")
B="$WORK/build-$kokkos"
timed cmake -S "$SRC" -B "$B" -G Ninja -DCMAKE_BUILD_TYPE=Release -DNACRE_BENCHMARKS_ONLY=ON \
  -DKokkos_ROOT="$K" -DKokkosKernels_ROOT="$KK" "${cxx[@]}" \
  -DNACRE_CLI11_INCLUDE="$BUNDLE/vendor/include" -DNACRE_RANDOM123_INCLUDE="$BUNDLE/vendor/include" \
  -DNACRE_EIGEN_INCLUDE="$BUNDLE/vendor/include/eigen3" \
  >> "$LOG" 2>&1 || { tail -n 30 "$LOG"; say "configure failed"; exit 1; }
targets=(nacre_perf_mc nacre_aes_bench nacre_perf_dyn_step nacre_perf_bie)
grep -q nacre_perf_colouring "$B/build.ninja" && targets+=(nacre_perf_colouring)
timed cmake --build "$B" -j "$NACRE_JOBS" --target "${targets[@]}" >> "$LOG" 2>&1 \
  || { tail -n 40 "$LOG"; say "build failed"; exit 1; }

say "3/3 benchmarks -> $OUT"
export OMP_PROC_BIND=spread OMP_PLACES=threads
if [ $quick = 1 ]; then mc_sizes=10000,30000; col_sizes=10000,100000; cyc=10; aes_max=16M; dyn_sizes=2000,10000; dyn_steps=10
else mc_sizes=100000,1000000; col_sizes=100000,1000000; cyc=30; aes_max=1G; dyn_sizes=10000,100000,200000; dyn_steps=100; fi
# BE/UE against the bandwidth bound also at 1M bricks: 200k bricks move ~120 MB a step, ~25 us at
# 4.8 TB/s, the order of a few kernel launches; 1M (~600 MB) shows the bandwidth-bound regime.
# (The host model build at 1M is seconds since the tile list is sorted per window.)
dyn_step_sizes=$dyn_sizes; [ $quick = 1 ] || dyn_step_sizes=$dyn_sizes,1000000
if [ $cpu = 0 ]; then schedules=natural,balanced,largest-first,kokkos-d1; else schedules=tiles,natural,kokkos-d1; fi
[ -x "$B/perf/nacre_perf_colouring" ] || schedules=${schedules/,kokkos-d1/}
rm -f "$OUT"/mc_throughput.csv "$OUT"/colouring.csv "$OUT"/dyn_step.csv "$OUT"/bie_timing.csv
say "MC sweep throughput ($schedules; $mc_sizes bricks)"
timed "$B/perf/nacre_perf_mc" --bricks "$mc_sizes" --cycles "$cyc" --colouring "$schedules" --csv "$OUT/mc_throughput.csv" 2>&1 | tee -a "$LOG"
if [ -x "$B/perf/nacre_perf_colouring" ]; then
  say "colourings: colours, balance, time to colour ($col_sizes bricks)"
  timed "$B/perf/nacre_perf_colouring" --bricks "$col_sizes" --csv "$OUT/colouring.csv" \
    --colouring tiles,natural,largest-first,balanced,random,kokkos-d1,kokkos-d1-default 2>&1 | tee -a "$LOG"
fi
say "AES-128 (nacre bitsliced) and random-number throughput"
echo "kind,impl,threads,size_bytes,count,seconds,cpu_seconds,rate,rate_per_cpu,unit,rep" > "$OUT/aes_bench.csv"
timed "$B/perf/nacre_aes_bench" --mode=nacre --max-size="$aes_max" --min-time=0.5 2>>"$LOG" | tee -a "$OUT/aes_bench.csv"
timed "$B/perf/nacre_aes_bench" --mode=rng --min-time=0.5 2>>"$LOG" | tee -a "$OUT/aes_bench.csv"
say "dynamics: time per step, UE and BE, against a triad ($dyn_step_sizes bricks)"
timed "$B/perf/nacre_perf_dyn_step" --bricks "$dyn_step_sizes" --methods ue,be --steps "$dyn_steps" --blocks 2 \
  --csv "$OUT/dyn_step.csv" 2>&1 | tee -a "$LOG"
say "dynamics: time per step, UE, BE, BIE and each J^-1 apply variant ($dyn_sizes bricks, ratio 500)"
timed "$B/perf/nacre_perf_bie" timing --sizes "$dyn_sizes" --ratio 500 --steps "$dyn_steps" \
  --out "$OUT/bie_timing.csv" 2>&1 | tee -a "$LOG"
python3 - "$OUT" <<'PY' 2>>"$LOG" || say "python3 missing: no summary.json (the CSVs are complete)"
import csv, json, os, sys
out = sys.argv[1]
s = {"env": open(os.path.join(out, "env.txt")).read().splitlines()}
def rows(f):
    p = os.path.join(out, f)
    return list(csv.DictReader(open(p))) if os.path.exists(p) else []
s["mc_trials_per_second"] = [{k: r[k] for k in ("bricks", "implementation", "threads", "trials_per_second")} for r in rows("mc_throughput.csv")]
s["colouring"] = [{k: r[k] for k in ("bricks", "strategy", "colours", "balance", "seconds")} for r in rows("colouring.csv")]
aes = [r for r in rows("aes_bench.csv") if r["kind"] == "cipher"]
s["aes_best_gbit_per_s"] = max((float(r["rate"]) for r in aes), default=None)
s["rng"] = [r for r in rows("aes_bench.csv") if r["kind"] != "cipher"]
s["dyn_step"] = rows("dyn_step.csv")
s["bie_timing"] = rows("bie_timing.csv")
json.dump(s, open(os.path.join(out, "summary.json"), "w"), indent=1)
print(json.dumps({k: s[k] for k in ("aes_best_gbit_per_s",)}))
PY
say "done: $(ls "$OUT" | tr '\n' ' ')"
