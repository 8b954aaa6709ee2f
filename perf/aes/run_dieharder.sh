#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Statistical quality of nacre's generators with dieharder (Debian package).
#
#   devenv/nacre-env run perf/aes/run_dieharder.sh [--full] [--build DIR] [--gens "aes-ctr ..."] OUTDIR
#
# Streams each generator's raw output (nacre_rng_stream: AES-CTR, MT+AES, Philox, raw MT) as
# binary into `dieharder -g 200` (stdin_input_raw) and tabulates the p-values in
# OUTDIR/dieharder.csv and OUTDIR/dieharder.md (raw reports: OUTDIR/dieharder_<gen>.txt).
# Default: a fast subset of the battery (about a minute per generator, generators run two at
# a time); --full runs `dieharder -a` (all tests, hours for the four generators).
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
BUILD="$ROOT/build/openmp"
FULL=0
GENS="aes-ctr mt-aes philox mt"
# Fast subset: diehard birthdays, operm5, 32x32 and 6x8 ranks, bitstream, count-the-1s (stream),
# parking lot, 2d/3d spheres, squeeze, runs, craps; STS monobit, runs, serial; RGB bitdist
# (n = 1..4 via -n), DAB byte distribution, DCT, fill tree, monobit2.
TESTS="0 1 2 3 4 8 10 11 12 13 15 16 100 101 102 200 205 206 207 209"
while [ $# -gt 1 ]; do
  case "$1" in
    --full) FULL=1; shift ;;
    --build) BUILD="$2"; shift 2 ;;
    --gens) GENS="$2"; shift 2 ;;
    --tests) TESTS="$2"; shift 2 ;;
    *) echo "unknown option $1" >&2; exit 2 ;;
  esac
done
[ $# -eq 1 ] || { sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
OUT="$1"; mkdir -p "$OUT"
if [ -x "$BUILD/perf/nacre_rng_stream" ]; then STREAM="$BUILD/perf/nacre_rng_stream";
elif [ -x "$BUILD/nacre_rng_stream" ]; then STREAM="$BUILD/nacre_rng_stream";
else echo "nacre_rng_stream not found under $BUILD (build the perf targets, or pass --build)" >&2; exit 1; fi
command -v dieharder >/dev/null || { echo "dieharder not installed" >&2; exit 1; }
export OMP_PROC_BIND=false OMP_NUM_THREADS=1

run_gen() {
  local g="$1" f="$OUT/dieharder_$1.txt"
  : >"$f"
  if [ "$FULL" = 1 ]; then
    "$STREAM" --gen="$g" 2>/dev/null | dieharder -g 200 -a >>"$f" 2>&1 || true
  else
    for t in $TESTS; do
      local extra=""
      [ "$t" = 200 ] && extra="-n 2"
      # shellcheck disable=SC2086
      "$STREAM" --gen="$g" 2>/dev/null | dieharder -g 200 -d "$t" $extra >>"$f" 2>&1 || true
    done
  fi
  echo "[dieharder] $g done" >&2
}

start=$(date +%s)
pids=()
for g in $GENS; do
  run_gen "$g" &
  pids+=($!)
  if [ ${#pids[@]} -ge 2 ]; then wait "${pids[0]}"; pids=("${pids[@]:1}"); fi
done
wait
echo "[dieharder] $(( $(date +%s) - start )) s" >&2
python3 "$HERE/dieharder_table.py" "$OUT" $GENS
