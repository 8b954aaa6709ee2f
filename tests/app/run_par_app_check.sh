#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# `mpiexec -n N nacre DECK` (docs/scaling.md): the Monte Carlo run spread over MPI ranks writes the
# files of the one-process run, bit for bit (tests/app/check_same_run.py: every HDF5 dataset and
# attribute, steps.csv, r_curve.csv, summary.json but the machine's timings):
#  1. tests/app/par_mc.toml (irreversible damage, ruptures, tiles, residual test) on 1 (under the
#     launcher), 2 and 4 ranks;
#  2. relaxation = "gradient" (FIRE alone) and the block-Newton polish on 2 ranks;
#  3. a run stopped at D = 0.016 on 2 ranks continued on 4 (--restart --extend): a checkpoint moves
#     between rank counts;
#  4. SIGTERM sent to rank 1 alone: every rank stops after the same cycle (exit 143, the
#     checkpoint of the last completed step, rank 0's message), and one process continues it to
#     the uninterrupted run's files;
#  5. `--gpu-aware-mpi on` (no staging of the halo messages) gives the same bits; a bad value is refused;
#  6. a restart from another deck's checkpoint, and a refusal of rank 1 alone, say why (exit 2);
#  7. trust-region Newton (relaxation = "auto", the Cholesky factor on rank 0): the default deck
#     (charts off) on 1, 2 and 4 ranks; par_mc.toml rotated by 30 degrees with the reversible law
#     and "auto" on 2 and 4 ranks, with the block-Jacobi preconditioner on 2, and stopped on 2
#     ranks, continued on 4;
#  8. the dynamics (src/dyn, dyn/halo.hpp): the README's decks inputs/dynamic.toml (BE) and
#     inputs/dynamic_bie.toml (BIE, split step), charts off, on 1, 2 and 4 ranks;
#     tests/app/par_dyn.toml (a 20-degree wall, irreversible damage, ruptures) on 2 and 4 ranks, UE
#     and the iterated BIE step with damping on 2; par_dyn stopped on 2 ranks and continued on 4
#     against one process stopped and continued (its checkpoint is one process's, bit for bit);
#     SIGTERM to rank 1 of a dynamic run: all ranks stop after the same row, one process continues
#     it to the uninterrupted run's files;
#  9. what is not spread over ranks yet is refused before anything is written, naming the deck
#     key: the anneal polish, --critical-step, `nacre sweep`.
#   run_par_app_check.sh NACRE_EXE SOURCE_DIR WORK_DIR MPIEXEC NUMPROC_FLAG [MPIEXEC_FLAGS...]
set -uo pipefail
exe="$1"; src="$2"; work="$3"; mpiexec="$4"; npflag="$5"; shift 5
flags=("$@")
rm -rf "$work"; mkdir -p "$work"; cd "$work"
. "$src/tests/app/checks_lib.sh"
same() { if python3 "$src/tests/app/check_same_run.py" "$@" > same.txt 2>&1; then ok "$(cat same.txt)"; else bad "$(cat same.txt)"; fi; }
run_np() { local n="$1"; shift; "$mpiexec" "$npflag" "$n" "${flags[@]}" "$exe" "$@"; }
deck="$src/tests/app/par_mc.toml"
# sigterm_rank1 DECK DIR FILE REF LABEL: DECK on 2 ranks into DIR, SIGTERM to rank 1 alone once FILE
# exists; expect exit 143 with the checkpoint, then one process continues it to REF's files.
# (a deadlock would end at 240 s with the launcher's exit 124, not at ctest's limit)
sigterm_rank1() {
  local dk="$1" dir="$2" file="$3" ref="$4" label="$5" rank1="" rc
  timeout 240 "$mpiexec" "$npflag" 2 "${flags[@]}" "$exe" "$dk" -o "$dir" > "$dir.txt" 2>&1 &
  local launcher=$!
  for _ in $(seq 1 600); do
    if [ -e "$file" ] && [ -z "$rank1" ]; then
      for p in $(pgrep -f -- "$dk -o $dir"); do
        tr '\0' '\n' < "/proc/$p/environ" 2>/dev/null | grep -Eq '^(OMPI_COMM_WORLD_RANK|PMI_RANK)=1$' && rank1=$p
      done
      [ -n "$rank1" ] && kill -TERM "$rank1"
    fi
    kill -0 "$launcher" 2>/dev/null || break
    sleep 0.05
  done
  wait "$launcher"; rc=$?
  if [ -z "$rank1" ]; then
    bad "${label}SIGTERM: rank 1's process not found (the run ended first: exit $rc)"
  elif [ "$rc" -eq 143 ] && grep -q "SIGTERM received: stopped after step" "$dir.txt" && [ -e "$dir/checkpoint.h5" ]; then
    ok "${label}SIGTERM to rank 1 alone: exit $rc, $(grep -o 'stopped after step [0-9]*' "$dir.txt")"
    if "$exe" "$dk" -o "$dir" -q --restart "$dir/checkpoint.h5"; then same "$ref" "$dir"
    else bad "${label}continue on one process: exit $?"; fi
  else
    bad "${label}SIGTERM to rank 1: exit $rc: $(tail -4 "$dir.txt" | tr '\n' ' ')"
  fi
}

