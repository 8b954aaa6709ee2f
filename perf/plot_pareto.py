#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Speed against accuracy: errors of each run of perf/run_pareto.sh against the
converged reference, against its CPU time; the Pareto front drawn, the default deck's settings
marked. Writes OUTDIR/pareto.csv, pareto.md and pareto.png.

Errors (each relative, against the run named "reference"):
  rms_force   RMS over the reference's displacements of F_run(D) - F_ref(D), over the peak force
  rms_energy  the same for the energy, over the reference's final energy
  peak_force  |max F_run - max F_ref| / max F_ref
  first_rupture |D_run - D_ref| / D_ref of the first step with a ruptured interface
Curves are piecewise linear between converged steps, starting at (0, 0).
"""
import csv
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "python"))
from nacre import read_json, read_rows  # noqa: E402  (the reader of nacre's outputs, python/nacre)

out = sys.argv[1]
names = sorted(d for d in os.listdir(out) if os.path.isfile(os.path.join(out, d, "time.txt"))
               and len(open(os.path.join(out, d, "time.txt")).read().split()) >= 3)


def load(name):
    d = os.path.join(out, name)
    rows = read_rows(os.path.join(d, "steps.csv"))  # [] where the run wrote none
    D = [0.0] + [float(r["displacement"]) for r in rows]
    E = [0.0] + [float(r["energy"]) for r in rows]
    F = [0.0] + [float(r["reaction"]) for r in rows]
    rup = [0] + [int(r["ruptured"]) for r in rows]
    res = [float(r["residual"]) for r in rows]
    user, sysc, wall = (float(x) for x in open(os.path.join(d, "time.txt")).read().split()[-3:])
    summary = read_json(os.path.join(d, "summary.json"))
    exit_code = int(open(os.path.join(d, "exit_code")).read()) if os.path.exists(os.path.join(d, "exit_code")) else 0
    return dict(name=name, D=D, E=E, F=F, rup=rup, max_residual=max(res) if res else float("nan"),
                cpu=user + sysc, wall=wall, steps=len(rows), exit=exit_code,
                cycles=summary.get("cycles", 0), polish=summary.get("polish_iterations", 0))


def interp(x, xs, ys):
    if x <= xs[0]:
        return ys[0]
    for i in range(1, len(xs)):
        if x <= xs[i]:
            t = (x - xs[i - 1]) / (xs[i] - xs[i - 1]) if xs[i] > xs[i - 1] else 1.0
            return ys[i - 1] + t * (ys[i] - ys[i - 1])
    return ys[-1]


def first_rupture(r):
    return next((d for d, n in zip(r["D"], r["rup"]) if n > 0), float("nan"))


runs = {n: load(n) for n in names}
if "reference" not in runs:
    sys.exit("plot_pareto: no reference run in " + out)
ref = runs["reference"]
Fpk, Efin = max(ref["F"]), ref["E"][-1]


def errors(r):
    dmax = min(r["D"][-1], ref["D"][-1])
    pts = [d for d in ref["D"][1:] if d <= dmax * (1 + 1e-12)]
    if not pts or r["D"][-1] < ref["D"][-1] * (1 - 1e-9):
        return None  # did not reach the final displacement
    ef = math.sqrt(sum((interp(d, r["D"], r["F"]) - interp(d, ref["D"], ref["F"])) ** 2 for d in pts) / len(pts)) / Fpk
    ee = math.sqrt(sum((interp(d, r["D"], r["E"]) - interp(d, ref["D"], ref["E"])) ** 2 for d in pts) / len(pts)) / Efin
    ep = abs(max(r["F"]) - Fpk) / Fpk
    fr, frr = first_rupture(r), first_rupture(ref)
    er = abs(fr - frr) / frr if not (math.isnan(fr) or math.isnan(frr)) else float("nan")
    return dict(rms_force=ef, rms_energy=ee, peak_force_err=ep, first_rupture=er)


table = []
for n, r in runs.items():
    e = errors(r)
    table.append(dict(name=n, cpu_seconds=r["cpu"], wall_seconds=r["wall"], steps=r["steps"], exit=r["exit"],
                      cycles=r["cycles"], polish_iterations=r["polish"], max_step_residual=r["max_residual"],
                      peak_force=max(r["F"]), final_ruptured=r["rup"][-1], **(e or {})))

keys = ["name", "cpu_seconds", "wall_seconds", "steps", "exit", "cycles", "polish_iterations", "max_step_residual",
        "peak_force", "final_ruptured", "rms_force", "rms_energy", "peak_force_err", "first_rupture"]
with open(os.path.join(out, "pareto.csv"), "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(keys)
    for t in sorted(table, key=lambda t: t["cpu_seconds"]):
        w.writerow([t.get(k, "") for k in keys])


def fmt(v, p=3):
    if v is None or v == "" or (isinstance(v, float) and math.isnan(v)):
        return "-"
    return f"{v:.{p}g}" if isinstance(v, float) else str(v)


with open(os.path.join(out, "pareto.md"), "w") as f:
    f.write(f"Reference: {ref['steps']} steps, peak force {Fpk:.6g}, final energy {Efin:.6g}, "
            f"largest step residual {ref['max_residual']:.2g}, first rupture at D = {first_rupture(ref):.4g}\n\n")
    f.write("| run | CPU s | steps | exit | MC cycles | polish it. | max residual | peak F | ruptured | "
            "RMS F err | RMS E err | peak F err | first rupture err |\n|" + "---|" * 13 + "\n")
    for t in sorted(table, key=lambda t: t["cpu_seconds"]):
        f.write(f"| {t['name']} | {t['cpu_seconds']:.0f} | {t['steps']} | {t['exit']} | {t['cycles']} | "
                f"{t['polish_iterations']} | {fmt(t['max_step_residual'], 2)} | {t['peak_force']:.5g} | "
                f"{t['final_ruptured']} | {fmt(t.get('rms_force'))} | {fmt(t.get('rms_energy'))} | "
                f"{fmt(t.get('peak_force_err'))} | {fmt(t.get('first_rupture'))} |\n")

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    sys.exit(0)

floor = 1e-7  # an error of exactly 0 is drawn here (log axes)
metrics = [("rms_force", "RMS force error / peak force"), ("rms_energy", "RMS energy error / final energy"),
           ("peak_force_err", "peak force error (relative)"), ("first_rupture", "first-rupture displacement error")]
fig, axes = plt.subplots(2, 2, figsize=(12, 9))
for ax, (key, label) in zip(axes.flat, metrics):
    pts = [(t["cpu_seconds"], max(t[key], floor), t["name"]) for t in table
           if t["name"] != "reference" and t.get(key) is not None and not math.isnan(t[key])]
    for x, y, n in pts:
        style = dict(marker="*", s=220, color="C3", zorder=5) if n == "default" else \
            dict(marker="s", s=60, color="C2", zorder=4) if n.startswith("gradient") else \
            dict(marker="o", s=40, color="C0", zorder=3)
        ax.scatter([x], [y], **style)
        ax.annotate(n, (x, y), textcoords="offset points", xytext=(5, 4), fontsize=7)
    front, best = [], float("inf")
    for x, y, n in sorted(pts):
        if y < best:
            front.append((x, y))
            best = y
    if front:  # drawn to the right edge so a one-point front shows too
        xs = [p[0] for p in front] + [max(p[0] for p in pts) * 1.1]
        ys = [p[1] for p in front] + [front[-1][1]]
        ax.step(xs, ys, where="post", color="C1", lw=1.2, label="Pareto front")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("CPU time to the final displacement (s, 1 thread)")
    ax.set_ylabel(label)
    ax.grid(True, which="both", alpha=0.3)
axes.flat[0].legend(loc="lower right", fontsize=8)
fig.suptitle(f"Speed against accuracy, {ref['steps']}-step reference (residual {ref['max_residual']:.0e}); "
             f"star: default deck settings, square: gradient only (FIRE)", fontsize=10)
fig.tight_layout()
fig.savefig(os.path.join(out, "pareto.png"), dpi=120)

# the curves themselves, every run on one axes
fig, (a1, a2) = plt.subplots(1, 2, figsize=(12, 4.5))
for n, r in sorted(runs.items()):
    lw, z = (2.5, 5) if n == "reference" else (1, 3)
    a1.plot(r["D"], r["F"], lw=lw, zorder=z, label=n)
    a2.plot(r["D"], r["E"], lw=lw, zorder=z, label=n)
a1.set_xlabel("D")
a1.set_ylabel("reaction force")
a2.set_xlabel("D")
a2.set_ylabel("energy")
a1.legend(fontsize=7)
fig.tight_layout()
fig.savefig(os.path.join(out, "curves.png"), dpi=110)
