#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Weak and strong scaling model of the Monte Carlo cycle over MPI ranks (docs/scaling.md).

Inputs, each stated in the output:
  * halo.csv (perf/run_par_scaling.sh, nacre_perf_par --model-only): the largest halo and the
    neighbour count of a rank for each rank count, measured on nacre's decomposition; fitted as
    halo = c sqrt(owned) (a block's perimeter);
  * the GPU's time per cycle against bricks, a two-point fit of docs/gpu.md's H200 rows
    (995,412 bricks 0.636 ms, 3,978,556 bricks 1.98 ms): t = t0 + n / R;
  * the network and the host staging: ASSUMED constants (InfiniBand NDR-class latency and
    bandwidth, a PCIe copy's latency), named below; change them with --alpha etc.
Per cycle and rank: each colour sweeps, then its halo bricks go to every neighbour (5 doubles
each, through host copies: no GPU-aware MPI assumed) and the stale energies are refreshed; once
per cycle the accepted energy change is summed (deterministic_sum over ranks: three
MPI_Allreduce of a few words, each ~ log2(P) latencies). No overlap of sweep and messages.

    perf/par_model.py perf/results/par            (reads halo.csv; writes model.csv, model.md, scaling.png)
"""
import argparse
import csv
import math
import os


def fit_halo(rows):
    # least squares of halo = c sqrt(owned) over the multi-rank rows
    num = den = 0.0
    for r in rows:
        if int(r["ranks"]) < 2:
            continue
        s = math.sqrt(float(r["max_owned"]))
        num += float(r["max_halo_bricks"]) * s
        den += s * s
    return num / den


def dynamics_model(a, c, nb):
    """The dynamic step over ranks (docs/scaling.md "Dynamics over ranks"): per step the method's
    GPU step, its halo exchanges (each: a latency per neighbour, the bytes over the network, two
    host copies, pack and unpack launches) and, every 32 steps, the books' reproducible sums."""
    fits = {  # method: (t0 s, bricks/s, bytes per halo brick, exchanges per step)
        "BE": (1.20e-3 - 981414 / ((3921092 - 981414) / (4.39e-3 - 1.20e-3)), (3921092 - 981414) / (4.39e-3 - 1.20e-3), 80, 1),
        "BIE": (2.52e-3 - 981414 / ((3921092 - 981414) / (9.68e-3 - 2.52e-3)), (3921092 - 981414) / (9.68e-3 - 2.52e-3), 80, 2),
        "UE": (0.0, 981414 / 2.39e-3, 192, 1),
    }
    rows = []
    for method in ("BE", "BIE", "UE"):
        t0, R, row_bytes, exchanges = fits[method]
        for label, per_rank in (("weak, 1M bricks per GPU", 1_000_000), ("weak, 40k bricks per GPU", 40_000)):
            for P in (1, 8, 1000):
                comp = t0 + per_rank / R
                if P == 1:
                    halo = red = 0.0
                else:
                    b = c * math.sqrt(per_rank) * row_bytes
                    halo = exchanges * (nb * a.alpha + b / a.beta + 2 * a.stage + 2 * b / a.pcie + 2 * a.launch)
                    red = 7 * 3 * math.ceil(math.log2(P)) * a.alpha / 32
                rows.append((f"dyn {method} {label}", P, per_rank, comp, halo, red, comp / (comp + halo + red)))
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out")
    ap.add_argument("--alpha", type=float, default=2e-6, help="MPI point-to-point latency, s (assumed)")
    ap.add_argument("--beta", type=float, default=25e9, help="network bandwidth per rank, B/s (assumed, NDR 200)")
    ap.add_argument("--stage", type=float, default=8e-6, help="one host<->device copy's latency, s (assumed)")
    ap.add_argument("--pcie", type=float, default=25e9, help="host<->device bandwidth, B/s (assumed)")
    ap.add_argument("--launch", type=float, default=5e-6, help="pack/unpack/refresh kernel launch, s (assumed)")
    ap.add_argument("--colours", type=int, default=0, help="colours per cycle (0: halo.csv's)")
    a = ap.parse_args()

    rows = list(csv.DictReader(open(os.path.join(a.out, "halo.csv"))))
    c = fit_halo(rows)
    colours = a.colours or int(rows[0]["colours"])
    nb = max(int(r["max_neighbours"]) for r in rows)
    # H200 fit (docs/gpu.md, "Second run" table): t = t0 + n / R
    n1, t1, n2, t2 = 995412, 0.636e-3, 3978556, 1.98e-3
    R = (n2 - n1) / (t2 - t1)
    t0 = t1 - n1 / R

    def cycle(n, P):
        comp = t0 + n / R
        if P == 1:
            return comp, 0.0, 0.0
        halo_bytes = c * math.sqrt(n) * 40.0  # every halo brick once per cycle, 5 doubles
        per_colour = halo_bytes / colours
        halo = colours * (nb * a.alpha + per_colour / a.beta + 2 * a.stage + 2 * per_colour / a.pcie + 3 * a.launch)
        reduce = 3 * math.ceil(math.log2(P)) * a.alpha
        return comp, halo, reduce

    out_rows = []
    for label, per_rank in (("weak, 1M bricks per GPU", 1_000_000), ("weak, 40k bricks per GPU", 40_000)):
        for P in (1, 8, 64, 512, 1000):
            comp, halo, red = cycle(per_rank, P)
            out_rows.append((label, P, per_rank, comp, halo, red, comp / (comp + halo + red)))
    total = 40_000_000  # real nacre, 10 mm x 10 mm of 5 x 0.5 um bricks
    base = sum(cycle(total, 1)[:3])
    for P in (1, 8, 64, 512, 1000):
        comp, halo, red = cycle(total / P, P)
        out_rows.append(("strong, 40M bricks", P, total // P, comp, halo, red, base / (P * (comp + halo + red))))

    with open(os.path.join(a.out, "model.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["case", "ranks", "bricks_per_rank", "compute_s", "halo_s", "reduce_s", "efficiency"])
        for r in out_rows:
            w.writerow([r[0], r[1], r[2], f"{r[3]:.4g}", f"{r[4]:.4g}", f"{r[5]:.4g}", f"{r[6]:.3f}"])
    with open(os.path.join(a.out, "model.md"), "w") as f:
        f.write(f"Halo fit: halo bricks = {c:.2f} sqrt(owned); {colours} colours; up to {nb} neighbours.\n")
        f.write(f"GPU cycle fit (H200): t = {t0 * 1e3:.3f} ms + n / {R / 1e9:.2f} G bricks/s.\n")
        f.write(f"Assumed: alpha {a.alpha * 1e6:.1f} us, network {a.beta / 1e9:.0f} GB/s, host copy "
                f"{a.stage * 1e6:.0f} us + {a.pcie / 1e9:.0f} GB/s, launch {a.launch * 1e6:.0f} us.\n\n")
        f.write("| case | ranks | bricks/rank | compute ms | halo ms | reduce ms | efficiency |\n|---|---|---|---|---|---|---|\n")
        for r in out_rows:
            f.write(f"| {r[0]} | {r[1]} | {r[2]:,} | {r[3] * 1e3:.3f} | {r[4] * 1e3:.3f} | {r[5] * 1e3:.3f} | {r[6]:.2f} |\n")
    dyn_rows = dynamics_model(a, c, nb)
    with open(os.path.join(a.out, "model.md"), "a") as f:
        f.write("\nDynamics (one halo exchange of u per interface-force pass, dyn/halo.hpp): time per step.\n"
                "GPU step fits (H200, docs/gpu.md): BE t = 0.13 ms + n / 0.92 G bricks/s "
                "(981,414: 1.20 ms, 3,921,092: 4.39 ms); BIE split t = 0.29 ms + n / 0.44 G bricks/s "
                "(2.52, 9.68 ms); UE n / 0.41 G bricks/s (one point). Halo row: the halo brick's elements' u "
                "(BE, BIE 80 B, UE 192 B); exchanges per step: BE, UE 1, BIE 2; the books' sums every "
                "32 steps (7 reproducible sums).\n\n")
        f.write("| case | ranks | bricks/rank | compute ms | halo ms | reduce ms | efficiency |\n|---|---|---|---|---|---|---|\n")
        for r in dyn_rows:
            f.write(f"| {r[0]} | {r[1]} | {r[2]:,} | {r[3] * 1e3:.3f} | {r[4] * 1e3:.3f} | {r[5] * 1e3:.3f} | {r[6]:.2f} |\n")
    with open(os.path.join(a.out, "model.csv"), "a", newline="") as f:
        w = csv.writer(f)
        for r in dyn_rows:
            w.writerow([r[0], r[1], r[2], f"{r[3]:.4g}", f"{r[4]:.4g}", f"{r[5]:.4g}", f"{r[6]:.3f}"])
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(6, 4))
        Ps = [2 ** k for k in range(0, 11)]
        for per_rank, style in ((1_000_000, "-"), (250_000, "--"), (40_000, ":")):
            eff = [cycle(per_rank, P)[0] / sum(cycle(per_rank, P)) for P in Ps]
            ax.semilogx(Ps, eff, style, label=f"weak, {per_rank:,} bricks/GPU")
        eff = [base / (P * sum(cycle(total / P, P))) for P in Ps]
        ax.semilogx(Ps, eff, "-.", label="strong, 40M bricks")
        ax.set_xlabel("GPUs (ranks)")
        ax.set_ylabel("parallel efficiency (model)")
        ax.set_ylim(0, 1.05)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
        ax.set_title("Monte Carlo cycle over MPI ranks: model from measured halos")
        fig.tight_layout()
        fig.savefig(os.path.join(a.out, "scaling.png"), dpi=120)
    except ImportError:
        pass
    print(open(os.path.join(a.out, "model.md")).read())


if __name__ == "__main__":
    main()
