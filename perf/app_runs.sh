# SPDX-License-Identifier: BSD-3-Clause
# Sourced by the studies that run the nacre app on many decks (perf/run_pareto.sh,
# perf/run_scaling.sh): why one file: the build, the timing of one run and the job pool are the
# same for both, and a fix to one (say, how a failed run is recorded) must reach the other.
#
#   app_build                 configure + build the app (preset openmp); sets APP (NACRE_APP, when
#                             set, names a binary to use instead: a copy that a rebuild beside a
#                             long study cannot change under it)
#   app_timed_run DIR [ARGS]  runs DIR/deck.toml on one thread (NACRE_APP_THREADS threads, when
#                             set) into DIR/run; writes DIR/log.txt, DIR/threads,
#                             DIR/exit_code, copies steps.csv and summary.json if there, and
#                             writes DIR/time.txt (user, system, wall seconds) last: its presence
#                             means the run is over (a failed run included)
#   app_pool JOBS FUNC ITEMS  FUNC ITEM for each item, JOBS at once

app_build() {
  if [ -n "${NACRE_APP:-}" ]; then APP="$NACRE_APP"; return 0; fi
  cmake --preset openmp >/dev/null && cmake --build --preset openmp --target nacre >/dev/null
  APP=build/openmp/src/nacre
}

app_timed_run() {
  local dir="$1" rc=0 TIMEFORMAT='%U %S %R' f
  shift
  # CPU seconds are robust on a shared machine; one thread, no binding (other jobs run beside).
  # More threads (NACRE_APP_THREADS) for a size one thread cannot finish in a session: then the
  # wall time is the figure (idle threads spin at Kokkos' barriers and count as CPU time).
  local threads="${NACRE_APP_THREADS:-1}"
  echo "$threads" > "$dir/threads"
  { time OMP_NUM_THREADS="$threads" OMP_PROC_BIND=false "$APP" "$dir/deck.toml" -o "$dir/run" --overwrite "$@" \
      > "$dir/log.txt" 2>&1 || rc=$?; } 2> "$dir/time.tmp"
  for f in steps.csv summary.json; do
    if [ -f "$dir/run/$f" ]; then cp "$dir/run/$f" "$dir/"; fi
  done
  echo "$rc" > "$dir/exit_code"
  mv "$dir/time.tmp" "$dir/time.txt"
}

app_pool() {
  local jobs="$1" func="$2" running=0 item
  shift 2
  for item in "$@"; do
    "$func" "$item" &
    running=$((running + 1))
    if [ "$running" -ge "$jobs" ]; then wait -n || true; running=$((running - 1)); fi
  done
  wait || true
}