"$exe" "$deck" -o one -q || bad "one process: exit $?"
for n in 1 2 4; do
  if run_np "$n" "$deck" -o "p$n" -q > "p$n.txt" 2>&1; then same one "p$n"; else bad "$n ranks: exit $?: $(tail -3 "p$n.txt")"; fi
done
grep -q '"ranks": 4' p4/summary.json && ok "summary.json: ranks 4" || bad "summary.json lacks ranks 4"
# the halo messages handed to MPI without staging (host memory here: the switch changes nothing
# but must not change the bits); a bad value is refused
if run_np 2 "$deck" -o d2 -q --gpu-aware-mpi on > d2.txt 2>&1; then same one d2; else bad "--gpu-aware-mpi on: exit $?"; fi
rm -rf bad_switch
run_np 2 "$deck" -o bad_switch --gpu-aware-mpi maybe > out.txt 2> err.txt; got=$?
[ "$got" -ne 0 ] && grep -q "gpu-aware-mpi" err.txt && [ ! -e bad_switch ] && ok "--gpu-aware-mpi maybe refused (exit $got)" \
  || bad "--gpu-aware-mpi maybe: exit $got $(head -c 300 err.txt)"

sed 's/^relaxation = "monte-carlo"/relaxation = "gradient"/' "$deck" > grad.toml
"$exe" grad.toml -o g1 -q || bad "gradient, one process: exit $?"
if run_np 2 grad.toml -o g2 -q > g2.txt 2>&1; then same g1 g2; else bad "gradient on 2 ranks: exit $?: $(tail -3 g2.txt)"; fi

# the block-Newton polish (colour-swept: each colour's poses to the halos before the next)
sed 's/^polish = "fire"/polish = "newton"/' "$deck" > bnewton.toml
"$exe" bnewton.toml -o bn1 -q || bad "block-Newton polish, one process: exit $?"
if run_np 2 bnewton.toml -o bn2 -q > bn2.txt 2>&1; then same bn1 bn2; else bad "block-Newton polish on 2 ranks: exit $?: $(tail -3 bn2.txt)"; fi

sed 's/^final_displacement = 0.028/final_displacement = 0.016/' "$deck" > half.toml
if run_np 2 half.toml -o h2 -q > h2.txt 2>&1 &&
   run_np 4 "$deck" -o x4 -q --restart h2/checkpoint.h5 --extend > x4.txt 2>&1; then
  same one x4 --steps-from 5
else
  bad "stop on 2 ranks, continue on 4: $(tail -3 h2.txt x4.txt)"
fi

# SIGTERM to rank 1 only, once step 2's dump is written (the run has 15 steps)
sed -e 's/^final_displacement = 0.028/final_displacement = 0.06/' -e 's/^DumpInter = 2/DumpInter = 1/' "$deck" > long.toml
"$exe" long.toml -o l1 -q || bad "long deck, one process: exit $?"
sigterm_rank1 long.toml s2 s2/dump_00002.h5 l1 ""

