#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Throughput of nacre's bitsliced AES-128 against OpenSSL, and of the random-number generators,
# in one run on one machine:
#
#   devenv/nacre-env run perf/aes/run_aes_bench.sh [--max-size 1G] [--min-time 0.5] [--reps 5]
#                                                   [--build DIR] OUTDIR
#
#   1. size sweep (kind cipher), 64 KiB .. max-size buffers: nacre's AES-128-ECB on 1 and 2
#      threads (--kokkos-num-threads); OpenSSL AES-128 (EVP, one thread) ECB with AES-NI, and
#      ECB and CTR with AES-NI masked off by OPENSSL_ia32cap="~0x200000200000000" (AES-NI and
#      PCLMULQDQ capability bits cleared: OpenSSL then runs its bitsliced bsaes/vpaes code);
#   2. interleaved comparison (kind compare), --reps rounds, each round running every
#      implementation once on an 8 MiB buffer for 1 s: nacre 1 and 2 threads, the three OpenSSL
#      variants in-process, and `openssl speed -evp` (16 KiB blocks) for the same three; the
#      summary takes per-round ratios (nacre / OpenSSL in the same round) and their median, so
#      the machine's other users move numerator and denominator together;
#   3. the bare cipher core (nacre_aes_core_bench, one thread, no Kokkos kernel, L2-resident):
#      the build's path against the portable transposition, and the phases, --reps rounds;
#   4. random doubles per second: Random123 Philox4x32-10, nacre's philox, aes-ctr and mt-aes
#      sources (4 doubles per stream and draw, 2^20 streams), 1 and 2 threads.
# Rates are per wall second and per CPU second of the process (columns rate, rate_per_cpu);
# OpenMP threads wait passively (OMP_WAIT_POLICY=passive). machine.txt records the load average.
# Writes OUTDIR/aes_bench.csv, aes_core.csv, aes_bench.json, aes_bench.md, aes_bench.log,
# machine.txt and the chart aes_bench.png.
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
BUILD="$ROOT/build/openmp"
MAX=1G
MINT=0.5
REPS=5
while [ $# -gt 1 ]; do
  case "$1" in
    --max-size) MAX="$2"; shift 2 ;;
    --min-time) MINT="$2"; shift 2 ;;
    --reps) REPS="$2"; shift 2 ;;
    --build) BUILD="$2"; shift 2 ;;
    *) echo "unknown option $1" >&2; exit 2 ;;
  esac
done
[ $# -eq 1 ] || { sed -n '2,24p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
OUT="$1"; mkdir -p "$OUT"
if [ -x "$BUILD/perf/nacre_aes_bench" ]; then BENCH="$BUILD/perf/nacre_aes_bench";
elif [ -x "$BUILD/nacre_aes_bench" ]; then BENCH="$BUILD/nacre_aes_bench";
else echo "nacre_aes_bench not found under $BUILD (build the perf targets, or pass --build)" >&2; exit 1; fi
# passive: a thread that reaches a barrier first sleeps instead of spinning, so on a shared
# machine the waiting is not counted as CPU time of the cipher (and the other thread can run).
export OMP_PROC_BIND=spread OMP_PLACES=cores OMP_WAIT_POLICY=passive
unset OPENSSL_ia32cap
NOAESNI="~0x200000200000000"
CSV="$OUT/aes_bench.csv"
LOG="$OUT/aes_bench.log"
LOAD_START="$(cut -d' ' -f1-3 /proc/loadavg)"
echo "kind,impl,threads,size_bytes,count,seconds,cpu_seconds,rate,rate_per_cpu,unit,rep" >"$CSV"
: >"$LOG"
run() { echo "+ $*" >>"$LOG"; "$@" 2>>"$LOG" | tee -a "$CSV"; }

# `openssl speed -evp CIPHER` on 16 KiB blocks as a CSV row (kind compare); its k = 1000 bytes.
speed() {  # speed LABEL CIPHER REP [env...]
  local label="$1" cipher="$2" rep="$3"; shift 3
  echo "+ $* openssl speed -seconds 1 -bytes 16384 -evp $cipher" >>"$LOG"
  local line
  line="$(env "$@" openssl speed -seconds 1 -bytes 16384 -evp "$cipher" 2>>"$LOG" | tail -1)"
  echo "$line" >>"$LOG"
  echo "$line" | awk -v l="$label" -v r="$rep" '{ v = $2; sub(/k$/, "", v);
    g = v * 1000 * 8 / 1e9; printf "compare,%s,1,16384,0,1,1,%.6g,%.6g,Gbit/s,%d\n", l, g, g, r }' |
    tee -a "$CSV"
}

