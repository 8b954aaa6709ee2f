#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# The dynamics over MPI ranks on this machine (docs/scaling.md "Dynamics over ranks"): strong
# scaling (the README's BE and BIE decks widened to ~21k bricks, 1, 2 and 4 ranks) and weak
# scaling (BE, ~10.5k bricks per rank), each run of the app checked against the one-process run's
# files bit for bit (tests/app/check_same_run.py). Time per step and the halo's bytes and
# exchanges per step from summary.json. One thread per rank (4 ranks oversubscribe a 2-core
# machine: an overhead and correctness measurement, not a speed-up). Inside the dev root:
#   devenv/nacre-env run perf/run_par_dyn_scaling.sh [OUT_DIR]        (default perf/results/par)
set -euo pipefail
out=${1:-perf/results/par}
exe=${NACRE_BUILD:-build/openmp}/src/nacre
[ -x "$exe" ] || { echo "run_par_dyn_scaling.sh: $exe not built" >&2; exit 2; }
mkdir -p "$out"
work=$(mktemp -d "${TMPDIR:-/tmp}/nacre_dyn_par.XXXXXX")
trap 'rm -rf "$work"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_btl=self,sm
export OMP_NUM_THREADS=1 OMP_PROC_BIND=false OMP_WAIT_POLICY=passive
# deck SRC SCALE_X SCALE_Y STEPS OUT.toml: the deck widened by SCALE_X and SCALE_Y (bricks, notch),
# about STEPS steps of its dt (the run takes 0.8 of its own critical step), charts off
deck() {
  python3 - "$@" <<'PY'
import re, sys
src, sx, sy, steps, dst = sys.argv[1], float(sys.argv[2]), float(sys.argv[3]), int(sys.argv[4]), sys.argv[5]
t = open(src).read()
get = lambda k: float(re.search(rf"^{k} = ([0-9.eE+-]+)", t, re.M).group(1))
t = re.sub(r"^width = .*", f"width = {get('width') * sx:.6g}", t, flags=re.M)
t = re.sub(r"^height = .*", f"height = {get('height') * sy:.6g}", t, flags=re.M)
t = re.sub(r"^notch_length = .*", f"notch_length = {get('notch_length') * sx:.6g}", t, flags=re.M)
t = re.sub(r"^end_time = .*", f"end_time = {get('dt') * steps:.9g}", t, flags=re.M)
if get("ramp_time") > 0.5 * get("dt") * steps:  # (the ramp within the run)
    t = re.sub(r"^ramp_time = .*", f"ramp_time = {0.5 * get('dt') * steps:.9g}", t, flags=re.M)
t = re.sub(r"^dt = .*", "dt_fraction = 0.8  # (the widened deck's edge pieces set its step)", t, flags=re.M)
t = re.sub(r"^csv_interval = .*", "csv_interval = 50", t, flags=re.M)
t = re.sub(r"^dump_interval = .*", "dump_interval = 0", t, flags=re.M)
t = re.sub(r"^charts = .*\n", "", t, flags=re.M) + "charts = false\n"
open(dst, "w").write(t)
PY
}
run() {  # run NP DECK DIR
  if [ "$1" = 1 ]; then "$exe" "$2" -o "$3" -q; else mpiexec -n "$1" --oversubscribe "$exe" "$2" -o "$3" -q; fi
}
row() {  # row STUDY METHOD NP DIR REFDIR >> csv
  local agree
  if python3 tests/app/check_same_run.py "$5" "$4" > /dev/null 2>&1; then agree=bit-identical; else agree=DIFFERS; fi
  python3 - "$1" "$2" "$3" "$4/summary.json" "$agree" <<'PY'
import json, sys
study, method, np_, path, agree = sys.argv[1:]
j = json.load(open(path))
print(f"{study},{method},{np_},{j['bricks']},{j['steps']},{j['seconds_per_step']:.6g},"
      f"{j['halo_bytes_per_exchange']},{j['halo_exchanges_per_step']:.3f},{agree}")
PY
}
csv="$out/dyn.csv"
echo "study,method,ranks,bricks,steps,s_per_step,halo_bytes_per_exchange,exchanges_per_step,agreement" > "$csv"
for m in dynamic dynamic_bie; do
  deck "inputs/$m.toml" 3.2 3.2 300 "$work/$m.toml"
  for np in 1 2 4; do
    run "$np" "$work/$m.toml" "$work/${m}_s$np"
    row strong "$m" "$np" "$work/${m}_s$np" "$work/${m}_s1" >> "$csv"
  done
done
for np in 1 2 4; do  # weak: the BE deck widened with the rank count (columns of ranks)
  deck inputs/dynamic.toml "$(python3 -c "print(2.24 * $np)")" 2.24 300 "$work/weak$np.toml"
  run "$np" "$work/weak$np.toml" "$work/w$np"
  ref="$work/w$np"
  if [ "$np" != 1 ]; then ref="$work/w1_$np"; run 1 "$work/weak$np.toml" "$ref"; fi  # its one-process reference
  row weak dynamic "$np" "$work/w$np" "$ref" >> "$csv"
done
cat "$csv"
echo "run_par_dyn_scaling.sh: wrote $csv"
