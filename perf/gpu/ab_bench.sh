#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# ab_bench.sh — two carried nacre builds on the same decks in one sitting (the machine's noise
# and clocks shared): `nacre bench` of each deck with binary A, then with B (`--compare` against
# A's state: the agreement of the two builds), so a kernel change is measured as a ratio in one
# run (docs/gpu.md). BUNDLE from carry_prebuilt.sh holding both binaries (e.g. nacre_prev, nacre).
#
#   perf/gpu/ab_bench.sh BUNDLE OUTDIR A B "NAME DECK BENCH-ARGS" ...
#     e.g. perf/gpu/ab_bench.sh .gpu out nacre_prev nacre "be1m path/to/deck.toml --steps 100"
# OUTDIR gets NAME_A.bench.{csv,json,log} and NAME_B.bench.* (flat: a device call brings back no
# deep folders; the states, hundreds of MB at 1M bricks, stay in a scratch folder, AB_SCRATCH,
# default /tmp/ab_bench); OUTDIR/ab.csv one row per
# deck: the two times per unit, B's speed-up over A and the agreement. BENCH_TIMEOUT s per bench
# (default 120).
set -uo pipefail
[ $# -ge 5 ] || { sed -n '2,11p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
B="$(realpath "$1")"; O="$(realpath -m "$2")"; a="$3"; b="$4"; shift 4
S="${AB_SCRATCH:-/tmp/ab_bench}"
mkdir -p "$O" "$S"
echo "name,a,b,a_seconds_per_unit,b_seconds_per_unit,speedup_b_over_a,b_against_a" > "$O/ab.csv"
field() {  # bench.json of $1: the reference backend's seconds per unit, or the --compare verdict
  python3 - "$1" "$2" <<'PY' 2>/dev/null || echo nan
import json, sys
d = json.load(open(sys.argv[1]))
if sys.argv[2] == "t":
    print(d["backends"][d["reference_backend"]]["seconds_per_unit"])
else:
    c = d.get("compared_to")
    print(json.dumps(c.get("backends", c)).replace(",", ";")[:300] if c else "none")
PY
}
for spec in "$@"; do
  read -r name deck args <<< "$spec"
  for bin in "$a" "$b"; do
    w="$S/$name/$bin"; mkdir -p "$w"
    cmp=(); [ "$bin" = "$b" ] && cmp=(--compare "$S/$name/$a" --tolerance "${AB_TOLERANCE:-1e-6}")
    echo "[ab_bench] $name: $bin bench $deck $args ${cmp[*]}"
    # shellcheck disable=SC2086
    timeout "${BENCH_TIMEOUT:-120}" "$B/run" "$bin" bench "$deck" --repeat 2 -o "$w" $args "${cmp[@]}" \
      > "$w/bench.log" 2>&1 || echo "[ab_bench]   exit $?"
    grep -v "OMP_PROC_BIND\|For best performance\|For unit testing\|In general" "$w/bench.log" | tail -n 4
    for f in csv json log; do cp "$w/bench.$f" "$O/${name}_$bin.bench.$f" 2>/dev/null; done
  done
  ta=$(field "$O/${name}_$a.bench.json" t); tb=$(field "$O/${name}_$b.bench.json" t)
  sp=$(python3 -c "import sys; a,b=float(sys.argv[1]),float(sys.argv[2]); print(round(a/b,3) if b>0 else 'nan')" "$ta" "$tb" 2>/dev/null || echo nan)
  echo "$name,$a,$b,$ta,$tb,$sp,$(field "$O/${name}_$b.bench.json" c)" >> "$O/ab.csv"
done
cat "$O/ab.csv"
