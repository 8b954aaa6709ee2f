#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# The shipped default deck, as a user runs it, to just past its first rupture (D = 0.07: 35 load
# steps of 0.002, one with a Monte Carlo burst): exit 0, every step converged below the deck's
# residual tolerance (1e-6), Newton finished every step (relaxation = "auto"), and the peak force
# of the converged path (docs/speed_accuracy.md, "The default deck": 1.53338 at D = 0.054).
#   run_default_deck_check.sh NACRE_EXE SOURCE_DIR WORK_DIR
set -euo pipefail
exe="$1"; src="$2"; work="$3"
rm -rf "$work" && mkdir -p "$work" && cd "$work"
sed -e 's/^final_displacement = .*/final_displacement = 0.07/' -e 's/^DumpInter = .*/DumpInter = 0/' \
  "$src/inputs/default.toml" > default.toml
"$exe" default.toml -o out -q
python3 - <<'PY'
import csv, sys
rows = list(csv.DictReader(open("out/steps.csv")))
fail = []
if len(rows) != 35: fail.append(f"{len(rows)} steps, expected 35")
worst = max(float(r["residual"]) for r in rows)
if not worst < 1e-6: fail.append(f"largest step residual {worst}")
methods = {r["method"] for r in rows}
if not methods <= {"newton", "newton+monte-carlo"} or "newton" not in methods: fail.append(f"methods {methods}")
if not any(r["method"] == "newton+monte-carlo" for r in rows): fail.append("no Monte Carlo burst after the first rupture")
peak = max(float(r["reaction"]) for r in rows)
if abs(peak - 1.53338) > 2e-5: fail.append(f"peak force {peak}, expected 1.53338")
if int(rows[-1]["ruptured"]) < 1: fail.append("no rupture by D = 0.07")
if fail: sys.exit("FAIL: " + "; ".join(fail))
print(f"default deck to D = 0.07: {len(rows)} steps, largest residual {worst:.2g}, peak force {peak:.6g}, "
      f"methods {sorted(methods)}")
PY
