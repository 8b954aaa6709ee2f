#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# bench_all.sh — every `nacre bench` figure in one sitting: the README decks and scaled decks on
# every backend of the build, the explicit methods against BIE at stiffness ratio 500, and one
# table of it all. Written for a short run on a GPU machine (perf/gpu/device_run.sh calls it
# with the carried CUDA binary) and rehearsed on a CPU with --quick.
#
#   perf/bench_all.sh [--quick] [--sizes N,N,...] [--backends a,b] [--readme-backends a,b] "NACRE COMMAND" OUTDIR
#     NACRE COMMAND  how to start nacre, e.g. build/kokkos-4.6/src/nacre or "perf/gpu/bundle/run nacre"
#     --sizes        scaled specimens in bricks (default 100000,1000000,4000000; --quick 10000,30000)
#     --backends     the backends of every bench (default: all the build has); --readme-backends
#                    those of the README decks alone (e.g. cuda,openmp,serial where Serial is too
#                    slow for the scaled specimens)
# Run from the repository root (it reads inputs/ and perf/scaled_deck.sh). Every bench has a time
# limit (BENCH_TIMEOUT s, default 240) so one stuck size cannot eat the sitting; what finished is
# kept. OUTDIR gets one folder per bench (bench.csv, bench.json, bench.png, the deck, the log),
# bench_all.csv (one row per deck, size, method and backend) and summary.json: MC trials/s and
# the fraction of the triad bound, the dynamic step against the triad bound (BE within 2x is the
# target at 1M bricks), BIE's speed-up over BE and UE at ratio 500 in simulated time per second,
# the uniform source's Gbit/s (AES-CTR inside the Monte Carlo run), and the agreement of every bench.
set -uo pipefail
quick=0; sizes=""; backends=(); readme_backends=()
while [ $# -gt 2 ]; do
  case "$1" in
    --quick) quick=1; shift ;;
    --sizes) sizes="$2"; shift 2 ;;
    --backends) backends=(--backends "$2"); shift 2 ;;
    --readme-backends) readme_backends=(--backends "$2"); shift 2 ;;
    *) echo "bench_all.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
