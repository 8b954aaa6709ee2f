#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# The README's BIE deck (inputs/dynamic_bie.toml) does what the README says ("done
# when"): its step is at least 10x BE's critical step on the same deck (found by the app's own
# `--critical-step` with `method = "be"`), the BIE run finishes (exit 0, no blow-up), and the crack
# runs from the notch tip: at the last dump at least 20 interfaces are ruptured, every ruptured
# interface lies on the notch's bed joint (within two brick heights), the one nearest the notch
# tip within a brick width of it, and the ruptured joints form one run along x with no gap wider
# than two brick widths.
#   run_bie_deck_check.sh NACRE_EXE SOURCE_DIR WORK_DIR
set -euo pipefail
exe="$1"; src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"; cd "$work"
deck="$src/inputs/dynamic_bie.toml"
key() { sed -n "s/^$1 = \([^ ]*\).*/\1/p" "$deck" | head -n1; }
dt=$(key dt)

# BE's critical step on this deck: same specimen, load and damping, method = "be"
sed -e 's/^method = .*/method = "be"/' -e '/^bie_solve = /d' "$deck" > be.toml
"$exe" be.toml --critical-step > be_critical.txt
h_be=$(sed -n 's/^critical step: \([^ ]*\) s.*/\1/p' be_critical.txt)
[ -n "$h_be" ] || { cat be_critical.txt; echo "FAIL: no critical step printed"; exit 1; }
python3 -c "
dt, h = $dt, $h_be
print(f'BIE deck dt = {dt:g} s = {dt / h:.2f} x BE critical step {h:.4g} s')
assert dt >= 10 * h, 'the deck step is below 10x BE critical step'"

# the BIE run itself
"$exe" "$deck" -o bie -q
python3 - bie "$(key brick_width)" "$(key brick_height)" "$(key notch_length)" "$(key height)" <<'PY'
import glob, json, sys
import h5py, numpy as np
out, bw, bh, notch, height = sys.argv[1], *map(float, sys.argv[2:])
s = json.load(open(f"{out}/summary.json"))
assert s["status"] == "done" and s["method"] == "bie", s
# bie_scheme = "auto" (the default) with the deck's Rayleigh damping takes the split step
assert s["bie_scheme"] == "split", s
dump = sorted(glob.glob(f"{out}/dump_*.h5"))[-1]
with h5py.File(dump, "r") as d:
    pts = d["/interfaces/points"][:].reshape(-1, 2, 2)
    state = d["/interfaces/state"][:]
mid = pts.mean(axis=1)[state == 2]
n = len(mid)
assert n >= 20, f"only {n} interfaces ruptured"
y0 = height / 2
off = np.abs(mid[:, 1] - y0).max()
assert off <= 2 * bh, f"a ruptured interface lies {off:.4g} mm off the notch's joint (> {2 * bh:g})"
xs = np.sort(mid[:, 0])
assert abs(xs[0] - notch) <= bw, f"the crack starts at x = {xs[0]:.4g} mm, not at the notch tip {notch:g}"
gap = np.diff(xs).max() if n > 1 else 0.0
assert gap <= 2 * bw, f"the ruptured joints have a gap of {gap:.4g} mm (> {2 * bw:g})"
# the run's own crack reading (summary.json "crack", docs/fracture.md) sees the same crack: most of
# the ruptured joints connected to the notch, the tip at the far end of the run of joints
c = s["crack"]
assert c["interfaces"] >= 0.8 * n, f"the crack reading connects {c['interfaces']} of {n} ruptured joints"
assert abs(c["tip_x"] - xs[-1]) <= bw, f"crack tip x = {c['tip_x']:.4g}, the last ruptured joint at {xs[-1]:.4g}"
assert abs(c["extension"] - (c["tip_x"] - c["notch_tip_x"])) <= 1e-9 and c["extension"] > 0.5, c
assert 1 - 1e-9 <= c["deflection"] < 1.5, f"deflection {c['deflection']} of a crack along one bed joint"
print(f"crack reading: {c['interfaces']} joints, tip x = {c['tip_x']:.3f} mm, extension {c['extension']:.3f} mm, "
      f"deflection {c['deflection']:.3f}")
print(f"crack from the notch tip: {n} ruptured, x = {xs[0]:.3f} .. {xs[-1]:.3f} mm, "
      f"within {off:.3g} mm of the notch line, largest gap {gap:.3g} mm; {s['steps']} steps")
PY
