#!/usr/bin/env bash
# Throughput of nacre's bitsliced AES-128 against OpenSSL, and of the random-number generators,
# in one run on one machine:
#
#   devenv/nacre-env run perf/aes/run_aes_bench.sh [--max-size 1G] [--min-time 0.5] [--build DIR] OUTDIR
#
#   * nacre's AES-128-ECB, 1 and 2 threads (--kokkos-num-threads), 64 KiB .. max-size buffers;
#   * OpenSSL AES-128-ECB (EVP, one thread) with AES-NI and with AES-NI masked off through
#     OPENSSL_ia32cap="~0x200000200000000" (AES-NI and PCLMULQDQ capability bits cleared) in
#     a child process;
#   * random doubles per second: Random123 Philox4x32-10, nacre's philox, aes-ctr and mt-aes
#     sources (4 doubles per stream and draw, 2^20 streams), 1 and 2 threads.
# Writes OUTDIR/aes_bench.csv, aes_bench.json, aes_bench.md and the chart aes_bench.png.
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
BUILD="$ROOT/build/openmp"
MAX=1G
MINT=0.5
while [ $# -gt 1 ]; do
  case "$1" in
    --max-size) MAX="$2"; shift 2 ;;
    --min-time) MINT="$2"; shift 2 ;;
    --build) BUILD="$2"; shift 2 ;;
    *) echo "unknown option $1" >&2; exit 2 ;;
  esac
done
[ $# -eq 1 ] || { sed -n '2,16p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
OUT="$1"; mkdir -p "$OUT"
if [ -x "$BUILD/perf/nacre_aes_bench" ]; then BENCH="$BUILD/perf/nacre_aes_bench";
elif [ -x "$BUILD/nacre_aes_bench" ]; then BENCH="$BUILD/nacre_aes_bench";
else echo "nacre_aes_bench not found under $BUILD (build the perf targets, or pass --build)" >&2; exit 1; fi
export OMP_PROC_BIND=spread OMP_PLACES=cores
unset OPENSSL_ia32cap
CSV="$OUT/aes_bench.csv"
LOG="$OUT/aes_bench.log"
echo "kind,impl,threads,size_bytes,count,seconds,rate,unit" >"$CSV"
: >"$LOG"
run() { echo "+ $*" >>"$LOG"; "$@" 2>>"$LOG" | tee -a "$CSV"; }
S=(--max-size="$MAX" --min-time="$MINT")
run "$BENCH" --mode=nacre "${S[@]}" --kokkos-num-threads=1
run "$BENCH" --mode=nacre "${S[@]}" --kokkos-num-threads=2
run "$BENCH" --mode=openssl --label=openssl-aesni "${S[@]}"
run env OPENSSL_ia32cap="~0x200000200000000" "$BENCH" --mode=openssl --label=openssl-no-aesni "${S[@]}"
run "$BENCH" --mode=rng --min-time="$MINT" --kokkos-num-threads=1
run "$BENCH" --mode=rng --min-time="$MINT" --kokkos-num-threads=2
{
  echo "cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //')"
  echo "cores: $(nproc)"
  echo "flags: $(grep -m1 '^flags' /proc/cpuinfo | grep -o 'avx512f\|avx2\|aes\|vaes\|gfni' | sort -u | tr '\n' ' ')"
} >"$OUT/machine.txt"
python3 "$HERE/plot_aes_bench.py" "$OUT"
