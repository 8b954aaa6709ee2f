# SPDX-License-Identifier: BSD-3-Clause
"""The overlay charts of a `nacre sweep` (docs/fracture.md "Sweeps"): sweep.png.

Reads SWEEP_DIR/sweep.json (the runs, their swept values and exit codes), the program's
SWEEP_DIR/sweep.csv (one row per run: peak force, quadratic coefficient c, critical displacement
D_c, toughening ratio, crack deflection, ...) and each run's steps.csv / series.csv for its
curve; draws energy against applied displacement per run with its initial quadratic c D^2 and
D_c (the dissertation's Fig. 2.8b; dynamic runs: the reaction), and the peak force, toughening
ratio and crack deflection against the first swept key (one line per combination of the
others). Without sweep.csv: a one-line warning and no chart.

    python3 -m nacre.charts.sweep SWEEP_DIR [--quiet]
"""
import math
import os
import sys

import numpy as np

from ..results import Sweep
from ._common import command_line, pyplot, save_png, warn


def number(v):
    try:
        return float(v)
    except ValueError:
        return v


def num(v):
    """A cell as a float (NaN where it is empty or text)."""
    try:
        return float(v)
    except (TypeError, ValueError):
        return math.nan


def table_rows(t):
    """sweep.csv's typed table as one dict per row."""
    n = len(next(iter(t.values()))) if t else 0
    return [{k: v[i] for k, v in t.items()} for i in range(n)]


def curve_of(entry, row):
    """The run's curve for the first panel: D and E (Monte Carlo, with sweep.csv's c and D_c) or
    D and F (dynamics); None without outputs."""
    if not entry.has_outputs():
        return None
    t = entry.run().table()
    if not t or not len(t.get("displacement", ())):
        return None
    c = dict(D=t["displacement"], F=t["reaction"])
    if "energy" in t:
        c.update(E=t["energy"], c=num(row.get("quadratic_coefficient")), Dc=num(row.get("critical_displacement")))
    return c


def main(argv=None):
    parsed = command_line(argv, __doc__)
    if parsed is None:
        return 0
    args, flags = parsed
    out = args[0]
    sw = Sweep(out)
    t = sw.table()
    if t is None:
        warn(f"{os.path.join(out, 'sweep.csv')} not found (nacre sweep writes it); sweep.png skipped")
        return 0
    by_name = {str(r["name"]): r for r in table_rows(t)}
    keys = sw.keys
    rows, curves = [], []
    for e in sw.runs:
        r = dict(by_name.get(e.name, {}))
        r.update(name=e.name, **e.values)  # the swept values as given to --set
        rows.append(r)
        curves.append(curve_of(e, r))

    plt = pyplot()
    fig, ax = plt.subplots(2, 2, figsize=(12, 8.5))
    a = ax[0][0]
    top = 0.0  # the runs' own range: the quadratics grow past it
    for r, c in zip(rows, curves):
        if c is None:
            continue
        if "E" in c:
            (line,) = a.plot(c["D"], c["E"], "o-", ms=2.5, label=r["name"])
            top = max(top, float(np.max(c["E"])))
            if math.isfinite(c["c"]):
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
    if a.get_legend_handles_labels()[0]:
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
            pts = sorted((number(r[x_key]), num(r.get(key))) for r in rs)
            xs = [p[0] for p in pts]
            numeric = all(isinstance(x, float) for x in xs)
            panel.plot(xs if numeric else range(len(xs)), [p[1] for p in pts], "o-",
                       label=", ".join(f"{k}={v}" for k, v in zip(keys[1:], g)) or None)
            if not numeric:
                panel.set_xticks(range(len(xs)), xs)
        if not any(math.isfinite(num(r.get(key))) for r in rows):
            panel.text(0.5, 0.5, "no crack left the notch in any run" if key != "peak_reaction" else "no data",
                       transform=panel.transAxes, ha="center", va="center", color="gray")
        panel.set_xlabel(x_key)
        panel.set_ylabel(label)
        panel.grid(True, alpha=0.3)
        if len(groups) > 1:
            panel.legend(fontsize=7)
    fig.suptitle(f"nacre sweep of {os.path.basename(sw.deck or '')} over {', '.join(keys)}")
    fig.tight_layout()
    save_png(fig, os.path.join(out, "sweep.png"), dpi=110)
    plt.close(fig)
    if "--quiet" not in flags:
        for r in rows:
            print(f"  {r['name']}: peak {num(r.get('peak_reaction')):.4g}, crack extension "
                  f"{num(r.get('crack_extension')):.4g}, deflection {num(r.get('crack_deflection')):.3f}, "
                  f"toughening {num(r.get('toughening_ratio')):.3g}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
