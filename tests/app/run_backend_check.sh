#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# The run-time backend choice (`--backend`, include/nacre/core/backend.hpp) through the app:
#  1. `nacre --backend list` names this build's backends, the default first; `--critical-step`
#     runs on the backend asked for (the same step on every host backend);
#  2. the small dynamic deck, BE and BIE, run on every listed backend: series.csv identical in
#     every column but seconds (nacre promises the same bits on every host backend), and
#     summary.json names the backend it ran on;
#  3. an unknown backend is refused (exit 2) naming the enabled ones; the small Monte Carlo deck
#     runs on every listed backend with the same steps.csv (but seconds), and a Monte Carlo run
#     stopped half-way on the first backend continues on the last one to the direct run's rows;
#  4. a run stopped half-way on the first backend, continued on the last one (--restart --extend)
#     gives the direct run's series (every column but seconds): the checkpoint moves between
#     backends of one build, and records the one it was written on;
#  (in a CUDA build the host backends are compared with each other; the device runs both families
#  and its checkpoint is refused on the host: step 6)
#  5. `nacre bench` on the small BE deck and the small Monte Carlo deck (cycles, and load steps
#     with the AES-CTR source), every backend: bench.csv,
#     bench.json and bench.png written, every backend timed with its phases (the solver's regions),
#     its triad and FMA bounds, and the agreement check "bit-identical"; a bad backend exits 2;
#     --compare against another bench's state: the same state passes, another seed fails (exit 1)
#     beyond a tight tolerance, another deck is refused (exit 2); the comparison is per array (u
#     moved alone is caught in u), and a reference of another layout is refused writing nothing;
#  6. (a CUDA build) the device runs both families; its checkpoint is refused on a host backend.
#   run_backend_check.sh NACRE_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$1"; src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"; cd "$work"
. "$src/tests/app/checks_lib.sh"
mapfile -t listed < <("$exe" --backend list)
[ "${#listed[@]}" -ge 1 ] && [[ "${listed[0]}" == *"(default)" ]] && ok "backends: ${listed[*]}" \
  || bad "--backend list printed '${listed[*]}'"
# the backends compared bit for bit: the host ones (in a CUDA build the device is checked apart:
# its arithmetic differs, so its checkpoints do not move to the host)
backends=(); device=""
for l in "${listed[@]}"; do
  b="${l%% *}"
  case "$b" in cuda|hip|sycl) device="$b" ;; *) backends+=("$b") ;; esac
done
[ "${#backends[@]}" -ge 1 ] || { bad "no host backend listed: ${listed[*]}"; exit 1; }
sed 's/^method = "be"/method = "bie"/' "$src/tests/app/tiny_dynamic.toml" > tiny_bie.toml
# --critical-step on the backend asked for: the same bisected step on every host backend (and,
# where a device is listed, a finite step there too)
crit=()
for b in "${backends[@]}" $device; do
  crit+=("$("$exe" "$src/tests/app/tiny_dynamic.toml" --critical-step -q --backend "$b" 2> "crit_$b.txt")")
done
python3 - "${#backends[@]}" "${crit[@]}" <<'PY' && ok "--critical-step --backend: ${crit[*]}" || bad "--critical-step per backend: ${crit[*]} $(cat crit_*.txt | head -3)"
import math, sys
n, steps = int(sys.argv[1]), [float(x) for x in sys.argv[2:]]
assert all(math.isfinite(h) and h > 0 for h in steps), steps
assert len(set(steps[:n])) == 1, steps
PY
# (the full report names the backend it ran on: a --backend ignored would show)
for b in "${backends[@]}" $device; do
  "$exe" "$src/tests/app/tiny_dynamic.toml" --critical-step --backend "$b" > "crit_full_$b.txt" 2>&1
  grep -q "^nacre: .* bricks, method .*, on $b\$" "crit_full_$b.txt" \
    && ok "--critical-step --backend $b: says it ran on $b" || bad "--critical-step --backend $b does not name $b"
done
expect 2 "not a backend of this build" "$exe" "$src/tests/app/tiny_dynamic.toml" --critical-step --backend no-such
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
# the Monte Carlo family on every backend: the same rows; a run moved between backends half-way
for b in "${backends[@]}"; do
  "$exe" "$src/tests/app/tiny.toml" --backend "$b" -o "mc_$b" -q > "mc_$b.txt" 2>&1 || bad "tiny.toml on $b: $(tail -3 "mc_$b.txt")"
