#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Hostile-user checks of the nacre executable: every case states what must hold.
#   run_robustness_checks.sh NACRE_EXE SOURCE_DIR WORK_DIR
# Cases: command line (shell injection, --kokkos-* values, a directory as deck), absurd decks
# (refused in < 1 s, nothing created), restart refusals (other deck, corrupt checkpoint; nothing
# deleted), stray files, restart into another directory, a failed write (injected, and a real
# full tmpfs where a private mount namespace is available), SIGTERM/SIGINT mid-run.
set -uo pipefail
exe="$1"; src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"; cd "$work"
source "$src/tests/app/checks_lib.sh"  # ok, bad, expect, state
tiny="$src/tests/app/tiny.toml"
cp "$tiny" tiny.toml
sed 's/^final_displacement = .*/final_displacement = 0.024/' tiny.toml > long.toml

# ---- 4. command line
"$exe" tiny.toml -o "x'; touch INJECTED; '" -q > /dev/null 2>&1
if [ -e INJECTED ] || [ -e "$src/INJECTED" ]; then bad "shell injection through -o created INJECTED"; else ok "-o \"x'; touch INJECTED; '\" created nothing"; fi
[ -f "x'; touch INJECTED; '/crack.png" ] && ok "charts written into the odd directory name" || bad "charts missing in the odd directory"
for v in abc 0 -2 "" 1x; do expect 2 "kokkos-num-threads" "$exe" tiny.toml "--kokkos-num-threads=$v" -q; done
expect 2 "is a directory" "$exe" "$work" -q
expect 2 "cannot open" "$exe" "$work/missing.toml" -q

# ---- 3. absurd decks: refused from the deck alone, in under a second, nothing written
absurd() {  # NAME PATTERN SED-EXPRESSION...
  local name="$1" pat="$2"; shift 2
  sed "$@" tiny.toml | sed "s#^directory = .*#directory = \"absurd_$name\"#" > "absurd_$name.toml"
  local t0 t1; t0=$(date +%s%N)
  expect 2 "$pat" "$exe" "absurd_$name.toml" -q
  t1=$(date +%s%N)
  local ms=$(( (t1 - t0) / 1000000 ))
  if [ "$ms" -lt 1000 ]; then ok "absurd_$name refused in $ms ms"; else bad "absurd_$name took $ms ms (>= 1 s)"; fi
  [ -e "absurd_$name" ] && bad "absurd_$name created its output directory" || true
}
absurd huge 'absurd_huge.toml:[0-9]+: geometry.brick_(width|height): .*max_bricks' \
  -e 's/^width = .*/width = 1e6/' -e 's/^height = .*/height = 1e6/' -e 's/^brick_width = .*/brick_width = 1.0/' -e 's/^notch_length = .*/notch_length = 1.0/'
absurd wide 'absurd_wide.toml:[0-9]+: geometry.width: .*outside \[1e-100, 1e100\]' -e 's/^width = .*/width = 1e300/'
absurd tiny_brick 'absurd_tiny_brick.toml:[0-9]+: geometry.brick_width: .*outside' -e 's/^brick_width = .*/brick_width = 1e-300/'
absurd denormal 'absurd_denormal.toml:[0-9]+: geometry.brick_height: ' -e 's/^brick_height = .*/brick_height = 4e-320/'
absurd endless 'absurd_endless.toml:[0-9]+: load.InitialLoadStepSize: .*max_load_steps' -e 's/^InitialLoadStepSize = .*/InitialLoadStepSize = 1e-12/'
absurd rows 'absurd_rows.toml:[0-9]+: geometry.driven_rows: ' -e 's/^notch_length = .*/notch_length = 7.0\ndriven_rows = 5/'
# a wall turned by 90 degrees in a specimen lower than a brick is long: every brick touches the
# top or the bottom edge (refused after building the wall, which takes milliseconds)
absurd nofree 'absurd_nofree.toml:[0-9]+: geometry: the specimen has [0-9]+ bricks and none is free' \
  -e 's/^height = .*/height = 3.4\nangle = 90.0/' -e 's/^notch_length = .*/notch_length = 0.0/'
# a limit is raised by its key: the same deck with [limits] max_bricks passes the estimate check
{ cat absurd_huge.toml; printf '\n[limits]\nmax_bricks = 1e13\nmax_memory_gib = 1e8\n'; } > raised.toml
if "$exe" raised.toml --check > /dev/null 2>&1; then ok "[limits] max_bricks raises the brick limit (--check passes)"; else bad "[limits] max_bricks did not raise the limit"; fi

