#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Faults that lost data of dynamic runs, each a case that failed before the outputs moved onto
# io::RunWriter and the shared driver, with what must hold now (tests/app/tiny_dynamic.toml):
#  - SIGKILL right after a checkpoint commit: the restart finds every row the checkpoint depends
#    on (rows are committed before the checkpoint) and equals the uninterrupted run;
#  - a new run into the directory of an interrupted dynamic run is refused (exit 2), unchanged;
#  - SIGINT in the last chunk: exit 130, not 0;
#  - a file-size limit (SIGXFSZ): a message naming the file, no temporary left;
#  - a shell command in -o, a directory named it's, a deck named with a quote: nothing run,
#    charts written, summary.json valid JSON;
#  - keys and checkpoints accepted but wrong: BIE keys with method be, end_time = 1e20 with
#    dt_fraction, dt = 1e-300, 1e11 steps, a NaN in a checkpoint, a checkpoint of a finished
#    run, --check --restart of a dynamic checkpoint, a method mismatch (exit 2, dt printed), a
#    misspelt [load] key named.
#   run_dyn_faults.sh NACRE_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$1"; src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"; cd "$work"
source "$src/tests/app/checks_lib.sh"  # ok, bad, expect, state
same_rows() {  # same_rows A B: every column but the wall time equal, same steps
  python3 - "$1" "$2" <<'PY'
import csv, sys
a, b = ([{k: v for k, v in r.items() if k != "seconds"} for r in csv.DictReader(open(p))] for p in sys.argv[1:])
sys.exit(0 if a == b else 1)
PY
}
sed -e 's/^charts = .*//' -e 's/^\[output\]/[output]\ncharts = false/' "$src/tests/app/tiny_dynamic.toml" > d.toml
sed 's/^dump_interval = .*/dump_interval = 100/' d.toml > k.toml
"$exe" k.toml -o direct -q || bad "direct run failed"

# ---- SIGKILL right after the 3rd checkpoint commit (step 200): rows first, so nothing is lost
NACRE_INJECT_KILL_AFTER=checkpoint.h5:3 "$exe" k.toml -o killed -q > /dev/null 2>&1; rc=$?
[ "$rc" -eq 137 ] || bad "the injected kill did not happen (exit $rc)"
cp_step=$(python3 -c "import h5py; print(int(h5py.File('killed/checkpoint.h5','r').attrs['step']))")
last_row=$(tail -n1 killed/series.csv | cut -d, -f1)
[ "$last_row" -ge "$cp_step" ] && ok "killed after the checkpoint at step $cp_step: series.csv reaches step $last_row" \
  || bad "checkpoint at step $cp_step, series.csv only to step $last_row"
"$exe" k.toml -o killed -q --restart killed/checkpoint.h5 || bad "restart after SIGKILL failed"
same_rows killed/series.csv direct/series.csv && ok "restart after SIGKILL equals the uninterrupted run (all rows)" \
  || bad "restart after SIGKILL: series.csv differs from the uninterrupted run"

# ---- a new run into an interrupted dynamic run's directory is refused
NACRE_INJECT_KILL_AFTER=checkpoint.h5:2 "$exe" k.toml -o unfinished -q > /dev/null 2>&1
st=$(state unfinished)
expect 2 "unfinished run .*t = .* of .*--restart unfinished/checkpoint.h5.*--overwrite" "$exe" k.toml -o unfinished -q
[ "$(state unfinished)" == "$st" ] && ok "the unfinished run's directory is unchanged" || bad "refused new run changed unfinished/"
expect 0 "" "$exe" k.toml -o unfinished -q --overwrite

# ---- SIGINT in the last chunk (one chunk: csv_interval = the whole run)
sed -e 's/^csv_interval = .*/csv_interval = 100000/' -e 's/^dump_interval = .*/dump_interval = 0/' \
    -e 's/^end_time = .*/end_time = 4e-4/' d.toml > last.toml
"$exe" last.toml -o last -q > /dev/null 2> last.err & pid=$!
for _ in $(seq 1 200); do [ -f last/checkpoint.h5 ] && break; sleep 0.05; done
sleep 0.3; kill -INT "$pid"; wait "$pid"; rc=$?
[ "$rc" -eq 130 ] && ok "SIGINT in the last chunk: exit 130 ($(head -1 last.err | head -c 120))" || bad "SIGINT in the last chunk: exit $rc"

# ---- a file-size limit: SIGXFSZ ignored, the write fails by name, no temporary left
( ulimit -f 40; exec "$exe" d.toml -o xfsz -q ) > /dev/null 2> xfsz.err; rc=$?
if [ "$rc" -eq 1 ] && grep -q "cannot write .*File too large" xfsz.err; then ok "ulimit -f: exit 1, $(grep "File too large" xfsz.err | head -1 | head -c 160)"
else bad "ulimit -f: exit $rc, $(head -c 300 xfsz.err)"; fi
ls -a xfsz 2> /dev/null | grep -q '\.tmp' && bad "ulimit -f left a temporary" || ok "ulimit -f left no temporary"