done
sed 's/^final_displacement = 0.012/final_displacement = 0.008/' "$src/tests/app/tiny.toml" > mc_half.toml
if "$exe" mc_half.toml --backend "$first" -o mc_moved -q > mc_half.txt 2>&1 &&
   "$exe" "$src/tests/app/tiny.toml" --backend "$last" -o mc_moved --restart mc_moved/checkpoint.h5 --extend > mc_moved.txt 2>&1; then
  python3 - "${backends[@]}" <<'PY' && ok "Monte Carlo: the same rows on ${backends[*]}, and moved from $first to $last" || bad "Monte Carlo across backends"
import csv, json, sys
backends = sys.argv[1:]
strip = lambda f: [{k: v for k, v in r.items() if k != "seconds"} for r in csv.DictReader(open(f))]
ref = strip(f"mc_{backends[0]}/steps.csv")
assert len(ref) >= 3
for b in backends:
    s = json.load(open(f"mc_{b}/summary.json"))
    assert s["backend"] == b and s["execution_space"].lower() == b, (b, s["backend"], s["execution_space"])
    assert strip(f"mc_{b}/steps.csv") == ref, f"{b} differs from {backends[0]}"
assert strip("mc_moved/steps.csv") == ref, "the moved run's rows differ"
assert json.load(open("mc_moved/summary.json"))["backend"] == backends[-1]
PY
  grep -q "restarting from" mc_moved.txt || bad "no restart line in the Monte Carlo log"
else
  bad "Monte Carlo half run or restart failed: $(tail -3 mc_half.txt mc_moved.txt)"
fi
sed 's/^seed = 5/seed = 5\ngenerator = "aes-ctr"/' "$src/tests/app/tiny.toml" > tiny_aes.toml
hostlist=$(IFS=,; echo "${backends[*]}")
if "$exe" bench "$src/tests/app/tiny_dynamic.toml" --steps 50 --repeat 2 --backends "$hostlist" -o bench_dyn > bench_dyn.txt 2>&1 &&
   "$exe" bench "$src/tests/app/tiny.toml" --cycles 5 --repeat 2 --backends "$hostlist" -o bench_mc > bench_mc.txt 2>&1 &&
   "$exe" bench tiny_aes.toml --steps 2 --repeat 2 --backends "$hostlist" -o bench_aes > bench_aes.txt 2>&1; then
  python3 - "${backends[@]}" <<'PY' && ok "bench: files, phases, bounds and agreement on ${backends[*]}" || bad "bench outputs"
import csv, json, os, sys
backends = sys.argv[1:]
for out, solver, phase in (("bench_dyn", "dynamics", "nacre::dyn::interface_force"),
                           ("bench_mc", "monte-carlo", "nacre::mc::sweep"), ("bench_aes", "monte-carlo", "nacre::mc::polish")):
    for f in ("bench.csv", "bench.json", "bench.png"):
        assert os.path.getsize(f"{out}/{f}") > 0, (out, f)
    j = json.load(open(f"{out}/bench.json"))
    assert j["solver"] == solver and j["agreement"] == "bit-identical", (out, j["agreement"])
    listed = backends
    assert list(j["backends"]) == listed, (out, list(j["backends"]))
    assert j["unit"] == {"bench_dyn": "step", "bench_mc": "cycle", "bench_aes": "load_step"}[out], j["unit"]
    assert "FMA 2" in j["flop_convention"], j["flop_convention"]
    for b, e in j["backends"].items():
        assert e["triad_gb_per_s"] > 0 and e["fma_gflop_per_s"] > 0 and e["seconds_per_unit"] > 0, e
        assert 0 < e["fraction_of_triad"] < 10 and e["bytes_per_unit"] > 0, e
        # the FMA bound's fraction: the flops a unit does (counted on the state, core/flop_count.hpp);
        # none for load steps (their Newton / FIRE flops are not counted)
        if out == "bench_aes":
            assert e["fraction_of_fma"] is None and e["flops_per_unit"] is None, e
        else:
            assert 0 < e["fraction_of_fma"] < 10 and e["flops_per_unit"] > 0, e
        # the uniform source's rate where it fills a table (AES-CTR), none for Philox in the sweep
        assert (e["rng_gbit_per_s"] is not None and e["rng_gbit_per_s"] > 0) == (out == "bench_aes"), e
        assert e["repeats_bit_identical"], b
        assert e["phases"] and (phase is None or e["phases"][phase] > 0), e["phases"]
        # each phase (an inclusive region: nested ones repeat their parts) lies within the total
        assert max(e["phases"].values()) <= 1.05 * e["seconds_per_unit"] + 1e-4, e["phases"]
    rows = list(csv.DictReader(open(f"{out}/bench.csv")))
    assert {r["backend"] for r in rows} == set(listed) and {r["repeat"] for r in rows} == {"0", "1"}
