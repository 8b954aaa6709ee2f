# SPDX-License-Identifier: BSD-3-Clause
"""The reference implementation of the data products nacre writes itself (the C++ is tested
against these): the R-curve and its toughening ratio (r_curve.csv, summary.json
crack.toughening_ratio; docs/fracture.md), and the rows of a sweep's sweep.csv with the initial
quadratic fit E = c D^2 and the critical displacement D_c (the dissertation's Fig. 2.8b).

Nothing here writes a file: the charts (nacre.charts) read what the program wrote.
"""
import math
import os

import numpy as np

from .results import Run, Sweep


def quadratic_fit(D, E):
    """c of E = c D^2 fitted (least squares) through the first fifth of the points (at least 2):
    where the response leaves linear elasticity (energy_force.png, the sweep's Fig. 2.8b)."""
    D, E = np.asarray(D, dtype=float), np.asarray(E, dtype=float)
    n0 = max(2, len(D) // 5)
    return float(np.dot(D[:n0] ** 2, E[:n0]) / max(np.dot(D[:n0] ** 2, D[:n0] ** 2), 1e-300))


def critical_displacement(D, E, c):
    """D_c: the first load step whose energy falls 5 % below the quadratic c D^2 (NaN if none)."""
    D, E = np.asarray(D, dtype=float), np.asarray(E, dtype=float)
    below = np.nonzero(E < 0.95 * c * D ** 2)[0]
    return float(D[below[0]]) if len(below) else math.nan


def r_curve_points(rows, thickness, gc):
    """The R-curve of a run's table (steps.csv or series.csv rows with crack_extension and
    fracture_energy; docs/fracture.md): one point each time the crack extension reaches a new
    largest value, G_R = the energy of fracture gained since the previous point over the extension
    gained, per unit thickness (the first point measured from the last row before the crack left
    the notch). Returns dicts of extension, fracture_energy, G_R and G_R / gc."""
    pts, amax, base = [], 0.0, None
    for r in rows:
        a, w = float(r["crack_extension"]), float(r["fracture_energy"])
        if a <= amax + 1e-12:
            if not pts:
                base = (0.0, w)  # before the crack leaves the notch: the last such row
            continue
        a0, w0 = (pts[-1]["extension"], pts[-1]["fracture_energy"]) if pts else (base or (0.0, 0.0))
        g = (w - w0) / (a - a0) / thickness
        pts.append(dict(extension=a, fracture_energy=w, G_R=g, toughening=g / gc))
        amax = a
    return pts


def toughening_ratio(pts, thickness, gc):
    """The mean G_R over the second half of the final extension, over gc (NaN with < 2 points)."""
    if len(pts) < 2:
        return float("nan")
    half = next(p for p in pts if p["extension"] >= 0.5 * pts[-1]["extension"])
    if half is pts[-1]:
        half = pts[-2]
    da = pts[-1]["extension"] - half["extension"]
    return (pts[-1]["fracture_energy"] - half["fracture_energy"]) / da / thickness / gc


def run_r_curve(run):
    """(points, toughening ratio) of a Run from its table and its summary's crack reading
    (thickness, bed_work_of_fracture); None for a run without them."""
    run = run if isinstance(run, Run) else Run(run)
    crack, rows = run.crack, run.rows()
    if not rows or "fracture_energy" not in rows[0] or "bed_work_of_fracture" not in crack:
        return None
    t, gc = crack["thickness"], crack["bed_work_of_fracture"]
    pts = r_curve_points(rows, t, gc)
    return pts, toughening_ratio(pts, t, gc)


def sweep_row(entry):
    """One row of sweep.csv for a sweep.json run entry (a dict with name, exit, values, directory;
    or a nacre.SweepEntry), and the run's curve (D, F; Monte Carlo also E, c, Dc; None without
    rows): (row dict, curve). Columns: name, exit, the swept keys, solver, status, bricks,
    peak_reaction, displacement_at_peak, ruptured, final_energy, quadratic_coefficient,
    critical_displacement (Monte Carlo), toughening_ratio (a run with a crack reading),
    crack_extension, crack_path_length, crack_deflection, crack_interfaces, crack_bed, crack_head,
    fracture_energy (those in summary.json's crack)."""
    if isinstance(entry, dict):
        name, code, values, d = entry["name"], entry["exit"], entry["values"], entry["directory"]
    else:
        name, code, values, d = entry.name, entry.exit, entry.values, entry.directory
    r = dict(name=name, exit=code, **{k: v for k, v in values.items()})
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
            r.update(final_energy=E[-1], quadratic_coefficient=cfit,
                     critical_displacement=critical_displacement(D, E, cfit))
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


def sweep_rows(directory):
    """sweep.csv's rows (dicts, in sweep.json's order) and their columns (the union, in order of
    first appearance) for a sweep directory: (rows, columns)."""
    sw = directory if isinstance(directory, Sweep) else Sweep(directory)
    rows = [sweep_row(e)[0] for e in sw.runs]
    return rows, list(dict.fromkeys(k for r in rows for k in r))


def csv_value(v):
    """A cell as the reference writes it: floats with every digit (repr), the rest as str."""
    if isinstance(v, (float, np.floating)):
        return repr(float(v))
    return "" if v is None else str(v)


__all__ = ["quadratic_fit", "critical_displacement", "r_curve_points", "toughening_ratio", "run_r_curve",
           "sweep_row", "sweep_rows", "csv_value"]
