#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# The R-curve against its known answer (docs/fracture.md): a straight crack along one bed joint
# between rigid bricks consumes the mortar's work of fracture k x1 x2 per unit length.
#  1. the run writes r_curve.csv (the program) and r_curve.png (its charts) and prints the
#     toughening ratio;
#  2. once the crack has crossed the ligament with no joint left softening, its energy of
#     fracture is k x1 x2 times its path length (exact: a ruptured joint holds k x1 x2 per length);
#  3. the mean G_R over the whole extension (the R-curve's area over the extension) is k x1 x2
#     within 5 % (what the process zone held before the crack left the notch);
#  4. r_curve.csv's toughening column is G_R / (k x1 x2), its points the rows where the extension grew;
#     r_curve.csv and summary.json's crack.toughening_ratio are the reference implementation's
#     (python/nacre/analysis.py) from the run's steps.csv;
#  5. a new run into the directory without charts leaves no chart of the old run behind, and its
#     own r_curve.csv (the program writes it with or without charts).
#   run_r_curve_check.sh NACRE_EXE SOURCE_DIR WORK_DIR
set -euo pipefail
exe="$1"; src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"; cd "$work"
"$exe" "$src/tests/app/r_curve.toml" > log.txt 2>&1 || { cat log.txt; echo "FAIL: the run failed"; exit 1; }
grep -q "toughening ratio" log.txt || { cat log.txt; echo "FAIL: no toughening ratio printed"; exit 1; }
[ -s r_curve/r_curve.png ] || { echo "FAIL: no r_curve.png"; exit 1; }
PYTHONPATH="$src/python" python3 - r_curve <<'PY'
import csv, json, math, sys
from nacre import analysis
out = sys.argv[1]
s = json.load(open(f"{out}/summary.json"))
c = s["crack"]
gc = c["bed_work_of_fracture"]
assert abs(gc - 100.0 * 0.002 * 0.004) < 1e-15, gc
rows = list(csv.DictReader(open(f"{out}/steps.csv")))
last = rows[-1]
assert int(last["process_zone"]) == 0 and float(last["crack_extension"]) > 0.7 * (42.0 - 10.5), last
w, path = float(last["fracture_energy"]), float(last["crack_path_length"])
assert abs(w - gc * path) <= 1e-9 * w, f"fracture energy {w} != k x1 x2 x path {gc * path}"
assert int(last["crack_head"]) == 0 and abs(float(last["crack_deflection"]) - 1) < 1e-9, last
pts = list(csv.DictReader(open(f"{out}/r_curve.csv")))
assert len(pts) >= 2, pts
ext = [float(p["extension"]) for p in pts]
assert ext == sorted(set(ext)), "R-curve extensions not increasing"
a0 = 0.0
area = 0.0
for p in pts:
    a, g = float(p["extension"]), float(p["G_R"])
    assert abs(float(p["toughening"]) - g / gc) <= 1e-12 * abs(g / gc) + 1e-15, p
    area += g * (a - a0)
    a0 = a
mean = area / ext[-1]
assert abs(mean / gc - 1) < 0.05, f"mean G_R {mean} vs k x1 x2 {gc}"
ref, ratio = analysis.run_r_curve(out)  # the reference implementation
assert len(ref) == len(pts), (len(ref), len(pts))
for p, q in zip(pts, ref):
    for k in ("extension", "fracture_energy", "G_R", "toughening"):
        assert abs(float(p[k]) - q[k]) <= 1e-12 * abs(q[k]), (k, p, q)
assert abs(c["toughening_ratio"] - ratio) <= 1e-12 * abs(ratio), (c["toughening_ratio"], ratio)
print(f"R-curve: {len(pts)} points, mean G_R / (k x1 x2) = {mean / gc:.4f}; final energy of fracture "
      f"{w:.6g} = k x1 x2 x path {gc * path:.6g}")
PY

# 5. the R-curve belongs to the run that wrote it: a new run without charts removes the old
#    charts and writes its own r_curve.csv (the old one marked stale first)
echo stale > r_curve/r_curve.csv
sed 's/^\[output\]/[output]\ncharts = false/' "$src/tests/app/r_curve.toml" > nocharts.toml
"$exe" nocharts.toml --overwrite -q
for f in r_curve.png crack.png energy_force.png; do
  [ ! -e "r_curve/$f" ] || { echo "FAIL: r_curve/$f of the previous run left behind"; exit 1; }
done
PYTHONPATH="$src/python" python3 - r_curve <<'PY' || { echo "FAIL: r_curve.csv is not the new run's"; exit 1; }
import sys
import nacre
from nacre import analysis
run = nacre.Run(sys.argv[1])
got, (ref, _) = run.r_curve(), analysis.run_r_curve(run)
assert got is not None and list(got) == ["extension", "fracture_energy", "G_R", "toughening"], got
assert list(got["extension"]) == [p["extension"] for p in ref], (got, ref)
PY
echo "a new run removes the previous run's charts and writes its own R-curve"