# trust-region Newton: the default deck, and a rotated wall with bursts of Monte Carlo
sed 's/^charts = true/charts = false/' "$src/inputs/default.toml" > default.toml
grep -q '^charts = false' default.toml || printf 'charts = false\n' >> default.toml  # [output] is last
"$exe" default.toml -o n1 -q || bad "default deck, one process: exit $?"
for n in 2 4; do
  if run_np "$n" default.toml -o "n$n" -q > "n$n.txt" 2>&1; then same n1 "n$n"; else bad "default deck on $n ranks: exit $?: $(tail -3 "n$n.txt")"; fi
done
sed -e 's/^damage = "irreversible"/damage = "reversible"/' -e 's/^relaxation = "monte-carlo"/relaxation = "auto"/' \
    -e 's/^final_displacement = 0.028/final_displacement = 0.04/' -e 's/^\[geometry\]/[geometry]\nangle = 30.0/' "$deck" > rot.toml
"$exe" rot.toml -o r1 -q || bad "rotated Newton deck, one process: exit $?"
grep -q 'newton+monte-carlo' r1/steps.csv && ok "rotated Newton deck: a step finished by a Monte Carlo burst" \
  || bad "rotated Newton deck: no step needed a burst (the test would not cover it)"
for n in 2 4; do
  if run_np "$n" rot.toml -o "r$n" -q > "r$n.txt" 2>&1; then same r1 "r$n"; else bad "rotated Newton deck on $n ranks: exit $?: $(tail -3 "r$n.txt")"; fi
done
# the block-Jacobi preconditioner (a device build's): no factor, the same halo rows
sed 's/^relaxation = "auto"/relaxation = "auto"\nnewton_preconditioner = "block-jacobi"/' rot.toml > rot_bj.toml
"$exe" rot_bj.toml -o b1 -q || bad "block-Jacobi Newton deck, one process: exit $?"
if run_np 2 rot_bj.toml -o b2 -q > b2.txt 2>&1; then same b1 b2; else bad "block-Jacobi on 2 ranks: exit $?: $(tail -3 b2.txt)"; fi
sed 's/^final_displacement = 0.04/final_displacement = 0.02/' rot.toml > rot_half.toml
if run_np 2 rot_half.toml -o rh2 -q > rh2.txt 2>&1 &&
   run_np 4 rot.toml -o rx4 -q --restart rh2/checkpoint.h5 --extend > rx4.txt 2>&1; then
  same r1 rx4 --steps-from 6
else
  bad "Newton: stop on 2 ranks, continue on 4: $(tail -3 rh2.txt rx4.txt)"
fi

# the dynamics: the README's decks, then a rotated wall with irreversible damage
for dk in dynamic dynamic_bie; do
  sed 's/^charts = true/charts = false/' "$src/inputs/$dk.toml" > "$dk.toml"
  grep -q '^charts = false' "$dk.toml" || printf 'charts = false\n' >> "$dk.toml"  # [output] is last
  "$exe" "$dk.toml" -o "${dk}_one" -q || bad "$dk, one process: exit $?"
  for n in 1 2 4; do
    if run_np "$n" "$dk.toml" -o "${dk}_$n" -q > "${dk}_$n.txt" 2>&1; then same "${dk}_one" "${dk}_$n"
    else bad "$dk on $n ranks: exit $?: $(tail -3 "${dk}_$n.txt")"; fi
  done
done
dyn="$src/tests/app/par_dyn.toml"
"$exe" "$dyn" -o y1 -q || bad "par_dyn, one process: exit $?"
grep -Eq '"ruptured": [1-9]' y1/summary.json && ok "par_dyn: joints ruptured" || bad "par_dyn: no rupture (the test would not cover damage)"
for n in 2 4; do
  if run_np "$n" "$dyn" -o "y$n" -q > "y$n.txt" 2>&1; then same y1 "y$n"; else bad "par_dyn on $n ranks: exit $?: $(tail -3 "y$n.txt")"; fi
done
sed -e 's/^method = "be"/method = "ue"/' -e 's/^end_time = 4.0e-6/end_time = 1.0e-6/' "$dyn" > dyn_ue.toml  # (UE: 6x the steps)
sed 's/^method = "be"/method = "bie"\nbie_iterations = 2/' "$dyn" > dyn_bie.toml  # iterated, damped: the app bisects too
for v in ue bie; do
  "$exe" "dyn_$v.toml" -o "yv1_$v" -q || bad "par_dyn $v, one process: exit $?"
  if run_np 2 "dyn_$v.toml" -o "yv2_$v" -q > "yv2_$v.txt" 2>&1; then same "yv1_$v" "yv2_$v"
  else bad "par_dyn $v on 2 ranks: exit $?: $(tail -3 "yv2_$v.txt")"; fi
