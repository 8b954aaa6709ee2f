#!/usr/bin/env bash
# The run-time backend choice (`--backend`, include/nacre/core/backend.hpp) through the app:
#  1. `nacre --backend list` names this build's backends, the default first;
#  2. the small dynamic deck, BE and BIE, run on every listed backend: series.csv identical in
#     every column but seconds (nacre promises the same bits on every host backend), and
#     summary.json names the backend it ran on;
#  3. an unknown backend is refused (exit 2) naming the enabled ones, and a Monte Carlo deck on a
#     backend other than the default is refused (the rigid family runs on the default one);
#  4. a run stopped half-way on the first backend, continued on the last one (--restart --extend)
#     gives the direct run's series (every column but seconds): the checkpoint moves between
#     backends of one build, and records the one it was written on;
#  5. `nacre bench` on the small BE deck (every backend) and the small Monte Carlo deck: bench.csv,
#     bench.json and bench.png written, every backend timed with its phases (the solver's regions),
#     its triad and FMA bounds, and the agreement check "bit-identical"; a bad backend exits 2.
#   run_backend_check.sh NACRE_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$1"; src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"; cd "$work"
. "$src/tests/app/checks_lib.sh"
mapfile -t listed < <("$exe" --backend list)
[ "${#listed[@]}" -ge 1 ] && [[ "${listed[0]}" == *"(default)" ]] && ok "backends: ${listed[*]}" \
  || bad "--backend list printed '${listed[*]}'"
backends=()
for l in "${listed[@]}"; do backends+=("${l%% *}"); done
sed 's/^method = "be"/method = "bie"/' "$src/tests/app/tiny_dynamic.toml" > tiny_bie.toml
for deck in "$src/tests/app/tiny_dynamic.toml" tiny_bie.toml; do
  name=$(basename "$deck" .toml)
  for b in "${backends[@]}"; do
    if "$exe" "$deck" --backend "$b" -o "${name}_$b" -q > "run_${name}_$b.txt" 2>&1; then ok "$name on $b"
    else bad "$name on $b: $(tail -3 "run_${name}_$b.txt")"; fi
  done
  python3 - "$name" "${backends[@]}" <<'PY' && ok "$name: the same series on ${backends[*]}" || bad "$name: backends disagree"
import csv, json, sys
name, backends = sys.argv[1], sys.argv[2:]
tables = {}
for b in backends:
    s = json.load(open(f"{name}_{b}/summary.json"))
    assert s["backend"] == b and s["status"] == "done", (b, s["backend"], s["status"])
    rows = list(csv.DictReader(open(f"{name}_{b}/series.csv")))
    assert len(rows) > 5
    tables[b] = [{k: v for k, v in r.items() if k != "seconds"} for r in rows]
ref = tables[backends[0]]
for b in backends[1:]:
    assert tables[b] == ref, f"{b} differs from {backends[0]}"
PY
done
sed 's/^end_time = 6e-6/end_time = 3e-6/' "$src/tests/app/tiny_dynamic.toml" > half.toml
first="${backends[0]}"; last="${backends[${#backends[@]}-1]}"
if "$exe" half.toml --backend "$first" -o moved -q > half.txt 2>&1 &&
   "$exe" "$src/tests/app/tiny_dynamic.toml" --backend "$last" -o moved --restart moved/checkpoint.h5 --extend > moved.txt 2>&1; then
  python3 - "$first" "$last" <<'PY' && ok "restart moved from $first to $last: the direct run's series" || bad "restart across backends"
import csv, json, sys
first, last = sys.argv[1:]
strip = lambda f: [{k: v for k, v in r.items() if k != "seconds"} for r in csv.DictReader(open(f))]
assert strip("moved/series.csv") == strip(f"tiny_dynamic_{first}/series.csv")
assert json.load(open("moved/summary.json"))["backend"] == last
PY
  grep -q "restarting from" moved.txt || bad "no restart line in the log"
else
  bad "half run or restart failed: $(tail -3 half.txt moved.txt)"
fi
# a backend's name is case-insensitive ("OpenMP" as Kokkos spells it), summary.json the canonical name
if "$exe" "$src/tests/app/tiny_dynamic.toml" --backend "${first^^}" -o upper -q > upper.txt 2>&1 &&
   python3 -c "import json,sys; sys.exit(json.load(open('upper/summary.json'))['backend'] != '$first')"; then
  ok "--backend ${first^^} runs on $first"
else
  bad "--backend ${first^^}: $(tail -2 upper.txt)"
fi
expect 2 "not a backend of this build; expected one of" "$exe" "$src/tests/app/tiny_dynamic.toml" --backend no-such-backend -o unknown
if [ "${#backends[@]}" -ge 2 ]; then
  expect 2 "Monte Carlo solver runs on the default backend" "$exe" "$src/tests/app/tiny.toml" --backend "${backends[1]}" -o mc_other
else
  ok "one backend in this build: the Monte Carlo refusal of another needs two"
fi
if "$exe" bench "$src/tests/app/tiny_dynamic.toml" --steps 50 --repeat 2 -o bench_dyn > bench_dyn.txt 2>&1 &&
   "$exe" bench "$src/tests/app/tiny.toml" --cycles 5 --repeat 2 -o bench_mc > bench_mc.txt 2>&1; then
  python3 - "${backends[@]}" <<'PY' && ok "bench: files, phases, bounds and agreement on ${backends[*]}" || bad "bench outputs"
import csv, json, os, sys
backends = sys.argv[1:]
for out, solver, phase in (("bench_dyn", "dynamics", "nacre::dyn::interface_force"), ("bench_mc", "monte-carlo", None)):
    for f in ("bench.csv", "bench.json", "bench.png"):
        assert os.path.getsize(f"{out}/{f}") > 0, (out, f)
    j = json.load(open(f"{out}/bench.json"))
    assert j["solver"] == solver and j["agreement"] == "bit-identical", (out, j["agreement"])
    listed = backends if solver == "dynamics" else backends[:1]
    assert list(j["backends"]) == listed, (out, list(j["backends"]))
    for b, e in j["backends"].items():
        assert e["triad_gb_per_s"] > 0 and e["fma_gflop_per_s"] > 0 and e["seconds_per_unit"] > 0, e
        assert e["repeats_bit_identical"], b
        assert e["phases"] and (phase is None or e["phases"][phase] > 0), e["phases"]
        assert sum(v for k, v in e["phases"].items() if k != "nacre::dyn::advance") <= 1.5 * e["seconds_per_unit"] + 1e-4
    rows = list(csv.DictReader(open(f"{out}/bench.csv")))
    assert {r["backend"] for r in rows} == set(listed) and {r["repeat"] for r in rows} == {"0", "1"}
PY
else
  bad "nacre bench failed: $(tail -3 bench_dyn.txt bench_mc.txt)"
fi
expect 2 "not one this build can run" "$exe" bench "$src/tests/app/tiny_dynamic.toml" --backends no-such -o bench_bad

[ "$fails" -eq 0 ] || { echo "$fails check(s) failed"; exit 1; }
echo "all backend checks passed"
