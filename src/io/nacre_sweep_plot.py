#!/usr/bin/env python3
"""The combined table and overlay charts of a `nacre sweep` (docs/fracture.md "Sweeps").

Reads SWEEP_DIR/sweep.json (the runs, their swept values and exit codes) and each run's
summary.json, steps.csv / series.csv and crack columns; writes SWEEP_DIR/sweep.csv (one row per
run) and sweep.png: energy against applied displacement per run with its initial quadratic fit
and critical displacement (the dissertation's Fig. 2.8b; dynamic runs: the reaction), and the
peak force, toughening ratio and crack deflection against the first swept key (one line per
combination of the others).

The critical displacement D_c: the first load step whose energy falls 5 % below the quadratic
E = c D^2 fitted through the first fifth of the steps (where the response leaves linear
elasticity: the first joints soften or break).

  nacre_sweep_plot.py SWEEP_DIR [--quiet]
"""
import csv
import json
import math
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from nacre_plot import quadratic_fit, r_curve_points, save_png, toughening_ratio  # noqa: E402
from nacre_results import Run  # noqa: E402


def number(v):
    try:
        return float(v)
    except ValueError:
        return v


def read_run(run):
    d = run["directory"]
    r = dict(name=run["name"], exit=run["exit"], **{k: v for k, v in run["values"].items()})
    if not os.path.exists(os.path.join(d, "summary.json")):
        return r, None
    run = Run(d)
    s, rows = run.summary, run.rows()
    c = s.get("crack", {})
    r.update(solver=s.get("solver"), status=s.get("status", "done"), bricks=s.get("bricks"))
    if rows:
        D = np.array([float(x["displacement"]) for x in rows])
        F = np.array([float(x["reaction"]) for x in rows])
        k = int(np.argmax(F))
        r.update(peak_reaction=F[k], displacement_at_peak=D[k], ruptured=int(rows[-1]["ruptured"]))
        curve = dict(D=D, F=F)
        if "energy" in rows[0]:  # Monte Carlo: the total energy and Fig. 2.8b's critical displacement
            E = np.array([float(x["energy"]) for x in rows])
            cfit = quadratic_fit(D, E)
            below = np.nonzero(E < 0.95 * cfit * D ** 2)[0]
            r.update(final_energy=E[-1], quadratic_coefficient=cfit,
                     critical_displacement=D[below[0]] if len(below) else math.nan)
            curve.update(E=E, c=cfit, Dc=r["critical_displacement"])
        if "bed_work_of_fracture" in c:
            pts = r_curve_points(rows, c["thickness"], c["bed_work_of_fracture"])
            r["toughening_ratio"] = toughening_ratio(pts, c["thickness"], c["bed_work_of_fracture"])
    else:
        curve = None
    for k in ("extension", "path_length", "deflection", "interfaces", "bed", "head", "fracture_energy"):
        if k in c:
            r["crack_" + k if not k.startswith("fracture") else k] = c[k]
    return r, curve


def main(argv):
    args = [a for a in argv if not a.startswith("--")]
    if len(args) != 1:
        sys.exit(__doc__)
    out = args[0]
    sw = json.load(open(os.path.join(out, "sweep.json")))
    keys = sw["keys"]
    rows, curves = [], []
    for run in sw["runs"]:
        r, c = read_run(run)
        rows.append(r)
        curves.append(c)
    fields = list(dict.fromkeys(k for r in rows for k in r))
    tmp = os.path.join(out, ".sweep.csv.tmp%d" % os.getpid())
    with open(tmp, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields)
        w.writeheader()
        for r in rows:
            w.writerow({k: (repr(float(v)) if isinstance(v, (float, np.floating)) else v) for k, v in r.items()})
    os.replace(tmp, os.path.join(out, "sweep.csv"))

    fig, ax = plt.subplots(2, 2, figsize=(12, 8.5))
    a = ax[0][0]
    top = 0.0  # the runs' own range: the quadratics grow past it
    for r, c in zip(rows, curves):
        if c is None:
            continue
        if "E" in c:
            (line,) = a.plot(c["D"], c["E"], "o-", ms=2.5, label=r["name"])
            top = max(top, float(np.max(c["E"])))
            a.plot(c["D"], c["c"] * c["D"] ** 2, "--", lw=0.8, color=line.get_color())
            if math.isfinite(c["Dc"]):
                a.axvline(c["Dc"], color=line.get_color(), lw=0.6, ls=":")
            a.set_ylabel("total energy (dashed: initial quadratic fit; dotted: D_c)")
        else:
            a.plot(c["D"], c["F"], "-", label=r["name"])
            a.set_ylabel("reaction force")
    if top > 0:
        a.set_ylim(0, 1.3 * top)
    a.set_xlabel("applied displacement D")
    a.legend(fontsize=7)
    mc = any(c is not None and "E" in c for c in curves)
    a.set_title("energy against D per run (Fig. 2.8b)" if mc else "reaction against D per run")
    # against the first key, one line per combination of the others
    x_key = keys[0]
    groups = {}
    for r in rows:
        groups.setdefault(tuple(r[k] for k in keys[1:]), []).append(r)
    for panel, (key, label) in zip((ax[0][1], ax[1][0], ax[1][1]),
                                    (("peak_reaction", "peak reaction force"),
                                     ("toughening_ratio", "toughening ratio (G_R / k x1 x2)"),
                                     ("crack_deflection", "crack deflection (path / extension)"))):
        for g, rs in groups.items():
            pts = sorted((number(r[x_key]), r.get(key, math.nan)) for r in rs)
            xs = [p[0] for p in pts]
            numeric = all(isinstance(x, float) for x in xs)
            panel.plot(xs if numeric else range(len(xs)), [p[1] for p in pts], "o-",
                       label=", ".join(f"{k}={v}" for k, v in zip(keys[1:], g)) or None)
            if not numeric:
                panel.set_xticks(range(len(xs)), xs)
        if not any(math.isfinite(float(r.get(key, math.nan))) for r in rows):
            panel.text(0.5, 0.5, "no crack left the notch in any run" if key != "peak_reaction" else "no data",
                       transform=panel.transAxes, ha="center", va="center", color="gray")
        panel.set_xlabel(x_key)
        panel.set_ylabel(label)
        panel.grid(True, alpha=0.3)
        if len(groups) > 1:
            panel.legend(fontsize=7)
    fig.suptitle(f"nacre sweep of {os.path.basename(sw['deck'])} over {', '.join(keys)}")
    fig.tight_layout()
    save_png(fig, os.path.join(out, "sweep.png"), dpi=110)
    plt.close(fig)
    if "--quiet" not in argv:
        for r in rows:
            print(f"  {r['name']}: peak {r.get('peak_reaction', math.nan):.4g}, crack extension "
                  f"{r.get('crack_extension', math.nan):.4g}, deflection {r.get('crack_deflection', math.nan):.3f}, "
                  f"toughening {r.get('toughening_ratio', math.nan):.3g}")


if __name__ == "__main__":
    main(sys.argv[1:])
