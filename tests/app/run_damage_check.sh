#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Load programmes and irreversible damage through the app (docs/fracture.md, docs/decks.md):
#  1. Monte Carlo, tiny.toml loaded to 0.012, unloaded to 0.004, reloaded to 0.016: the rows follow
#     the path, damage = "auto" turned irreversible (summary.json says so and why), the energy of
#     fracture never decreases, the charts are drawn;
#  2. killed right after a checkpoint on the unloading leg and restarted: every column of
#     steps.csv but the wall time equals the direct run's;
#  3. the same programme with damage = "reversible" runs and says so; final_displacement given
#     beside programme, a target repeating the one before, a non-number: exit 2 naming the key;
#  4. dynamics, tiny_dynamic.toml loaded to 0.008 mm and back to 0: irreversible, books closed,
#     killed after a checkpoint and restarted: series.csv equals the direct run's.
#   run_damage_check.sh NACRE_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$1"; src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"; cd "$work"
fail=0
ok() { echo "ok: $*"; }
bad() { echo "FAIL: $*"; fail=1; }

# ---- 1. Monte Carlo programme
sed 's/^final_displacement = .*/programme = [0.012, 0.004, 0.016]/' "$src/tests/app/tiny.toml" > prog.toml
"$exe" prog.toml -o direct > direct.log 2>&1 || { cat direct.log; bad "the programme run failed"; }
python3 - direct <<'PY' && ok "rows follow the programme, damage auto -> irreversible, fracture energy never decreases" || bad "Monte Carlo programme outputs"
import csv, json, sys
out = sys.argv[1]
s = json.load(open(f"{out}/summary.json"))
assert s["damage"] == "irreversible" and s["damage_rule"] == "auto", (s["damage"], s["damage_rule"])
assert s["programme"] == [0.012, 0.004, 0.016], s["programme"]
assert s["crack"]["fracture_energy_is"] == "dissipated", s["crack"]
rows = list(csv.DictReader(open(f"{out}/steps.csv")))
d = [float(r["displacement"]) for r in rows]
want = [0.004, 0.008, 0.012, 0.008, 0.004, 0.008, 0.012, 0.016]
assert len(d) == len(want) and all(abs(a - b) < 1e-12 for a, b in zip(d, want)), d
w = [float(r["fracture_energy"]) for r in rows]
assert all(b >= a for a, b in zip(w, w[1:])), w
assert w[-1] > 0, w
f = [float(r["reaction"]) for r in rows]
assert f[3] < f[1], f"unloading at D = 0.008 ({f[3]}) not below loading ({f[1]}): no hysteresis"
print(f"  D path {d}; reaction at 0.008 up {f[1]:.4g}, down {f[3]:.4g}; dissipated {w[-1]:.4g}")
PY
[ -s direct/energy_force.png ] && [ -s direct/r_curve.png ] && ok "charts drawn" || bad "charts missing"

# ---- 2. kill after the 5th checkpoint (step 4, on the unloading leg), restart
NACRE_INJECT_KILL_AFTER=checkpoint.h5:5 "$exe" prog.toml -o killed -q > /dev/null 2>&1; rc=$?
[ "$rc" -eq 137 ] || bad "the injected kill did not happen (exit $rc)"
"$exe" prog.toml -o killed -q --restart killed/checkpoint.h5 || bad "restart on the unloading leg failed"
if diff <(cut -d, -f1-12,14- direct/steps.csv) <(cut -d, -f1-12,14- killed/steps.csv) > diff.txt; then
  ok "restart from the unloading leg equals the direct run (every column but seconds)"
else
  cat diff.txt; bad "restarted programme differs from the direct run"
fi

# ---- 3. reversible on request; bad programmes
sed 's/^x2 = 0.004/x2 = 0.004\ndamage = "reversible"/' prog.toml > rev.toml
"$exe" rev.toml -o rev -q || bad "reversible programme failed"
python3 -c "import json; s = json.load(open('rev/summary.json')); assert s['damage'] == 'reversible' and s['damage_rule'] == 'deck', s" \
  && ok "damage = \"reversible\" kept on request" || bad "reversible summary"
expect2() {  # expect exit 2 and the message
  local pat="$1"; shift
  "$exe" "$@" -q > out.txt 2>&1; local rc=$?
  if [ "$rc" -eq 2 ] && grep -Eq "$pat" out.txt; then ok "$* -> 2: $(head -c 160 out.txt)"; else bad "$* -> $rc: $(cat out.txt)"; fi
}
sed 's/^programme = .*/programme = [0.012, 0.004, 0.016]\nfinal_displacement = 0.016/' prog.toml > both.toml
expect2 "load.final_displacement: given with programme" both.toml -o x
sed 's/^programme = .*/programme = [0.012, 0.012]/' prog.toml > repeat.toml
expect2 "load.programme: entry 2 .*repeats" repeat.toml -o x
sed 's/^programme = .*/programme = [0.012, "a"]/' prog.toml > word.toml
expect2 "load.programme: an entry is not a number" word.toml -o x
sed 's/^x2 = 0.004/x2 = 0.004\ndamage = "sometimes"/' prog.toml > dmg.toml
expect2 "mortar.damage.*expected" dmg.toml -o x

# ---- 4. dynamics: to 0.008 mm and back to 0 (irreversible by auto), kill and restart
sed -e 's/^final_displacement = .*/programme = [0.008, 0.0]/' -e 's/^end_time = .*/end_time = 1e-5/' \
  "$src/tests/app/tiny_dynamic.toml" > dyn.toml
"$exe" dyn.toml -o ddirect -q || bad "dynamic programme run failed"
python3 - ddirect <<'PY' && ok "dynamic programme: irreversible, books closed, D back to 0" || bad "dynamic programme outputs"
import csv, json, sys
out = sys.argv[1]
s = json.load(open(f"{out}/summary.json"))
assert s["damage"] == "irreversible" and s["programme"] == [0.008, 0.0], s
rows = list(csv.DictReader(open(f"{out}/series.csv")))
d = [float(r["displacement"]) for r in rows]
assert max(d) > 0.0079 and abs(d[-1]) < 1e-12, (max(d), d[-1])
res = max(abs(float(r["balance_residual"])) for r in rows[2:])
assert res < 1e-3, res
w = [float(r["fracture_energy"]) for r in rows]
assert all(b >= a for a, b in zip(w, w[1:])), "dissipated energy decreased"
print(f"  peak D {max(d):.4g} mm, end D {d[-1]}, worst balance {res:.2e}, dissipated {w[-1]:.4g} N mm")
PY
NACRE_INJECT_KILL_AFTER=checkpoint.h5:3 "$exe" dyn.toml -o dkilled -q > /dev/null 2>&1; rc=$?
[ "$rc" -eq 137 ] || bad "the injected dynamic kill did not happen (exit $rc)"
"$exe" dyn.toml -o dkilled -q --restart dkilled/checkpoint.h5 || bad "dynamic restart failed"
python3 - ddirect dkilled <<'PY' && ok "dynamic restart equals the direct run (every column but seconds)" || bad "dynamic restart differs"
import csv, sys
a = list(csv.DictReader(open(f"{sys.argv[1]}/series.csv")))
b = list(csv.DictReader(open(f"{sys.argv[2]}/series.csv")))
assert len(a) == len(b), (len(a), len(b))
for ra, rb in zip(a, b):
    for k in ra:
        if k != "seconds":
            assert ra[k] == rb[k], (k, ra[k], rb[k])
PY
exit $fail
