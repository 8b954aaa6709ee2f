#!/usr/bin/env python3
"""Charts of a nacre run: energy and reaction force against applied displacement
(energy_force.png) and the final crack (crack.png: bricks coloured by energy, displaced,
ruptured interfaces in red). Usage: nacre_plot.py OUTPUT_DIR"""
import csv
import os
import re
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection, PolyCollection  # noqa: E402



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

def main(out):
    rows = list(csv.DictReader(open(os.path.join(out, "steps.csv"))))
    D = np.array([0.0] + [float(r["displacement"]) for r in rows])
    E = np.array([0.0] + [float(r["energy"]) for r in rows])
    F = np.array([0.0] + [float(r["reaction"]) for r in rows])
    R = np.array([0] + [int(r["ruptured"]) for r in rows])
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    ax[0].plot(D, E, "o-", ms=3, label="Monte Carlo")
    # quadratic fit through the first steps shows where the response leaves linear elasticity
    n0 = max(2, len(D) // 5)
    c = np.dot(D[:n0] ** 2, E[:n0]) / max(np.dot(D[:n0] ** 2, D[:n0] ** 2), 1e-300)
    ax[0].plot(D, c * D ** 2, "--", color="gray", label="quadratic (initial fit)")
    ax[0].set_xlabel("applied displacement D")
    ax[0].set_ylabel("total energy")
    ax[0].legend()
    ax[1].plot(D, F, "o-", ms=3, color="C1")
    ax[1].set_xlabel("applied displacement D")
    ax[1].set_ylabel("reaction force dE/dD")
    a2 = ax[1].twinx()
    a2.plot(D, R, ":", color="C3")
    a2.set_ylabel("ruptured interfaces", color="C3")
    fig.suptitle(os.path.basename(os.path.abspath(out)))
    fig.tight_layout()
    save_png(fig, os.path.join(out, "energy_force.png"), dpi=120)
    plt.close(fig)

    # nacre's dumps only (dump_NNNNN.h5): a stray dump_final.h5 or dump_7.h5.bak is not one
    dumps = sorted((int(m.group(1)), os.path.join(out, f)) for f in os.listdir(out)
                   if (m := re.fullmatch(r"dump_(\d+)\.h5", f)))
    dumps = [p for _, p in dumps]
    mesh = os.path.join(out, "mesh.h5")
    if not dumps or not os.path.exists(mesh):
        return
    import h5py
    with h5py.File(mesh, "r") as m, h5py.File(dumps[-1], "r") as d:
        topo = m["/bricks/topology"][:]
        pts = d["/bricks/points"][:]
        energy = d["/bricks/energy"][:]
        area = m["/bricks/area"][:]
        ipts = d["/interfaces/points"][:].reshape(-1, 2, 2)
        state = d["/interfaces/state"][:]
        disp = d.attrs["displacement"]
        ref = m["/bricks/reference_points"][:]
        iref = m["/interfaces/reference_points"][:].reshape(-1, 2, 2)
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
    ax.autoscale()
    ax.set_aspect("equal")
    ax.set_title(f"D = {disp:.4g} (displacements x{mag:.0f}): {len(broken)} ruptured (red), "
                 f"{len(soft)} softening (orange)")
    fig.tight_layout()
    save_png(fig, os.path.join(out, "crack.png"), dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