# ---- paths: no shell, charts in any directory name, a valid summary for any deck name
sed 's/^charts = false/charts = true/' d.toml > 'bie"q.toml'
"$exe" 'bie"q.toml' -o "x'; touch INJECTED; '" -q > /dev/null 2>&1
[ -e INJECTED ] && bad "shell injection through -o created INJECTED" || ok "-o with a shell command ran nothing"
[ -f "x'; touch INJECTED; '/crack.png" ] && ok "charts written into the odd directory" || bad "charts missing in the odd directory"
"$exe" 'bie"q.toml' -o "it's" -q > /dev/null 2>&1
[ -f "it's/energy_force.png" ] && ok "charts written into it's/" || bad "charts missing in it's/"
python3 -c "import json,sys; d=json.load(open(sys.argv[1])); assert d['deck'].endswith('bie\"q.toml')" "it's/summary.json" \
  && ok "summary.json of a deck named bie\"q.toml is valid JSON" || bad "summary.json invalid for a quoted deck name"

# ---- a full disk during the charts: the chart module writes a temporary and renames it
# (python3 -m nacre.charts.dyn, run here in this process with savefig failing half-way)
mkdir -p ro && cp -r direct ro/run && PYTHONPATH="$src/python" python3 - ro/run <<'PY'
import os, runpy, sys
import matplotlib.figure
real = matplotlib.figure.Figure.savefig
# the module runs in this process with savefig failing half-way, as a full disk would
def failing(self, fname, *a, **k):
    open(fname, "wb").write(b"\x89PNG\r\n\x1a\npartial")
    raise OSError(28, "No space left on device")
matplotlib.figure.Figure.savefig = failing
out = sys.argv[1]
sys.argv = ["nacre.charts.dyn", out]
try:
    runpy.run_module("nacre.charts.dyn", run_name="__main__", alter_sys=True)  # python3 -m nacre.charts.dyn OUT
except OSError:
    pass
left = [f for f in os.listdir(out) if f.endswith(".png") or ".tmp" in f]
sys.exit(1 if left else 0)
PY
[ $? -eq 0 ] && ok "a chart write failing half-way leaves no PNG and no temporary" || bad "a failed chart write left a PNG or temporary: $(ls ro/run)"

# ---- accepted but wrong, now refused with file, line and key
printf 'bie_block = 4\n' > bie_key.txt
sed '/^\[dynamics\]/r bie_key.txt' d.toml > bie_be.toml
expect 2 "bie_be.toml:[0-9]+: dynamics.bie_block: applies to method = \"bie\" only" "$exe" bie_be.toml --check
sed -e 's/^dt = .*/dt_fraction = 0.5/' -e 's/^end_time = .*/end_time = 1e20/' -e 's/^ramp_time = .*/ramp_time = 0/' d.toml > endless.toml
expect 2 "endless.toml:[0-9]+: dynamics.dt_fraction: end_time / dt = .* time steps, above the limit" "$exe" endless.toml -o endless -q
sed 's/^dt = .*/dt = 1e-300/' d.toml > tiny_dt.toml
expect 2 "tiny_dt.toml:[0-9]+: dynamics.dt: end_time / dt" "$exe" tiny_dt.toml --check
sed -e 's/^dt = .*/dt = 1e-15/' -e 's/^end_time = .*/end_time = 1e-4/' d.toml > many.toml
expect 2 "many.toml:[0-9]+: dynamics.dt: .*1e\+11 time steps" "$exe" many.toml --check
sed 's/^bending = 1.0/bendng = 1.0/' d.toml > typo.toml
expect 2 "typo.toml:[0-9]+: load.bendng" "$exe" typo.toml --check
cp direct/checkpoint.h5 finished.h5
expect 2 "at or beyond this deck's end_time.*nothing to continue" "$exe" k.toml -o fin -q --restart finished.h5
[ -e fin ] && bad "a refused restart created fin/" || ok "a refused restart created nothing"
python3 - killed/checkpoint.h5 nan.h5 <<'PY'
import shutil, sys, h5py, numpy as np
shutil.copy(sys.argv[1], sys.argv[2])
with h5py.File(sys.argv[2], "r+") as h:
    k = sorted(h["/arrays"])[0]
    a = h["/arrays/" + k][...]; a.flat[0] = np.nan; h["/arrays/" + k][...] = a
PY
# (the checksum catches the edit first; a NaN that passes it is refused by the finiteness check,
# tested in test_io)
expect 2 "checksum|non-finite" "$exe" k.toml -o nanrun -q --restart nan.h5
NACRE_INJECT_KILL_AFTER=checkpoint.h5:2 "$exe" k.toml -o mid -q > /dev/null 2>&1
expect 0 "" "$exe" k.toml --check --restart mid/checkpoint.h5
grep -q "checkpoint is valid for this deck (step 100, t = " out.txt && ok "--check --restart reads a dynamic checkpoint" || bad "--check --restart: $(cat out.txt)"
sed 's/^method = "be"/method = "ue"/' k.toml > ue.toml
expect 2 "dynamics.method = \"be\" in the checkpoint, \"ue\" in ue.toml" "$exe" ue.toml -o mid -q --restart mid/checkpoint.h5
sed 's/^end_time = .*/end_time = 1.2e-5/' k.toml > longer.toml
expect 2 "ends at end_time = 6e-06 s, this deck at 1.2e-05 s.*--extend" "$exe" longer.toml -o mid -q --restart mid/checkpoint.h5
expect 0 "" "$exe" longer.toml -o mid -q --restart mid/checkpoint.h5 --extend

echo "dynamic faults: $fails failure(s)"
[ "$fails" -eq 0 ]
