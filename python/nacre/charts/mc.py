# SPDX-License-Identifier: BSD-3-Clause
"""Charts of a Monte Carlo nacre run: energy and reaction force against applied displacement
(energy_force.png), the final crack (crack.png: bricks coloured by energy, displaced, ruptured
interfaces in red, the crack from the notch dark red) and the R-curve (r_curve.png, from the
program's r_curve.csv; docs/fracture.md).

    python3 -m nacre.charts.mc OUTPUT_DIR [--quiet]
"""
import os
import sys

import numpy as np

from ..analysis import quadratic_fit
from ..results import Run
from ._common import command_line, pyplot, r_curve_chart, save_png, warn


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
    from matplotlib.collections import LineCollection
    sel = on_crack == 1
    if not sel.any():
        return 0
    ax.add_collection(LineCollection(ipts[sel], colors="darkred", linewidths=2.4, zorder=3))
    ends, ends_ref = ipts[sel].reshape(-1, 2), iref[sel].reshape(-1, 2)
    tip = ends[np.argmax(ends_ref[:, 0])]
    ax.plot([tip[0]], [tip[1]], "x", color="black", markersize=9, mew=2, zorder=4)
    return int(sel.sum())


def energy_force(run, t):
    """energy_force.png: energy (with the initial quadratic fit) and reaction against D, one curve
    per leg of a load programme, the ruptured interfaces on a second axis."""
    plt = pyplot()
    D = np.concatenate([[0.0], t["displacement"]])
    E = np.concatenate([[0.0], t["energy"]])
    F = np.concatenate([[0.0], t["reaction"]])
    R = np.concatenate([[0.0], t["ruptured"]])
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
    if run.summary.get("damage") == "irreversible" and "fracture_energy" in t:
        W = np.concatenate([[0.0], t["fracture_energy"]])
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
    fig.suptitle(os.path.basename(os.path.abspath(run.directory)))
    fig.tight_layout()
    save_png(fig, run.path("energy_force.png"), dpi=120)
    plt.close(fig)


def crack(run):
    """crack.png of the last dump (nacre's dump_NNNNN.h5: a stray dump_final.h5 or dump_7.h5.bak
    is not one); nothing without a dump or mesh.h5."""
    m, d = run.mesh(), run.dump()
    if d is None or m is None:
        return
    plt = pyplot()
    from matplotlib.collections import LineCollection, PolyCollection
    from matplotlib.colors import LogNorm
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
    save_png(fig, run.path("crack.png"), dpi=120)
    plt.close(fig)


def main(argv=None):
    parsed = command_line(argv, __doc__)
    if parsed is None:
        return 0
    args, flags = parsed
    run = Run(args[0])
    r_curve_chart(run, quiet="--quiet" in flags)
    t = run.table()
    if t is None or not len(t.get("displacement", ())):
        warn(f"{run.path(run.table_name)} holds no rows; energy_force.png skipped")
    else:
        energy_force(run, t)
    crack(run)
    return 0


if __name__ == "__main__":
    sys.exit(main())
