#!/usr/bin/env python3
"""Charts of a nacre run: energy and reaction force against applied displacement
(energy_force.png), the final crack (crack.png: bricks coloured by energy, displaced,
ruptured interfaces in red, the crack from the notch dark red) and the R-curve (r_curve.csv,
r_curve.png; docs/fracture.md). Usage: nacre_plot.py OUTPUT_DIR [--quiet]"""
import csv
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection, PolyCollection  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from nacre_results import Run  # noqa: E402  (the one reader of run directories)



def save_png(fig, path, **kw):
    """Write the chart to a temporary sibling and rename it: a failure (a full disk) leaves no
    truncated PNG under the final name, and the script exits non-zero."""
    tmp = os.path.join(os.path.dirname(path) or ".", "." + os.path.basename(path) + ".tmp%d" % os.getpid())
    try:
        fig.savefig(tmp, format="png", **kw)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.remove(tmp)
        raise

def quadratic_fit(D, E):
    """c of E = c D^2 fitted (least squares) through the first fifth of the points (at least 2):
    where the response leaves linear elasticity (energy_force.png, the sweep's Fig. 2.8b)."""
    n0 = max(2, len(D) // 5)
    return float(np.dot(D[:n0] ** 2, E[:n0]) / max(np.dot(D[:n0] ** 2, D[:n0] ** 2), 1e-300))


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


def r_curve(out, rows):
    """r_curve.csv and r_curve.png of a run directory (both solver families); prints the
    toughening ratio. Nothing is written for a run whose summary.json has no crack reading."""
    crack = Run(out).summary.get("crack", {})
    if not rows or "fracture_energy" not in rows[0] or "bed_work_of_fracture" not in crack:
        return None
    t, gc = crack["thickness"], crack["bed_work_of_fracture"]
    pts = r_curve_points(rows, t, gc)
    ratio = toughening_ratio(pts, t, gc)
    path = os.path.join(out, "r_curve.csv")
    tmp = os.path.join(out, ".r_curve.csv.tmp%d" % os.getpid())
    with open(tmp, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["extension", "fracture_energy", "G_R", "toughening"])
        w.writeheader()
        for p in pts:
            w.writerow({k: repr(v) for k, v in p.items()})
    os.replace(tmp, path)
    fig, ax = plt.subplots(figsize=(6.5, 4.2))
    if pts:
        ax.step([p["extension"] for p in pts], [p["G_R"] for p in pts], where="pre", color="C0",
                label="G_R (energy of fracture gained / extension gained)")
    ax.axhline(gc, color="gray", ls="--", label=f"mortar's work of fracture k x1 x2 = {gc:.4g}")
    ax.set_xlabel("crack extension (along the ligament)")
    ax.set_ylabel("G_R (energy per unit crack area)")
    ax.set_ylim(bottom=0)
    said = f"{ratio:.3g}" if ratio == ratio else "n/a (the crack grew at fewer than 2 rows)"
    ax.set_title(f"R-curve: toughening ratio {said}\n(mean G_R over the second half of the extension / k x1 x2)", fontsize=10)
    ax.legend(fontsize=8)
    fig.tight_layout()
    save_png(fig, os.path.join(out, "r_curve.png"), dpi=120)
    plt.close(fig)
    if "--quiet" not in sys.argv:
        print(f"crack: extension {crack.get('extension', 0):.4g} to tip x = {crack.get('tip_x', 0):.4g}, "
              f"deflection {crack.get('deflection', 0):.3f}, toughening ratio {said} (r_curve.csv)")
    return ratio


def path_legs(D):
    """Index ranges [i0, i1] of the monotonic legs of a load path D (one leg for a monotonic run)."""
    legs, i0 = [], 0
    for i in range(1, len(D) - 1):
        if (D[i] - D[i - 1]) * (D[i + 1] - D[i]) < 0:
            legs.append((i0, i))
            i0 = i
    legs.append((i0, len(D) - 1))
    return legs


def draw_crack(ax, ipts, iref, on_crack):
    """The crack from the notch (the dumps' "crack" field, docs/fracture.md) drawn thick, its tip
    (the end point furthest along x in the reference frame) marked; returns its joint count."""
    sel = on_crack == 1
    if not sel.any():
        return 0
    ax.add_collection(LineCollection(ipts[sel], colors="darkred", linewidths=2.4, zorder=3))
    ends, ends_ref = ipts[sel].reshape(-1, 2), iref[sel].reshape(-1, 2)
    tip = ends[np.argmax(ends_ref[:, 0])]
    ax.plot([tip[0]], [tip[1]], "x", color="black", markersize=9, mew=2, zorder=4)
    return int(sel.sum())


def main(out):
    run = Run(out)
    rows = run.rows()
    r_curve(out, rows)
    D = np.array([0.0] + [float(r["displacement"]) for r in rows])
    E = np.array([0.0] + [float(r["energy"]) for r in rows])
    F = np.array([0.0] + [float(r["reaction"]) for r in rows])
    R = np.array([0] + [int(r["ruptured"]) for r in rows])
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    # a load programme ([load] programme) turns back: one curve per leg, so the loop reads
    legs = path_legs(D)
    for k, (i0, i1) in enumerate(legs):
        tag = "Monte Carlo" if len(legs) == 1 else (("load" if D[i1] > D[i0] else "unload") + f" to {D[i1]:g}")
        ax[0].plot(D[i0:i1 + 1], E[i0:i1 + 1], "o-", ms=3, color=f"C{k}", label=tag)
        ax[1].plot(D[i0:i1 + 1], F[i0:i1 + 1], "o-", ms=3, color=f"C{k}" if len(legs) > 1 else "C1", label=tag)
    # quadratic fit through the first steps shows where the response leaves linear elasticity
    c = quadratic_fit(D, E)
    D1 = D[:legs[0][1] + 1]
    ax[0].plot(D1, c * D1 ** 2, "--", color="gray", label="quadratic (initial fit)")
    if run.summary.get("damage") == "irreversible" and "fracture_energy" in rows[0]:
        W = np.array([0.0] + [float(r["fracture_energy"]) for r in rows])
        ax[0].plot(D, W, ":", color="k", label="dissipated (irreversible damage)")
    ax[0].set_xlabel("applied displacement D")
    ax[0].set_ylabel("total energy")
    ax[0].legend()
    if len(legs) > 1:
        ax[1].legend(loc="upper left", fontsize=8)
    ax[1].set_xlabel("applied displacement D")
    ax[1].set_ylabel("reaction force dE/dD")
    a2 = ax[1].twinx()
    a2.plot(D, R, ":", color="C3")
    a2.set_ylabel("ruptured interfaces", color="C3")
    fig.suptitle(os.path.basename(os.path.abspath(out)))
    fig.tight_layout()
    save_png(fig, os.path.join(out, "energy_force.png"), dpi=120)
    plt.close(fig)

    # the last of nacre's dumps (dump_NNNNN.h5: a stray dump_final.h5 or dump_7.h5.bak is not one)
    m, d = run.mesh(), run.dump()
    if d is None or m is None:
        return
    topo = m["/bricks/topology"]
    pts = d["/bricks/points"]
    energy = d["/bricks/energy"]
    area = m["/bricks/area"]
    ipts = d["/interfaces/points"].reshape(-1, 2, 2)
    state = d["/interfaces/state"]
    on_crack = d.get("/interfaces/crack", np.zeros_like(state))
    disp = d.attrs["displacement"]
    ref = m["/bricks/reference_points"]
    iref = m["/interfaces/reference_points"].reshape(-1, 2, 2)
    # displacements are tiny next to a brick: magnify them so the crack opening shows
    u = pts - ref
    umax = np.abs(u).max()
    h = np.sqrt(np.median(area))
    mag = 0.3 * h / umax if umax > 0 else 1.0
    pts = ref + mag * u
    polys, i = [], 0
    while i < len(topo):
        n = topo[i + 1]
        polys.append(pts[topo[i + 2:i + 2 + n]])
        i += 2 + n
    density = np.maximum(energy / area, 1e-12)
    fig, ax = plt.subplots(figsize=(9, 6))
    from matplotlib.colors import LogNorm
    pc = PolyCollection(polys, array=density, cmap="viridis", edgecolors="none",
                        norm=LogNorm(vmin=max(density.max() * 1e-4, 1e-12), vmax=density.max()))
    ax.add_collection(pc)
    fig.colorbar(pc, ax=ax, shrink=0.7, label="brick energy / area")
    ipts = iref + mag * (ipts - iref)
    broken = ipts[state == 2]
    ax.add_collection(LineCollection(broken, colors="red", linewidths=1.2, label="ruptured"))
    soft = ipts[state == 1]
    ax.add_collection(LineCollection(soft, colors="orange", linewidths=0.6, label="softening"))
    ncrack = draw_crack(ax, ipts, iref, on_crack)
    ax.autoscale()
    ax.set_aspect("equal")
    ax.set_title(f"D = {disp:.4g} (displacements x{mag:.0f}): {len(broken)} ruptured (red), "
                 f"{len(soft)} softening (orange)\n{ncrack} on the crack from the notch (dark red), its tip x", fontsize=10)
    fig.tight_layout()
    save_png(fig, os.path.join(out, "crack.png"), dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    args = [a for a in sys.argv[1:] if a != "--quiet"]
    if len(args) != 1:
        sys.exit(__doc__)
    main(args[0])
