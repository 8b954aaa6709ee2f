# SPDX-License-Identifier: BSD-3-Clause
"""Charts of a dynamic nacre run (sibling of nacre.charts.mc, which charts Monte Carlo runs):
energy_force.png: energies against time, the energy-balance residual, and the reaction force
against the applied displacement; crack.png: the deformed triangle mesh of the last dump (or of
DUMP) coloured by each brick's vertical stress (Fig. 4.5), ruptured interfaces in black;
r_curve.png from the program's r_curve.csv.
Above RASTER_TRIANGLES triangles (or with --raster) the triangles are about the size of the
picture's pixels and drawing them polygon by polygon costs a minute per million bricks: they
are then rasterised directly (each pixel takes the stress of the triangle holding its centre;
gaps and an open crack stay white) and shown as an image with the same colour scale, the
ruptured interfaces drawn on top.

    python3 -m nacre.charts.dyn OUTPUT_DIR [DUMP.h5] [--magnify M] [--raster] [--quiet]
"""
import os
import sys

import numpy as np

from ..results import Dump, Run, read_h5
from ._common import have_matplotlib, pyplot, r_curve_chart, save_png

RASTER_TRIANGLES = 200_000  # ~50k bricks: past this, polygons are sub-pixel at dpi 130


def series(out):
    return Run(out).table()


def energy_force(out, s):
    plt = pyplot()
    t = s["time"] * 1e6  # µs
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.2))
    for key, label in [("strain_energy", "strain"), ("kinetic_energy", "kinetic"), ("cohesive_energy", "cohesive"),
                       ("damping_dissipated", "damping (dissipated)"), ("external_work", "external work")]:
        ax[0].plot(t, s[key], label=label)
    total = s["strain_energy"] + s["kinetic_energy"] + s["cohesive_energy"] + s["damping_dissipated"]
    ax[0].plot(t, total, "k--", lw=0.8, label="sum of the four")
    ax[0].set_xlabel("time (µs)")
    ax[0].set_ylabel("energy (N mm)")
    ax[0].legend(fontsize=8)
    ax[1].semilogy(t, np.maximum(np.abs(s["balance_residual"]), 1e-17))
    ax[1].set_xlabel("time (µs)")
    ax[1].set_ylabel("|energy balance residual| (relative)")
    ax[2].plot(s["displacement"], s["reaction"], color="C1")
    ax[2].set_xlabel("applied displacement D (mm)")
    ax[2].set_ylabel("reaction force (N)")
    a2 = ax[2].twinx()
    a2.plot(s["displacement"], s["ruptured"], ":", color="C3")
    a2.set_ylabel("ruptured interfaces", color="C3")
    fig.suptitle(os.path.basename(os.path.abspath(out)))
    fig.tight_layout()
    save_png(fig, os.path.join(out, "energy_force.png"), dpi=120)
    plt.close(fig)


def raster_image(pts, conn, val, nx, ny, x0, x1, y0, y1):
    """The triangles (nodes pts, connectivity conn) filled with val into an ny x nx image of
    [x0, x1] x [y0, y1]: a pixel takes the value of a triangle holding its centre (NaN where
    none does: gaps, an open crack). Vectorised over triangles, one pass per pixel offset
    within a triangle's bounding box, so it is fast for sub-pixel to few-pixel triangles."""
    img = np.full((ny, nx), np.nan)
    if len(conn) == 0:
        return img
    gx = (pts[conn][:, :, 0] - x0) / ((x1 - x0) / nx) - 0.5  # pixel-centre coordinates: centre i at i
    gy = (pts[conn][:, :, 1] - y0) / ((y1 - y0) / ny) - 0.5
    i0, i1 = np.ceil(gx.min(1)).astype(np.int64), np.floor(gx.max(1)).astype(np.int64)
    j0, j1 = np.ceil(gy.min(1)).astype(np.int64), np.floor(gy.max(1)).astype(np.int64)
    ax_, ay, bx, by, cx, cy = gx[:, 0], gy[:, 0], gx[:, 1], gy[:, 1], gx[:, 2], gy[:, 2]
    det = (bx - ax_) * (cy - ay) - (cx - ax_) * (by - ay)
    ok = det != 0
    det = np.where(ok, det, 1.0)
    for di in range(max(0, int((i1 - i0).max()) + 1)):
        for dj in range(max(0, int((j1 - j0).max()) + 1)):
            i, j = i0 + di, j0 + dj
            l1 = ((i - ax_) * (cy - ay) - (cx - ax_) * (j - ay)) / det
            l2 = ((bx - ax_) * (j - ay) - (i - ax_) * (by - ay)) / det
            m = ok & (i <= i1) & (j <= j1) & (i >= 0) & (i < nx) & (j >= 0) & (j < ny)
            m &= (l1 >= 0) & (l2 >= 0) & (l1 + l2 <= 1)
            img[j[m], i[m]] = val[m]
    return img