# ---- a run to restart from
"$exe" tiny.toml -o a -q > /dev/null 2>&1 || bad "tiny run failed"
before=$(state a)
# ---- 2. restart refusals, and nothing in the output directory deleted or changed
sed 's/^k = 100.0/k = 120.0/' tiny.toml > k.toml
sed 's/^seed = 5/seed = 6/' tiny.toml > seed.toml
expect 2 "different deck.*mortar.k = 100 in the checkpoint, 120" "$exe" k.toml -o a -q --restart a/checkpoint.h5
expect 2 "different deck.*random.seed = 5 in the checkpoint, 6" "$exe" seed.toml -o a -q --restart a/checkpoint.h5
expect 2 "final_displacement.*--extend" "$exe" long.toml -o a -q --restart a/checkpoint.h5
expect 2 "not a nacre checkpoint" "$exe" tiny.toml -o a -q --restart a/mesh.h5
expect 2 "unreadable checkpoint" "$exe" tiny.toml -o a -q --restart a/steps.csv
cp a/checkpoint.h5 good.h5
python3 - <<'PY'
import shutil
import h5py
import numpy as np
def flip(name, fn):
    shutil.copy("good.h5", name)
    with h5py.File(name, "r+") as h:
        fn(h)
def pose_bit(h):
    p = h["/arrays/pose"][:]
    b = p.view(np.uint64)
    b[5] ^= np.uint64(1 << 40)
    h["/arrays/pose"][:] = b.view(np.float64)