PY
else
  bad "nacre bench failed: $(tail -3 bench_dyn.txt bench_mc.txt bench_aes.txt)"
fi
# BIE's flops: the split step (this damped deck's auto scheme) and the iterated one (two
# iterations: two J^-1 applies, three K applies, the residual) are counted, so each has a fraction
# of the FMA bound, in the order of their work: iterated above split above BE on the same deck
sed 's/^method = "bie"/method = "bie"\nbie_scheme = "iterate"/' tiny_bie.toml > tiny_bie_iter.toml
if "$exe" bench tiny_bie.toml --steps 20 --repeat 1 --backends "$last" -o bench_bie > bench_bie.txt 2>&1 &&
   "$exe" bench tiny_bie_iter.toml --steps 20 --repeat 1 --backends "$last" -o bench_bie_iter > bench_bie_iter.txt 2>&1; then
  python3 - "$last" <<'PY' && ok "bench: BIE's split and iterated steps counted (fractions of the FMA bound, in the order of their work)" || bad "bench BIE flops"
import json, sys
b = sys.argv[1]
split = json.load(open("bench_bie/bench.json"))["backends"][b]
it = json.load(open("bench_bie_iter/bench.json"))["backends"][b]
be = json.load(open("bench_dyn/bench.json"))["backends"][b]
for e in (split, it):
    assert 0 < e["fraction_of_fma"] < 10, e
assert it["flops_per_unit"] > split["flops_per_unit"] > be["flops_per_unit"], (it, split, be)
PY
else
  bad "nacre bench on BIE decks failed: $(tail -3 bench_bie.txt bench_bie_iter.txt)"
fi
# the iterated scheme without damping (C = 0, the block form): every pass on the kept force is the
# reduced one, and only the two-iteration start is positions-only. So 2 -> 3 iterations adds one
# iteration pass plus the full start's extra (apply + update - the positions-only apply: 2 nd^2 +
# 3 nd per element), 3 -> 4 one iteration pass: the two steps differ by exactly that extra
for k in 2 3 4; do
  sed -e "s/^method = \"be\"/method = \"bie\"\nbie_iterations = $k/" -e 's/^damping = "table"/damping = "none"/' \
    "$src/tests/app/tiny_dynamic.toml" > "undamped_$k.toml"
done
if (for k in 2 3 4; do "$exe" bench "undamped_$k.toml" --steps 3 --repeat 1 --backends "$last" -o "bench_ud_$k" > "bench_ud_$k.txt" 2>&1 || exit 1; done); then
  python3 - "$last" <<'PY' && ok "bench: BIE's iterated count steps as its passes do (undamped, 2-4 iterations)" || bad "bench BIE iterated count"
import json, math, sys
f = {k: json.load(open(f"bench_ud_{k}/bench.json")) for k in (2, 3, 4)}
n = f[2]["bricks"]  # one bolted element per brick
c = {k: f[k]["backends"][sys.argv[1]]["flops_per_unit"] for k in f}
extra = ((c[3] - c[2]) - (c[4] - c[3])) / n  # 2 nd^2 + 3 nd
nd = (-3 + math.sqrt(9 + 8 * extra)) / 4
assert c[4] > c[3] > c[2] > 0 and nd in (6, 8, 10, 12, 14, 16), (c, extra, nd)
PY
else
  bad "nacre bench on undamped BIE decks failed: $(tail -3 bench_ud_*.txt)"
fi
expect 2 "not one this build can run" "$exe" bench "$src/tests/app/tiny_dynamic.toml" --backends no-such -o bench_bad
expect 2 "lists $first twice" "$exe" bench "$src/tests/app/tiny_dynamic.toml" --steps 2 --backends "$first,${first^^}" -o bench_bad
expect 2 "got an empty one" "$exe" bench "$src/tests/app/tiny_dynamic.toml" --steps 2 --backends "" -o bench_bad
expect 2 "expected a positive finite number" "$exe" bench "$src/tests/app/tiny_dynamic.toml" --steps 2 --tolerance nan -o bench_bad
[ ! -e bench_bad ] && ok "refused benches wrote nothing" || bad "a refused bench wrote $(ls bench_bad)"
# --compare: another bench's state (here this build's own, on the last backend: bit-identical);
# another seed differs (beyond a tolerance of 1e-300: exit 1); another deck is refused (exit 2)
if "$exe" bench tiny_aes.toml --steps 2 --repeat 1 --backends "$last" --compare bench_aes -o bench_cmp > bench_cmp.txt 2>&1 &&
   grep -q "bit-identical" bench_cmp.txt &&
   python3 -c "import json,sys; c=json.load(open('bench_cmp/bench.json'))['compared_to']; sys.exit(not c['backends']['$last']['within'])"; then
  ok "bench --compare: the same state on $last as bench_aes's"