# 1. Size sweep.
S=(--max-size="$MAX" --min-time="$MINT")
run "$BENCH" --mode=nacre "${S[@]}" --kokkos-num-threads=1
run "$BENCH" --mode=nacre "${S[@]}" --kokkos-num-threads=2
run "$BENCH" --mode=openssl --label=openssl-aesni-ecb "${S[@]}"
run env OPENSSL_ia32cap="$NOAESNI" "$BENCH" --mode=openssl --cipher=ecb --label=openssl-no-aesni-ecb "${S[@]}"
run env OPENSSL_ia32cap="$NOAESNI" "$BENCH" --mode=openssl --cipher=ctr --label=openssl-no-aesni-ctr "${S[@]}"

# 2. Interleaved comparison at one size.
C=(--kind=compare --min-size=8M --max-size=8M --min-time=1)
for rep in $(seq 1 "$REPS"); do
  run "$BENCH" --mode=nacre "${C[@]}" --rep="$rep" --kokkos-num-threads=1
  run env OPENSSL_ia32cap="$NOAESNI" "$BENCH" --mode=openssl --cipher=ctr --label=openssl-no-aesni-ctr "${C[@]}" --rep="$rep"
  run env OPENSSL_ia32cap="$NOAESNI" "$BENCH" --mode=openssl --cipher=ecb --label=openssl-no-aesni-ecb "${C[@]}" --rep="$rep"
  run "$BENCH" --mode=openssl --cipher=ecb --label=openssl-aesni-ecb "${C[@]}" --rep="$rep"
  run "$BENCH" --mode=nacre "${C[@]}" --rep="$rep" --kokkos-num-threads=2
  speed speed-no-aesni-ctr aes-128-ctr "$rep" OPENSSL_ia32cap="$NOAESNI"
  speed speed-no-aesni-ecb aes-128-ecb "$rep" OPENSSL_ia32cap="$NOAESNI"
  speed speed-aesni-ecb aes-128-ecb "$rep"
done

# 3. The bare cipher core on one thread (no kernel): build path, portable transposition, phases.
CORE="$(dirname "$BENCH")/nacre_aes_core_bench"
if [ -x "$CORE" ]; then
  echo "+ $CORE --rounds=$REPS" >>"$LOG"
  "$CORE" --rounds="$REPS" 2>>"$LOG" >"$OUT/aes_core.csv"
fi

# 4. Random-number generators.
run "$BENCH" --mode=rng --min-time="$MINT" --kokkos-num-threads=1
run "$BENCH" --mode=rng --min-time="$MINT" --kokkos-num-threads=2
{
  echo "cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //') (family $(grep -m1 '^cpu family' /proc/cpuinfo | cut -d: -f2 | tr -d ' '), model $(grep -m1 '^model[[:space:]]*:' /proc/cpuinfo | cut -d: -f2 | tr -d ' '))"
  echo "cores: $(nproc)"
  echo "load average (1/5/15 min) at start: $LOAD_START, at end: $(cut -d' ' -f1-3 /proc/loadavg)"
  echo "flags: $(grep -m1 '^flags' /proc/cpuinfo | grep -ow 'avx512f\|avx512bw\|avx512vbmi\|avx2\|aes\|vaes\|gfni' | sort -u | tr '\n' ' ')"
  echo "openssl: $(openssl version)"
  echo "compiler: $(c++ --version | head -1)"
  echo "layout: $(grep -m1 'nacre AES layout' "$LOG" | sed 's/^nacre AES layout: //')"
} >"$OUT/machine.txt"
python3 "$HERE/plot_aes_bench.py" "$OUT"
