#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# `nacre sweep` (docs/fracture.md "Sweeps") on the tiny deck:
#  1. two angles: one run each in OUT/angle=V/, their decks beside them, sweep.json, sweep.csv
#     (one row per run, the swept value and the crack columns) and sweep.png;
#  2. the same command again keeps both finished runs (nothing re-run: steps.csv untouched);
#  3. an interrupted run (its summary gone, its checkpoint kept) is restarted, the other kept;
#  4. two keys: every combination, named by both leaves;
#  5. a key without its section and a value the deck refuses: exit 2 / a failed run named, exit 1.
#   run_sweep_check.sh NACRE_EXE SOURCE_DIR WORK_DIR
set -euo pipefail
exe="$1"; src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"; cd "$work"
deck="$src/tests/app/tiny.toml"

"$exe" sweep "$deck" --set geometry.angle=0,30 -o sw -q
for d in "sw/angle=0" "sw/angle=30"; do
  [ -s "$d/summary.json" ] && [ -s "$d/steps.csv" ] && [ -s "$d.toml" ] || { ls -R sw; echo "FAIL: $d incomplete"; exit 1; }
done
grep -q "^angle = 30" "sw/angle=30.toml" || { cat "sw/angle=30.toml"; echo "FAIL: the deck of angle=30 lacks the key"; exit 1; }
[ -s sw/sweep.png ] || { echo "FAIL: no sweep.png"; exit 1; }
python3 - sw <<'PY'
import csv, json, sys
out = sys.argv[1]
rows = list(csv.DictReader(open(f"{out}/sweep.csv")))
assert [r["geometry.angle"] for r in rows] == ["0", "30"], rows
for r in rows:
    s = json.load(open(f"{out}/{r['name']}/summary.json"))
    assert float(r["peak_reaction"]) > 0 and r["exit"] == "0", r
    assert float(r["crack_extension"]) == s["crack"]["extension"], (r, s["crack"])
j = json.load(open(f"{out}/sweep.json"))
assert [x["how"] for x in j["runs"]] == ["run", "run"], j
print("sweep: 2 runs, sweep.csv and sweep.png")
PY
before=$(stat -c %Y "sw/angle=0/steps.csv")
sleep 1
"$exe" sweep "$deck" --set geometry.angle=0,30 -o sw -q
[ "$(stat -c %Y "sw/angle=0/steps.csv")" = "$before" ] || { echo "FAIL: a finished run was run again"; exit 1; }
python3 -c "
import json; j = json.load(open('sw/sweep.json'))
assert [x['how'] for x in j['runs']] == ['kept (finished before)'] * 2, j"

# an interrupted run: no summary, its checkpoint kept -> restarted from it
rm "sw/angle=30/summary.json"
"$exe" sweep "$deck" --set geometry.angle=0,30 -o sw -q
python3 -c "
import json; j = json.load(open('sw/sweep.json'))
assert [x['how'] for x in j['runs']] == ['kept (finished before)', 'restarted from its checkpoint'], j"
[ -s "sw/angle=30/summary.json" ] || { echo "FAIL: the restarted run did not finish"; exit 1; }

"$exe" sweep "$deck" --set geometry.angle=0 --set mortar.x2=0.004,0.006 -o sw2 -q
[ -s "sw2/angle=0_x2=0.004/summary.json" ] && [ -s "sw2/angle=0_x2=0.006/summary.json" ] || { ls sw2; echo "FAIL: two-key names"; exit 1; }

set +e
"$exe" sweep "$deck" --set angle=0,30 -o bad -q 2> bad.err; rc=$?
set -e
[ "$rc" -eq 2 ] && grep -q "needs its section" bad.err || { cat bad.err; echo "FAIL: a key without section gave $rc"; exit 1; }
set +e
"$exe" sweep "$deck" --set mortar.x2=0.004,-1 -o bad2 -q 2> bad2.err; rc=$?
set -e
[ "$rc" -eq 1 ] && grep -q "1 of 2 runs failed" bad2.err || { cat bad2.err; echo "FAIL: a refused value gave $rc"; exit 1; }
grep -q "mortar.x2" bad2.err || { cat bad2.err; echo "FAIL: the refused key is not named"; exit 1; }
echo "sweep checks passed"

# 6. --list: each run's deck written, one command per run still to do (the finished ones left
#    out), nothing run; those commands run (as a job array would), the sweep again keeps them all
"$exe" sweep "$deck" --set geometry.angle=0,30,60 -o sw --list > list.txt
[ "$(wc -l < list.txt)" -eq 1 ] && grep -q "angle=60" list.txt && [ -s "sw/angle=60.toml" ] &&
  [ ! -e "sw/angle=60" ] || { cat list.txt; ls sw; echo "FAIL: sweep --list"; exit 1; }
bash -e list.txt > /dev/null
"$exe" sweep "$deck" --set geometry.angle=0,30,60 -o sw -q
python3 -c "
import json; j = json.load(open('sw/sweep.json'))
assert [x['how'] for x in j['runs']] == ['kept (finished before)'] * 3, j['runs']
" || { echo "FAIL: the listed run was not kept"; exit 1; }
echo "sweep --list: one command per run to do; run by hand, then kept by the sweep"

# 7. --jobs 2: two runs at once, each on CPUs of its own, each one's log in its log.txt; the
#    same sweep.csv as the one run after another (every run is deterministic)
"$exe" sweep "$deck" --set geometry.angle=0,30,60 -o sw3 -j 2 > jobs.out
grep -q "sweep run 1/3: angle=0 (CPUs " jobs.out || { cat jobs.out; echo "FAIL: -j 2 did not name the runs' CPUs"; exit 1; }
cmp sw/sweep.csv sw3/sweep.csv || { diff sw/sweep.csv sw3/sweep.csv; echo "FAIL: -j 2 changed sweep.csv"; exit 1; }
for a in 0 30 60; do
  grep -q "^nacre: .*angle=$a.toml: " "sw3/angle=$a/log.txt" || { cat "sw3/angle=$a/log.txt"; echo "FAIL: angle=$a/log.txt"; exit 1; }
done
python3 -c "
import json; j = json.load(open('sw3/sweep.json'))
assert j['jobs'] == 2 and [x['how'] for x in j['runs']] == ['run'] * 3, j
"
echo "sweep -j 2: 3 runs, two at once, the same sweep.csv, a log per run"