else
  bad "bench --compare: $(tail -3 bench_cmp.txt)"
fi
sed 's/^seed = 5/seed = 6/' tiny_aes.toml > tiny_aes6.toml
expect 1 "beyond the tolerance" "$exe" bench tiny_aes6.toml --steps 2 --repeat 1 --backends "$hostlist" --compare bench_aes --tolerance 1e-300 -o bench_cmp6
expect 2 "compare the same deck and units" "$exe" bench "$src/tests/app/tiny_dynamic.toml" --steps 5 --repeat 1 --compare bench_aes -o bench_cmp_dyn
# per array: a reference whose displacements (u) alone are moved by 1e-4 of their own largest
# value is beyond a tolerance of 1e-5, named "u", though the move is far below 1e-5 of the
# state's largest value (the accelerations); a reference with another array layout is refused
# (exit 2) before anything is written
mkdir -p bench_dyn_u bench_dyn_layout
python3 - <<'PY' || bad "could not write the moved references"
import json, struct
j = json.load(open("bench_dyn/bench.json"))
flat = list(struct.unpack(f"{j['state_file']['values']}d", open("bench_dyn/state.bin", "rb").read()))
at, arrays = 0, {}
for a in j["state_file"]["arrays"]:
    arrays[a["name"]] = (at, a["values"]); at += a["values"]
u0, nu = arrays["u"]
scale = max(abs(x) for x in flat[u0:u0 + nu])
assert scale > 0 and scale < 1e-4 * max(abs(x) for x in flat), (scale, max(abs(x) for x in flat))
k = max(range(u0, u0 + nu), key=lambda i: abs(flat[i]))
flat[k] += 1e-4 * scale
for d, js in (("bench_dyn_u", j), ("bench_dyn_layout", dict(j, state_file=dict(j["state_file"], arrays=j["state_file"]["arrays"][::-1])))):
    open(f"{d}/state.bin", "wb").write(struct.pack(f"{len(flat)}d", *flat))
    json.dump(js, open(f"{d}/bench.json", "w"))
PY
expect 1 "beyond the tolerance" "$exe" bench "$src/tests/app/tiny_dynamic.toml" --steps 50 --repeat 1 --backends "$last" \
  --compare bench_dyn_u --tolerance 1e-5 -o bench_cmp_u
python3 -c "import json,sys; c=json.load(open('bench_cmp_u/bench.json'))['compared_to']['backends']['$last']; sys.exit(not (c['largest_relative_in'] == 'u' and 5e-5 < c['relative'] < 2e-4))" \
  && ok "bench --compare: a move of 1e-4 in u alone is caught in u" || bad "bench --compare per array: $(grep -o '"largest_relative_in.*' bench_cmp_u/bench.json | head -2)"
expect 2 "its state holds" "$exe" bench "$src/tests/app/tiny_dynamic.toml" --steps 50 --repeat 1 --backends "$last" \
  --compare bench_dyn_layout -o bench_cmp_layout
[ ! -e bench_cmp_layout ] && ok "bench --compare: a refused reference leaves no output" || bad "bench_cmp_layout written"
# a device (a CUDA build on a GPU machine): it runs both families, and its checkpoint is refused on
# the host (their arithmetic differs) naming the backend to continue on
if [ -n "$device" ]; then
  if "$exe" half.toml --backend "$device" -o dev_half -q > dev_half.txt 2>&1; then ok "dynamics on $device"
  else bad "dynamics on $device: $(tail -3 dev_half.txt)"; fi
  "$exe" "$src/tests/app/tiny.toml" --backend "$device" -o "mc_$device" -q > "mc_$device.txt" 2>&1 \
    && ok "Monte Carlo on $device" || bad "Monte Carlo on $device: $(tail -3 "mc_$device.txt")"
  expect 2 "restart it with --backend $device" "$exe" "$src/tests/app/tiny_dynamic.toml" --backend "$first" \
    -o dev_moved --restart dev_half/checkpoint.h5 --extend
fi

[ "$fails" -eq 0 ] || { echo "$fails check(s) failed"; exit 1; }
echo "all backend checks passed"
