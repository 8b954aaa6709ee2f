#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# device_run.sh — on a GPU machine, with binaries carried by carry_prebuilt.sh (built here by
# `devenv/nacre-env cuda-build`, plus optionally OpenMP builds renamed *_omp for the machine's
# CPU cores): the test suite's binaries on the GPU, then the dynamics and Monte Carlo
# benchmarks, GPU and CPU in one sitting. Every step has a time limit so the whole run fits one
# device call; everything lands in OUTDIR (CSV, logs, env.txt).
#
#   perf/gpu/device_run.sh BUNDLE OUTDIR [tests|bench|apptests|all]   (all: bench, tests until DEADLINE s (default 560), app tests)
#
# The test binaries read decks through the source path compiled into them (NACRE_SOURCE_DIR,
# the checkout they were built in): the script links that path to this checkout when it is
# missing (`NACRE_BUILT_AT`, default /work/main).
set -uo pipefail
B="$(realpath "$1")"; O="$(realpath -m "$2")"; what="${3:-all}"
mkdir -p "$O"
R="$B/run"
built_at="${NACRE_BUILT_AT:-/work/main}"
if [ ! -e "$built_at" ]; then mkdir -p "$(dirname "$built_at")" && ln -s "$PWD" "$built_at"; fi
{
  echo "date: $(date -u +%FT%TZ)"
  echo "revision: $(git rev-parse HEAD 2>/dev/null || echo unknown)"
  echo "cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //'), $(nproc) cores"
  nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm,clocks.max.mem --format=csv,noheader 2>&1 | sed 's/^/gpu: /'
  echo "binaries: $(ls "$B/bin" | tr '\n' ' ')"
} > "$O/env.txt"
cat "$O/env.txt"
t0=$(date +%s)
say() { echo "[device_run +$(( $(date +%s) - t0 ))s] $*" | tee -a "$O/device_run.log"; }
have() { [ -x "$B/bin/$1" ]; }