[ $# -eq 2 ] || { sed -n '2,17p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
read -ra nacre <<< "$1"
out="$(realpath -m "$2")"; mkdir -p "$out"
[ -f inputs/default.toml ] && [ -x perf/scaled_deck.sh ] || { echo "bench_all.sh: run from the repository root" >&2; exit 2; }
[ -n "$sizes" ] || { [ $quick = 1 ] && sizes=10000,30000 || sizes=100000,1000000,4000000; }
if [ $quick = 1 ]; then cyc=5; steps=20; bie_steps=5; else cyc=20; steps=100; bie_steps=20; fi
limit="${BENCH_TIMEOUT:-240}"
t0=$SECONDS
failed=()
say() { echo "[bench_all +$(( SECONDS - t0 ))s] $*" | tee -a "$out/bench_all.log"; }

# bench NAME DECK ARGS...: one `nacre bench` into OUTDIR/NAME (on bench_backends)
bench() {
  local name="$1" deck="$2"; shift 2
  local bb=("${bench_backends[@]}")
  mkdir -p "$out/$name"
  cp "$deck" "$out/$name/deck.toml"
  say "$name: nacre bench $(basename "$deck") $*"
  timeout "$limit" "${nacre[@]}" bench "$out/$name/deck.toml" "${bb[@]}" --repeat 2 -o "$out/$name" "$@" \
    > "$out/$name/bench.log" 2>&1
    local rc=$?
  [ $rc = 0 ] || { say "  $name: exit $rc ($(tail -n 1 "$out/$name/bench.log"))"; failed+=("$name"); }
  rm -f "$out/$name/state.bin"  # (large; the agreement is in bench.json)
  tail -n 4 "$out/$name/bench.log" | sed 's/^/    /' | tee -a "$out/bench_all.log" > /dev/null
}

# a dynamic deck scaled to about N bricks (the README deck has 2,100), method and step set
dyn_deck() {  # dyn_deck SOURCE N METHOD > deck
  local src="$1" n="$2" method="$3"
  python3 - "$src" "$n" "$method" <<'PY'
import math, re, sys
src, n, method = sys.argv[1], int(sys.argv[2]), sys.argv[3]
text = open(src).read()
s = math.sqrt(n / 2100.0) if n > 0 else 1.0
def value(key):
    return float(re.search(rf"^{key} = ([0-9.eE+-]+)", text, flags=re.M).group(1))
def scale(key, text, unit=None):
    # the README deck's shape kept: the width in whole bricks, the height in an even number of
    # rows (the notch at mid-height on a bed joint). Scaled by s alone, the edge cut slivers and
    # the notch halved the bricks it crossed, and the smallest piece set the explicit methods'
    # step: BE's was 1.4e-10 s at 100k bricks (485 slivers), 1.15e-9 s at 1M, 2.9e-9 s with
    # whole bricks, so BIE's speed-up over BE depended on where the edge and the notch fell
    def new(m):
        x = float(m.group(1)) * s
        if unit:
            x = max(1, round(x / unit)) * unit
        return f"{key} = {x:.10g}"
    return re.sub(rf"^{key} = ([0-9.eE+-]+)", new, text, flags=re.M)
text = scale("width", text, value("brick_width"))
text = scale("height", text, 2 * value("brick_height"))
text = scale("notch_length", text)
text = re.sub(r'^method = "\w+"', f'method = "{method}"', text, flags=re.M)
if method != "bie":  # the explicit methods at 0.9 of their own critical step (the run's estimate)
    text = re.sub(r"^bie_solve = .*\n", "", text, flags=re.M)
    text = re.sub(r"^dt = .*\n", "dt_fraction = 0.9\n", text, flags=re.M)
text = re.sub(r"^dump_interval = .*", "dump_interval = 0", text, flags=re.M)
sys.stdout.write(text)
PY
}

say "nacre: ${nacre[*]}; sizes $sizes; $(nproc) cores"
"${nacre[@]}" --backend list > "$out/backends.txt" 2>&1; say "backends: $(tr '\n' ' ' < "$out/backends.txt")"
command -v nvidia-smi > /dev/null && nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader \
  > "$out/gpu.txt" 2>&1

# 1. the README decks as they are
bench_backends=("${backends[@]}")
[ ${#readme_backends[@]} -gt 0 ] && bench_backends=("${readme_backends[@]}")
bench readme_default inputs/default.toml --cycles "$cyc"
bench readme_dynamic inputs/dynamic.toml --steps "$steps"
bench readme_dynamic_bie inputs/dynamic_bie.toml --steps "$bie_steps"
# 2. Monte Carlo with the AES-CTR source (the uniform source's Gbit/s inside the run)
if grep -q '^generator = ' inputs/default.toml; then
  sed 's/^generator = .*/generator = "aes-ctr"/' inputs/default.toml > "$out/default_aes.toml"
else
  sed 's/^seed = \(.*\)/seed = \1\ngenerator = "aes-ctr"/' inputs/default.toml > "$out/default_aes.toml"
fi
bench readme_default_aes "$out/default_aes.toml" --cycles "$cyc"
# 3. scaled: Monte Carlo sweeps; UE, BE and BIE at ratio 500 (the speed-up of Fig. 4.9)
bench_backends=("${backends[@]}")
IFS=, read -ra ns <<< "$sizes"
for n in "${ns[@]}"; do
  perf/scaled_deck.sh "$n" 0.16 > "$out/mc_$n.toml"
  bench "mc_$n" "$out/mc_$n.toml" --cycles "$cyc"
  for m in ue be bie; do
    dyn_deck inputs/dynamic_bie.toml "$n" "$m" > "$out/r500_${m}_$n.toml"
    if [ "$m" = bie ]; then k=$bie_steps; else k=$steps; fi
    bench "r500_${m}_$n" "$out/r500_${m}_$n.toml" --steps "$k"
  done
done

# 4. one table and the headline figures
python3 - "$out" <<'PY' 2>&1 | tee -a "$out/bench_all.log"
import csv, glob, json, os, sys
out = sys.argv[1]
rows, summary = [], {"benches": {}, "bie_speedup_ratio500": {}, "agreement": {}}
for f in sorted(glob.glob(os.path.join(out, "*", "bench.json"))):
    name = os.path.basename(os.path.dirname(f))
    j = json.load(open(f))
    summary["agreement"][name] = j["agreement"]
    for b, e in j["backends"].items():
        r = {"bench": name, "solver": j["solver"], "bricks": j["bricks"], "unit": j["unit"], "backend": b,
             "threads": e["threads"], "seconds_per_unit": e["seconds_per_unit"],
             "throughput": e.get("trials_per_second", e.get("brick_steps_per_second")),
             "fraction_of_triad": e["fraction_of_triad"], "triad_gb_per_s": e["triad_gb_per_s"],
             "fraction_of_fma": e.get("fraction_of_fma"), "flops_per_unit": e.get("flops_per_unit"),
             "fma_gflop_per_s": e["fma_gflop_per_s"], "rng_gbit_per_s": e.get("rng_gbit_per_s"),
             "time_step": j.get("time_step"), "agreement": j["agreement"]}
        rows.append(r)
        summary["benches"].setdefault(name, {})[b] = r
if rows:
    with open(os.path.join(out, "bench_all.csv"), "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
# BIE over BE and UE: simulated seconds per wall second, same specimen, same backend
for name, by in summary["benches"].items():
    if not name.startswith("r500_bie_"):
        continue
    n = name.split("_")[-1]
    for b, bie in by.items():
        rate = lambda r: r["time_step"] / r["seconds_per_unit"] if r and r["time_step"] else None
        s = {}
        for m in ("be", "ue"):
            other = summary["benches"].get(f"r500_{m}_{n}", {}).get(b)
            if other and rate(other) and rate(bie):
                s[f"over_{m}"] = rate(bie) / rate(other)
        summary["bie_speedup_ratio500"][f"{n} bricks, {b}"] = s
json.dump(summary, open(os.path.join(out, "summary.json"), "w"), indent=1)
for r in rows:
    tri, fma = r["fraction_of_triad"], r["fraction_of_fma"]
    print(f'{r["bench"]:<22} {r["backend"]:<7} {r["bricks"]:>9} {r["seconds_per_unit"]:>11.4g} s/{r["unit"]:<9} '
          f'{r["throughput"]:>10.4g}/s  triad {100 * tri if tri is not None else float("nan"):5.1f}%  '
          f'FMA {100 * fma if fma is not None else float("nan"):5.1f}%  {r["agreement"]}'
          + (f'  rng {r["rng_gbit_per_s"]:.3g} Gbit/s' if r["rng_gbit_per_s"] else ""))
for k, v in summary["bie_speedup_ratio500"].items():
    print("BIE speed-up at ratio 500,", k, {m: round(x, 2) for m, x in v.items()})
bad = [k for k, v in summary["agreement"].items() if v == "differs"]
print("agreement:", "as nacre promises everywhere (bit-identical on the host, the device within the "
      "tolerance or, for Monte Carlo cycles, not judged)" if not bad else "DIFFERS in " + ", ".join(bad))
PY
say "done: $out (bench_all.csv, summary.json, one folder per bench)"
if [ ${#failed[@]} -gt 0 ]; then say "FAILED: ${failed[*]} (their bench.log says why)"; exit 1; fi