flip("flip_pose.h5", pose_bit)
flip("flip_step.h5", lambda h: h.attrs.modify("step", np.int64(h.attrs["step"]) ^ np.int64(1 << 31)))
flip("nan_pose.h5", lambda h: h["/arrays/pose"].__setitem__(4, np.nan))
data = bytearray(open("good.h5", "rb").read())
data[len(data) // 2] ^= 0x10
open("flip_raw.h5", "wb").write(data)
open("truncated.h5", "wb").write(open("good.h5", "rb").read()[:1000])
PY
for f in flip_pose flip_step nan_pose flip_raw; do
  expect 2 "checksum mismatch|unreadable" "$exe" tiny.toml -o a -q --restart "$f.h5"
done
expect 2 "unreadable" "$exe" tiny.toml -o a -q --restart truncated.h5
[ "$(state a)" == "$before" ] && ok "refused restarts deleted and changed nothing in a/" || bad "a refused restart changed a/"
"$exe" tiny.toml --check --restart a/checkpoint.h5 > /dev/null && ok "--check --restart validates a good checkpoint" || bad "--check --restart refused a good checkpoint"

# ---- 5. stray files: dump_final.h5 and backups are ignored, stale temporaries removed
touch a/dump_final.h5 a/dump_7.h5.bak a/.steps.csv.tmp999999
expect 0 "" "$exe" tiny.toml -o a -q --restart a/checkpoint.h5
[ -e a/.steps.csv.tmp999999 ] && bad "stale temporary not removed" || ok "stale temporary .steps.csv.tmp999999 removed"
[ -e a/dump_final.h5 ] && [ -e a/dump_7.h5.bak ] && ok "dump_final.h5 and dump_7.h5.bak left alone" || bad "stray files removed"
rm -f a/dump_final.h5 a/dump_7.h5.bak

# ---- 2. restart into another directory: its own mesh.h5, full steps.csv, equal to a direct run
expect 0 "" "$exe" long.toml -o b -q --restart a/checkpoint.h5 --extend
"$exe" long.toml -o direct -q > /dev/null 2>&1
if diff <(cut -d, -f1-12 b/steps.csv) <(cut -d, -f1-12 direct/steps.csv) > /dev/null; then ok "restart into b/ equals the direct run"; else bad "restart into b/ differs from the direct run"; fi
python3 "$src/tests/app/check_outputs.py" b > /dev/null && ok "b/ outputs consistent (own mesh.h5, XDMF)" || bad "b/ outputs inconsistent"

# ---- 1. a failed write (injected ENOSPC) keeps the previous checkpoint, leaves no temporary
cp a/checkpoint.h5 before.h5
NACRE_INJECT_WRITE_FAILURE=checkpoint.h5 expect 1 "cannot write a/checkpoint.h5: No space left on device; the previous checkpoint.h5" \
  "$exe" long.toml -o a -q --restart a/checkpoint.h5 --extend
cmp -s before.h5 a/checkpoint.h5 && ok "previous checkpoint.h5 unchanged after the failed write" || bad "checkpoint.h5 changed by a failed write"
ls -a a | grep -q '\.tmp' && bad "temporary left after a failed write" || ok "no temporary left"
"$exe" tiny.toml --check --restart a/checkpoint.h5 > /dev/null && ok "previous checkpoint still restartable" || bad "previous checkpoint not restartable"
for f in steps.csv dump_00004.h5 nacre.xdmf summary.json; do
  NACRE_INJECT_WRITE_FAILURE=$f expect 1 "cannot write a/$f: No space left on device" "$exe" long.toml -o a -q --restart a/checkpoint.h5 --extend
done

# ---- 1. a real full disk: a small tmpfs in a private mount namespace (skipped where unavailable)
# (--propagation unchanged: inside a chroot the root is no mount point; the dev root's own
# namespace is private already)
if unshare --mount --propagation unchanged true 2> /dev/null; then
  for kb in 32 64 80 96 112 128 144; do
    unshare --mount --propagation unchanged bash -c '
      set -u; exe="$1"; kb="$2"; mkdir -p full; mount -t tmpfs -o size=${kb}k tmpfs full || exit 77
      "$exe" tiny.toml -o full/out -q > full_out.txt 2> full_err.txt; rc=$?
      # what must hold: no temporary left; every HDF5 file under a final name readable; a
      # failure names the file and ENOSPC; checkpoint.h5, if any, validates
      ls -a full/out | grep -q "\.tmp" && { echo "temporary left"; exit 1; }
      for h in full/out/*.h5; do [ -e "$h" ] || continue; python3 -c "import h5py,sys; h5py.File(sys.argv[1],\"r\").close()" "$h" || { echo "unreadable $h"; exit 1; }; done
      if [ $rc -ne 0 ]; then grep -q "No space left on device" full_err.txt || { echo "rc $rc without ENOSPC message: $(cat full_err.txt)"; exit 1; }; fi
      if [ -e full/out/checkpoint.h5 ]; then "$exe" tiny.toml --check --restart full/out/checkpoint.h5 > /dev/null || { echo "checkpoint not valid"; exit 1; }; fi
      echo "rc=$rc"' _ "$exe" "$kb" > full.txt 2>&1
    r=$?
    if [ $r -eq 77 ]; then echo "skip: tmpfs mount not permitted"; break; fi
    [ $r -eq 0 ] && ok "full tmpfs of ${kb} KiB: $(cat full.txt), outputs intact" || bad "full tmpfs of ${kb} KiB: $(cat full.txt)"
  done
else
  echo "skip: unshare --mount not available (the injected failure above covers point 1)"
fi

# ---- 5. SIGTERM / SIGINT mid-run: checkpoint of the last completed step, exit 143 / 130, and
# the restart reproduces the uninterrupted run
sed -e 's/^final_displacement = .*/final_displacement = 0.04/' -e 's/^DumpInter = .*/DumpInter = 100/' tiny.toml > sig.toml
"$exe" sig.toml -o sig_direct -q > /dev/null 2>&1
for s in TERM INT; do
  rm -rf "sig_$s"
  "$exe" sig.toml -o "sig_$s" -q > /dev/null 2> "sig_$s.err" &
  pid=$!
  for _ in $(seq 1 600); do  # until two steps are done
    [ -f "sig_$s/steps.csv" ] && [ "$(wc -l < "sig_$s/steps.csv")" -ge 3 ] && break
    sleep 0.05
  done
  kill -s "$s" "$pid"; wait "$pid"; rc=$?
  want=$([ "$s" == TERM ] && echo 143 || echo 130)
  rows=$(($(wc -l < "sig_$s/steps.csv") - 1))
  if [ "$rc" -eq "$want" ] && grep -q "checkpoint written to sig_$s/checkpoint.h5" "sig_$s.err"; then
    ok "SIG$s after $rows steps: exit $rc, $(grep -o 'stopped after step [0-9]*' "sig_$s.err")"
  else
    bad "SIG$s: exit $rc (expected $want): $(cat "sig_$s.err")"
  fi
  [ "$rows" -lt 10 ] || bad "SIG$s arrived after the run ended (test did not interrupt)"
  if [ "$s" == TERM ]; then  # a new run would remove the unfinished run's checkpoint: refused
    st=$(state sig_TERM)
    expect 2 "unfinished run .*--restart sig_TERM/checkpoint.h5.*--overwrite" "$exe" sig.toml -o sig_TERM -q
    [ "$(state sig_TERM)" == "$st" ] && ok "the unfinished run's directory is unchanged" || bad "refused new run changed sig_TERM/"
  fi
  "$exe" sig.toml -o "sig_$s" -q --restart "sig_$s/checkpoint.h5" > /dev/null 2>&1 || bad "restart after SIG$s failed"
  if diff <(cut -d, -f1-12 "sig_$s/steps.csv") <(cut -d, -f1-12 sig_direct/steps.csv) > /dev/null; then
    ok "restart after SIG$s equals the uninterrupted run"
  else
    bad "restart after SIG$s differs from the uninterrupted run"
  fi
done

echo "robustness: $fails failure(s)"
[ "$fails" -eq 0 ]
