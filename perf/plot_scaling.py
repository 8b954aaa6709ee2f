#!/usr/bin/env python3
"""Scaling of total time with the number of bricks (perf/run_scaling.sh): fits time = a N^p by
least squares in log-log, for the solve (CPU time minus initialisation) and for the
initialisation alone; writes OUTDIR/scaling.csv, scaling.md and scaling.png."""
import csv
import json
import math
import os
import re
import sys

out = sys.argv[1]
rows = []
for d in sorted(os.listdir(out)):
    p = os.path.join(out, d)
    if not (d.startswith("n") and os.path.exists(os.path.join(p, "time.txt")) and os.path.exists(os.path.join(p, "summary.json"))):
        continue
    user, sysc, wall = (float(x) for x in open(os.path.join(p, "time.txt")).read().split()[-3:])
    s = json.load(open(os.path.join(p, "summary.json")))
    m = re.search(r"bricks, \d+ interfaces \(([0-9.eE+-]+) s\)", open(os.path.join(p, "log.txt")).read())
    init = float(m.group(1)) if m else float("nan")
    steps = list(csv.DictReader(open(os.path.join(p, "steps.csv"))))
    rows.append(dict(bricks=s["bricks"], free=s["free_bricks"], steps=s["steps"], cycles=s["cycles"],
                     polish_iterations=s["polish_iterations"], cpu=user + sysc, wall=wall, init=init,
                     solve=user + sysc - init, max_residual=max(float(r["residual"]) for r in steps)))
rows.sort(key=lambda r: r["bricks"])


def fit(xs, ys):
    lx, ly = [math.log(x) for x in xs], [math.log(y) for y in ys]
    n = len(lx)
    mx, my = sum(lx) / n, sum(ly) / n
    sxx = sum((a - mx) ** 2 for a in lx)
    p = sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / sxx
    return p, math.exp(my - p * mx)


with open(os.path.join(out, "scaling.csv"), "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=list(rows[0].keys()) if rows else ["bricks"])
    w.writeheader()
    w.writerows(rows)
if len(rows) < 2:
    sys.exit("plot_scaling: need at least two sizes")
N = [r["bricks"] for r in rows]
p_solve, a_solve = fit(N, [r["solve"] for r in rows])
p_init, a_init = fit(N, [max(r["init"], 1e-6) for r in rows])
p_cyc, a_cyc = fit(N, [r["cycles"] for r in rows])
with open(os.path.join(out, "scaling.md"), "w") as f:
    f.write("| bricks | steps | MC cycles | polish it. | max residual | init s | solve CPU s | total CPU s |\n"
            "|---|---|---|---|---|---|---|---|\n")
    for r in rows:
        f.write(f"| {r['bricks']} | {r['steps']} | {r['cycles']} | {r['polish_iterations']} | {r['max_residual']:.1e} | "
                f"{r['init']:.3f} | {r['solve']:.1f} | {r['cpu']:.1f} |\n")
    f.write(f"\nFitted (least squares, log-log, {len(rows)} sizes): solve time ~ N^{p_solve:.2f}, "
            f"cycles ~ N^{p_cyc:.2f}, initialisation ~ N^{p_init:.2f}\n")
print(open(os.path.join(out, "scaling.md")).read())

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    sys.exit(0)
fig, ax = plt.subplots(figsize=(7, 5))
ax.loglog(N, [r["solve"] for r in rows], "o", color="C0", label="solve (CPU s, 1 thread)")
ax.loglog(N, [r["init"] for r in rows], "s", color="C2", label="initialisation (s)")
xs = [N[0], N[-1]]
ax.loglog(xs, [a_solve * x ** p_solve for x in xs], "-", color="C0", label=f"fit N^{p_solve:.2f}")
ax.loglog(xs, [a_init * x ** p_init for x in xs], "-", color="C2", label=f"fit N^{p_init:.2f}")
ax.loglog(xs, [rows[0]["solve"] * (x / N[0]) ** 1.5 for x in xs], ":", color="gray", label="N^1.5 (dissertation)")
ax.set_xlabel("bricks")
ax.set_ylabel("seconds")
ax.grid(True, which="both", alpha=0.3)
ax.legend(fontsize=8)
ax.set_title("Time to the same final displacement against specimen size", fontsize=10)
fig.tight_layout()
fig.savefig(os.path.join(out, "scaling.png"), dpi=120)
