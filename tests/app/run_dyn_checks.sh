#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# End-to-end test of a dynamic deck (tests/app/tiny_dynamic.toml):
#  1. the run's outputs are consistent (check_dyn_outputs.py); the crack picture's rasterised
#     path (large meshes) gives exact pixels and a PNG (check_dyn_plot.py);
#  2. a run restarted from its checkpoint to twice the end time equals a direct run bit for bit
#     (every series.csv column but the wall time, and every checkpoint array);
#  2b. a checkpoint of a deck with other physics is refused (exit 2), the directory untouched;
#  3. a step above the critical step stops with exit code 3 and a message naming step, time and
#     quantity, and leaves only finite rows, dumps and checkpoint behind.
#   run_dyn_checks.sh NACRE_EXE SOURCE_DIR WORK_DIR
set -euo pipefail
exe="$1"; src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"; cd "$work"
deck="$src/tests/app/tiny_dynamic.toml"
end=$(sed -n 's/^end_time = \([^ ]*\).*/\1/p' "$deck")
long_end=$(python3 -c "print(2 * $end)")

# 1. outputs
"$exe" "$deck" -o short -q
python3 "$src/tests/app/check_dyn_outputs.py" short
python3 "$src/tests/app/check_dyn_plot.py" "$src" short
# off a terminal, [output] heartbeat: "in progress" lines between dumps (every chunk at 1e-9)
sed 's/^directory = .*/directory = "beat"\nheartbeat = 1e-9\ncharts = false/' "$deck" > beat.toml
"$exe" beat.toml > beat.log 2>&1
grep -q "^  step 25/600 in progress: t = " beat.log || { cat beat.log; echo "FAIL: no heartbeat line"; exit 1; }

# 2. restart, bit for bit
sed "s/^end_time = .*/end_time = $long_end/" "$deck" > long.toml
"$exe" long.toml -o short -q --restart short/checkpoint.h5 --extend
"$exe" long.toml -o direct -q
python3 - short/series.csv direct/series.csv <<'PY'
# every row of the direct run appears, identical but for the wall time, in the restarted series
# (which also keeps the first run's last row, at the checkpoint, off the csv_interval grid)
import csv, sys
a, b = ({r["step"]: r for r in csv.DictReader(open(p))} for p in sys.argv[1:])
for step, row in b.items():
    assert step in a, f"restarted series lacks step {step}"
    for k, v in row.items():
        assert k == "seconds" or a[step][k] == v, f"step {step}: {k} = {a[step][k]} restarted, {v} direct"
assert set(a) - set(b) <= {max(set(a) - set(b), default=None, key=int)}, "restarted series has extra rows"
print(f"restart: {len(b)} rows of the direct run reproduced exactly")
PY
python3 - short/checkpoint.h5 direct/checkpoint.h5 <<'PY'
import sys, h5py, numpy as np
a, b = (h5py.File(p, "r") for p in sys.argv[1:])
assert int(a.attrs["step"]) == int(b.attrs["step"]), "checkpoints at different steps"
assert sorted(a["/arrays"]) == sorted(b["/arrays"]), "different state arrays"
for k in a["/arrays"]:
    x, y = a["/arrays/" + k][...], b["/arrays/" + k][...]
    assert x.shape == y.shape and np.array_equal(x.view(np.uint64), y.view(np.uint64)), f"/arrays/{k} differs"
print(f"restart: {len(a['/arrays'])} state arrays bit-identical at step {int(a.attrs['step'])}")
PY
python3 "$src/tests/app/check_dyn_outputs.py" short

# 2b. a checkpoint of a deck with other physics is refused (exit 2) and changes nothing
sed "s/^stiffness_ratio = .*/stiffness_ratio = 50/" long.toml > other.toml
cp -r short refused && before=$(ls -l refused | md5sum)
set +e; "$exe" other.toml -o refused -q --restart refused/checkpoint.h5 2> refused.err; rc=$?; set -e
cat refused.err
[ "$rc" -eq 2 ] || { echo "FAIL: a checkpoint of other physics gave exit $rc, expected 2"; exit 1; }
grep -q "stiffness_ratio" refused.err || { echo "FAIL: the refusal does not name the differing key"; exit 1; }
[ "$before" = "$(ls -l refused | md5sum)" ] || { echo "FAIL: a refused restart changed the output directory"; exit 1; }

# 3. an unstable step is caught
h=$("$exe" "$deck" --critical-step -q)
dt=$(python3 -c "print(4 * $h)")
sed -e "s/^dt = .*/dt = $dt/" -e "s/^end_time = .*/end_time = $(python3 -c "print(400 * $dt)")/" \
    -e "s/^csv_interval = .*/csv_interval = 2/" -e "s/^dump_interval = .*/dump_interval = 4/" "$deck" > unstable.toml
set +e
"$exe" unstable.toml -o unstable -q 2> unstable.err
rc=$?
set -e
cat unstable.err
if [ "$rc" -ne 3 ]; then echo "FAIL: unstable run exited with $rc, expected 3"; exit 1; fi
grep -q "unstable" unstable.err || { echo "FAIL: no 'unstable' in the message"; exit 1; }
grep -qi "step" unstable.err || { echo "FAIL: the message does not name the step"; exit 1; }
if grep -qiE "nan|inf" unstable/series.csv; then echo "FAIL: series.csv holds a non-finite value"; exit 1; fi
python3 "$src/tests/app/check_dyn_outputs.py" unstable --partial
grep -q '"status": "unstable"' unstable/summary.json || { echo "FAIL: summary does not say unstable"; exit 1; }
echo "unstable: dt = $dt (4 x critical $h) stopped with exit 3, outputs finite"
# every nacre.xdmf this test wrote, as ParaView's Xdmf3 reader needs it (connectivity per topology)
python3 "$src/tests/app/check_xdmf.py" $(find . -name nacre.xdmf | sort)
