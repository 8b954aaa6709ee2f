#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Throughput of several nacre_perf_mc builds (one per change), interleaved in one sitting
# (b1, b2, ..., b1, b2, ...) so that every build sees the same machine load; each row's ratio to
# the first build is taken per repetition ("a row per change, ratios in one run").
# Usage (inside the dev root, from the repository root):
#   devenv/nacre-env run env NACRE_MC_SIZES=10000,300000 perf/run_mc_rows.sh OUTDIR NAME=BIN [NAME=BIN ...]
# Writes OUTDIR/<NAME>.csv (nacre_perf_mc's columns) and OUTDIR/summary.md: per size, schedule
# and thread count the median wall-clock and per-CPU-second rates of each build and the median of
# its per-repetition ratio to the first build. REPS (default 3), NACRE_MC_CYCLES (default 20).
set -euo pipefail
out="$1"; shift
reps="${REPS:-3}"; sizes="${NACRE_MC_SIZES:-10000,300000}"; cycles="${NACRE_MC_CYCLES:-20}"
mkdir -p "$out"
names=()
for nb in "$@"; do names+=("${nb%%=*}"); rm -f "$out/${nb%%=*}.csv"; done
# passive: idle threads sleep at the colour barriers instead of spinning, so CPU-seconds count work
export OMP_PROC_BIND=spread OMP_PLACES=threads OMP_WAIT_POLICY=passive
for rep in $(seq "$reps"); do
  for nt in 1 2; do
    for nb in "$@"; do
      "${nb#*=}" --bricks "$sizes" --cycles "$cycles" --repeats 2 --colouring tiles,natural \
        --csv "$out/${nb%%=*}.csv" --kokkos-num-threads=$nt >/dev/null
    done
  done
done
python3 - "$out" "${names[@]}" <<'PY'
import csv, statistics, sys
out, names = sys.argv[1], sys.argv[2:]
rows = {n: list(csv.DictReader(open(f"{out}/{n}.csv"))) for n in names}
keys = []
for r in rows[names[0]]:
    k = (int(r["bricks"]), r["implementation"], int(r["threads"]))
    if k not in keys: keys.append(k)
def series(n, k, col):
    return [float(r[col]) for r in rows[n] if (int(r["bricks"]), r["implementation"], int(r["threads"])) == k]
lines = ["M brick trials per second (median of the repetitions): wall clock | per CPU-second; "
         "ratio = median over repetitions of (this build / first build), per CPU-second | wall.", ""]
for k in sorted(keys):
    lines.append(f"### {k[0]} bricks, {k[1]}, {k[2]} thread{'s' if k[2] > 1 else ''}")
    lines.append("")
    lines.append("| build | M trials/s (wall) | M trials per CPU-s | ratio per CPU-s | ratio wall | energy_after |")
    lines.append("|---|---|---|---|---|---|")
    base_c, base_w = series(names[0], k, "trials_per_cpu_second"), series(names[0], k, "trials_per_second")
    for n in names:
        c, w = series(n, k, "trials_per_cpu_second"), series(n, k, "trials_per_second")
        e = [r["energy_after"] for r in rows[n] if (int(r["bricks"]), r["implementation"], int(r["threads"])) == k]
        rc = statistics.median(x / y for x, y in zip(c, base_c))
        rw = statistics.median(x / y for x, y in zip(w, base_w))
        lines.append(f"| {n} | {statistics.median(w)/1e6:.2f} | {statistics.median(c)/1e6:.2f} | {rc:.2f} | {rw:.2f} | {e[0]} |")
    lines.append("")
open(f"{out}/summary.md", "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
PY
