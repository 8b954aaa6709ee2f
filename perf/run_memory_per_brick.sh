#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Peak resident memory of a whole nacre run for two specimen sizes; the slope is the memory per
# brick behind [limits] max_memory_gib (deck/limits.hpp: bytes_per_brick, docs/guarantees.md).
#   devenv/nacre-env run perf/run_memory_per_brick.sh [NACRE_EXE] [WORK_DIR]
set -euo pipefail
exe="$(realpath "${1:-build/openmp/src/nacre}")"; work="${2:-build/memory_per_brick}"
mkdir -p "$work"; cd "$work"
for w in 140 700; do
  cat > "mem_$w.toml" <<T
[geometry]
width = $w.0
height = 1000.0
brick_width = 3.5
brick_height = 1.0
notch_length = 20.0
[mortar]
k = 100.0
x1 = 0.002
x2 = 0.004
[load]
bending = 1.0
final_displacement = 0.004
InitialLoadStepSize = 0.004
[solver]
max_cycles = 3
WindowSize = 3
ConvergenceRep = 1
[output]
directory = "mem_$w"
charts = false
T
  python3 - "$exe" "$w" <<'PY'
import json, resource, subprocess, sys
exe, w = sys.argv[1], sys.argv[2]
subprocess.run([exe, f"mem_{w}.toml", "-q"], check=True)
rss = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss * 1024
b = json.load(open(f"mem_{w}/summary.json"))["bricks"]
print(f"width {w}: {b} bricks, peak RSS {rss / 2**20:.1f} MiB, {rss / b:.0f} B/brick")
PY
done