if [ "$what" = bench ] || [ "$what" = all ]; then
  export OMP_PROC_BIND=spread OMP_PLACES=threads
  if have nacre; then
    # every `nacre bench` figure first (README decks, scaled 100k / 1M / 4M bricks, UE / BE / BIE at
    # ratio 500, AES-CTR inside the run): perf/bench_all.sh, the same files as on any machine
    say "nacre bench: perf/bench_all.sh (sizes ${BENCH_SIZES:-100000,1000000,4000000})"
    # BENCH_BACKENDS for every bench (default cuda: the CUDA build also lists its host backends,
    # far too slow for the scaled specimens), BENCH_README_BACKENDS for the README decks (default
    # cuda,openmp: the GPU against the CPU in one process)
    timeout "${BENCH_ALL_TIMEOUT:-420}" perf/bench_all.sh --sizes "${BENCH_SIZES:-100000,1000000,4000000}" \
      --backends "${BENCH_BACKENDS:-cuda}" --readme-backends "${BENCH_README_BACKENDS:-cuda,openmp}" \
      "$R nacre" "$O/bench_all" >> "$O/bench.log" 2>&1 || say "  exit $?"
  fi
  sizes="${DYN_SIZES:-10000,50000,100000,200000}"
  for m in "" _omp; do
    have nacre_perf_dyn_step$m || continue
    for damp in none table42_mass table42; do
      say "dyn_step$m: UE, BE, BIE, damping $damp ($sizes bricks)"
      timeout 200 "$R" nacre_perf_dyn_step$m --bricks "$sizes" --methods ue,be,bie,bie_split --steps 50 --blocks 3 \
        --damping $damp --csv "$O/dyn_step${m}_$damp.csv" >> "$O/bench.log" 2>&1 || say "  exit $?"
    done
  done
  for m in "" _omp; do
    have nacre_perf_bie$m || continue
    n=50000; [ "$m" = _omp ] && n=5000
    say "bie$m speedup (Fig. 4.9): $n bricks, ratios 100, 500"
    timeout 150 "$R" nacre_perf_bie$m speedup --bricks $n --ratios 100,500 --bie-steps 100 --steps 1000 --safety 0.8 \
      --out "$O/bie_speedup$m.csv" >> "$O/bench.log" 2>&1 || say "  exit $?"
  done
  if have nacre_perf_bie; then
    say "bie timing: every J^-1 apply variant (50000, 200000 bricks, ratio 500)"
    timeout 120 "$R" nacre_perf_bie timing --sizes 50000,200000 --ratio 500 --steps 20 \
      --out "$O/bie_timing.csv" >> "$O/bench.log" 2>&1 || say "  exit $?"
  fi
  if have nacre_aes_bench; then
    say "AES-128 (nacre bitsliced) on the GPU"
    timeout 60 "$R" nacre_aes_bench --mode=nacre --max-size=1073741824 --min-time=0.3 > "$O/aes_bench.csv" 2>> "$O/bench.log" || say "  exit $?"
  fi
  if have nacre_perf_mc; then
    say "MC sweep on the GPU: 300k bricks, natural colouring"
    timeout 90 "$R" nacre_perf_mc --bricks 300000,1000000 --cycles 30 --repeats 3 --colouring natural \
      --csv "$O/mc_throughput.csv" >> "$O/bench.log" 2>&1 || say "  exit $?"
  fi
  if have nacre; then
    for d in dynamic_bie dynamic; do
      say "app: inputs/$d.toml on the GPU"
      s0=$SECONDS
      timeout 120 "$R" nacre "inputs/$d.toml" -q -o "/tmp/nacre_$d" --overwrite >> "$O/app.log" 2>&1
      say "  exit $? after $(( SECONDS - s0 )) s"
      mkdir -p "$O/app_$d" && cp /tmp/nacre_$d/*.csv /tmp/nacre_$d/*.json "$O/app_$d/" 2>/dev/null
    done
  fi
fi
if [ "$what" = tests ] || [ "$what" = all ]; then
  left=$(( ${DEADLINE:-560} - ($(date +%s) - t0) ))
  say "test binaries on the GPU (6 at a time, 2 host threads each, all within $left s)"
  : > "$O/tests_exit.txt"
  ls "$B/bin" | grep '^test_' | OMP_NUM_THREADS=2 timeout "$left" xargs -P 6 -I{} bash -c \
    '"$0" {} --reporter compact > "$1/{}.log" 2>&1; echo "{} exit $?" >> "$1/tests_exit.txt"' "$R" "$O"
  for t in $(ls "$B/bin" | grep '^test_'); do grep -q "^$t exit" "$O/tests_exit.txt" || echo "$t unfinished (deadline)" >> "$O/tests_exit.txt"; done
  sort "$O/tests_exit.txt" | tee -a "$O/device_run.log"
  for f in "$O"/test_*.log; do grep -v '^$' "$f" | tail -n 2 | sed "s|^|$(basename "$f" .log): |"; done > "$O/tests_summary.txt"
  tar czf "$O/test_logs.tar.gz" -C "$O" $(cd "$O" && ls test_*.log) tests_exit.txt && rm -f "$O"/test_*.log
  cat "$O/tests_summary.txt"
fi
if [ "$what" = apptests ] || [ "$what" = all ]; then
  # the end-to-end scripts of CTest (tests/app), with the carried app behind the path the test
  # binaries were built with (test_deck runs it too)
  exe="$built_at/build/cuda/src/nacre"
  if [ ! -x "$exe" ]; then mkdir -p "$(dirname "$exe")" && printf '#!/usr/bin/env bash\nexec %s nacre "$@"\n' "$R" > "$exe" && chmod +x "$exe"; fi
  for t in ${APPTESTS:-run_bie_deck_check run_dyn_checks run_app_checks}; do
    say "app test $t"
    s0=$SECONDS
    timeout "${APPTEST_TIMEOUT:-200}" bash "tests/app/$t.sh" "$exe" "$PWD" "/tmp/apptest_$t" > "$O/apptest_$t.log" 2>&1
    say "  exit $? after $(( SECONDS - s0 )) s: $(tail -n 1 "$O/apptest_$t.log")"
  done
fi
say "done"