done
sed 's/^end_time = 4.0e-6/end_time = 2.0e-6/' "$dyn" > dyn_half.toml
"$exe" dyn_half.toml -o yh1 -q || bad "par_dyn half, one process: exit $?"
if run_np 2 dyn_half.toml -o yh2 -q > yh2.txt 2>&1; then same yh1 yh2; else bad "par_dyn half on 2 ranks: exit $?"; fi
"$exe" "$dyn" -o yx1 -q --restart yh1/checkpoint.h5 --extend || bad "par_dyn continued on one process: exit $?"
if run_np 4 "$dyn" -o yx4 -q --restart yh2/checkpoint.h5 --extend > yx4.txt 2>&1; then same yx1 yx4
else bad "par_dyn: stop on 2 ranks, continue on 4: exit $?: $(tail -3 yx4.txt)"; fi

# SIGTERM to rank 1 of a dynamic run: every rank stops after the same row with the checkpoint,
# and one process continues it to the uninterrupted run's files (summary.json included)
sed 's/^end_time = 4.0e-6/end_time = 1.2e-5/' "$dyn" > dyn_long.toml
"$exe" dyn_long.toml -o yl1 -q || bad "par_dyn long, one process: exit $?"
sigterm_rank1 dyn_long.toml ys2 ys2/dump_000000400.h5 yl1 "dynamics, "

expect_np() {  # expect_np PATTERN ARGS...: refused on 2 ranks, nothing written
  local pat="$1"; shift
  rm -rf refused
  run_np 2 "$@" -o refused > out.txt 2> err.txt; local got=$?
  if [ "$got" -ne 0 ] && grep -aEq -- "$pat" err.txt && [ ! -e refused ]; then
    ok "2 ranks $(basename "$1") refused (exit $got): $(grep -aE -- "$pat" err.txt | head -1 | head -c 200)"
  else
    bad "2 ranks $*: exit $got, $( [ -e refused ] && echo 'output written, ')$(tr '\n' ' ' < err.txt | head -c 300)"
  fi
}
sed 's/^polish = "fire"/polish = "anneal"/' "$deck" > anneal.toml
expect_np 'solver.polish.*not yet spread over ranks' anneal.toml
# a checkpoint of another deck, found after Kokkos started: every rank says why before the abort
expect_np 'cannot restart' "$deck" --restart g1/checkpoint.h5
# a refusal of rank 1 alone (here: its deck does not exist): rank 1 says why, nobody runs
rm -rf refused
"$mpiexec" "$npflag" 2 "${flags[@]}" bash -c \
  'r=${OMPI_COMM_WORLD_RANK:-${PMI_RANK:-0}}; [ "$r" = 1 ] && d=missing.toml || d="$2"; exec "$1" "$d" -o refused' \
  _ "$exe" "$deck" > out.txt 2> err.txt; got=$?
if [ "$got" -eq 2 ] && grep -aq "rank 1 of 2" err.txt && grep -aq "missing.toml" err.txt && [ ! -e refused ]; then
  ok "a refusal of rank 1 alone: exit 2, $(grep -m1 'rank 1 of 2' err.txt | head -c 160)"
else
  bad "a refusal of rank 1 alone: exit $got, $( [ -e refused ] && echo 'output written, ')$(tr '\n' ' ' < err.txt | head -c 300)"
fi
expect_np 'critical-step runs on one process' "$src/tests/app/tiny_dynamic.toml" --critical-step
rm -rf refused
run_np 2 sweep "$src/tests/app/tiny.toml" --set random.seed=1,2 -o refused > out.txt 2> err.txt; got=$?
[ "$got" -ne 0 ] && grep -q "nacre sweep runs on one rank" err.txt && [ ! -e refused ] && ok "2 ranks sweep refused" \
  || bad "2 ranks sweep: exit $got $(head -c 300 err.txt)"

[ "$fails" -eq 0 ] || { echo "$fails check(s) failed"; exit 1; }
echo "all MPI app checks passed"