def crack(out, dump, magnify=None, target=None, raster=None):
    plt = pyplot()
    from matplotlib.collections import LineCollection, PolyCollection
    m, d = Run(out).mesh(), Dump(*read_h5(dump))
    conn = m["/triangles/connectivity"]
    ref = m["/nodes/reference"]
    tri_brick = m["/triangles/brick"]
    iref = m["/interfaces/reference_points"].reshape(-1, 2, 2) if "/interfaces/reference_points" in m else None
    u = d["/nodes/displacement"][:, :2]
    syy = d["/bricks/syy"]
    ipts = d["/interfaces/points"].reshape(-1, 2, 2) if "/interfaces/points" in d else None
    state = d.get("/interfaces/state")
    on_crack = d.get("/interfaces/crack")
    time, disp = float(d.attrs["time"]), float(d.attrs["displacement"])
    # displacements are small next to a brick: magnify them so the crack opening shows
    e1, e2 = ref[conn[:, 1]] - ref[conn[:, 0]], ref[conn[:, 2]] - ref[conn[:, 0]]
    size = np.sqrt(np.median(np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])))
    umax = np.abs(u).max()
    mag = magnify if magnify else (0.5 * size / umax if umax > 0 else 1.0)
    pts = ref + mag * u
    lim = np.percentile(np.abs(syy), 99) if len(syy) else 1.0
    lim = lim if lim > 0 else 1.0
    w = ref[:, 0].max() - ref[:, 0].min()
    h = ref[:, 1].max() - ref[:, 1].min()
    figsize = (min(14, 3 + 9 * w / max(h, w)), min(10, 1.5 + 9 * h / max(h, w)))
    fig, ax = plt.subplots(figsize=figsize)
    if raster if raster is not None else len(conn) > RASTER_TRIANGLES:
        x0, x1, y0, y1 = pts[:, 0].min(), pts[:, 0].max(), pts[:, 1].min(), pts[:, 1].max()
        nx = int(0.8 * figsize[0] * 130)  # about the axes' width in pixels at dpi 130
        ny = max(1, int(round(nx * (y1 - y0) / max(x1 - x0, 1e-300))))
        img = raster_image(pts, conn, syy[tri_brick], nx, ny, x0, x1, y0, y1)
        pc = ax.imshow(img, origin="lower", extent=(x0, x1, y0, y1), cmap="RdBu_r", vmin=-lim, vmax=lim,
                       interpolation="nearest")
    else:
        pc = PolyCollection(pts[conn], array=syy[tri_brick], cmap="RdBu_r", edgecolors="face", linewidths=0.3,
                            clim=(-lim, lim))
        ax.add_collection(pc)
    fig.colorbar(pc, ax=ax, shrink=0.7, label="vertical stress per brick (N/mm²)")
    nr = 0
    if ipts is not None and state is not None and len(state):
        ipts = iref + mag * (ipts - iref)
        broken = ipts[state == 2]
        nr = len(broken)
        ax.add_collection(LineCollection(broken, colors="black", linewidths=1.0))
    ncrack = 0
    if ipts is not None and on_crack is not None and (on_crack == 1).any():
        sel = on_crack == 1  # the crack from the notch (docs/fracture.md): thick, its tip marked
        ncrack = int(sel.sum())
        ax.add_collection(LineCollection(ipts[sel], colors="darkviolet", linewidths=2.0, zorder=3))
        ends, ends_ref = ipts[sel].reshape(-1, 2), iref[sel].reshape(-1, 2)
        tip = ends[np.argmax(ends_ref[:, 0])]
        ax.plot([tip[0]], [tip[1]], "x", color="black", markersize=9, mew=2, zorder=4)
    ax.autoscale()
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.set_title(f"t = {time * 1e6:.4g} µs, D = {disp:.4g} mm (displacements x{mag:.3g}): {nr} ruptured (black)\n"
                 f"{ncrack} on the crack from the notch (violet), its tip x", fontsize=10)
    fig.tight_layout()
    save_png(fig, target or os.path.join(out, "crack.png"), dpi=130)
    plt.close(fig)


def main(argv=None):
    argv = list(sys.argv[1:] if argv is None else argv)
    mag = None
    if "--magnify" in argv:
        k = argv.index("--magnify")
        if k + 1 >= len(argv):
            sys.exit(__doc__)
        mag = float(argv[k + 1])
        del argv[k:k + 2]
    unknown = [a for a in argv if a.startswith("--") and a not in ("--raster", "--quiet")]
    if unknown:
        sys.exit(f"nacre: unknown option {unknown[0]}\n{__doc__}")
    raster = True if "--raster" in argv else None
    quiet = "--quiet" in argv
    args = [a for a in argv if not a.startswith("--")]
    if not args or len(args) > 2:
        sys.exit(__doc__)
    if not have_matplotlib():
        return 0
    out = args[0]
    run = Run(out)
    s = run.table()
    if s is not None and len(s["time"]) > 1:
        energy_force(out, s)
    r_curve_chart(run, quiet=quiet)
    dump = args[1] if len(args) > 1 else run.dump_path()
    if dump and os.path.exists(os.path.join(out, "mesh.h5")):
        crack(out, dump, mag, raster=raster)
    return 0


if __name__ == "__main__":
    sys.exit(main())
