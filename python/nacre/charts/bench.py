# SPDX-License-Identifier: BSD-3-Clause
"""The chart of a `nacre bench` run: per backend, the time per step (or cycle) split into the
solver's phases (its labelled Kokkos regions, the innermost ones that partition the timed
stretch), and the throughput against the backend's triad bound where the solver states the bytes
a step must move. Reads BENCH_DIR/bench.json, writes BENCH_DIR/bench.png.

    python3 -m nacre.charts.bench BENCH_DIR [--quiet]
"""
import os
import sys

from ..results import Bench
from ._common import command_line, pyplot, save_png


def leaf_phases(phases):
    """Regions that hold no other listed region (by name prefix of the solver's hierarchy is not
    available, so: drop the outermost driver regions that contain the others)."""
    drop = {"nacre::dyn::advance", "nacre::mc::cycle"}
    return {k: v for k, v in phases.items() if k not in drop}


def main(argv=None):
    parsed = command_line(argv, __doc__)
    if parsed is None:
        return 0
    args, flags = parsed
    d = args[0]
    b = Bench(d)
    j = b.json
    names = b.backends
    unit = j["unit"]
    plt = pyplot()
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(12, 4.8))
    phases = sorted({p for n in names for p in leaf_phases(b.backend(n).get("phases", {}))})
    bottom = [0.0] * len(names)
    for p in phases:
        v = [1e3 * b.backend(n).get("phases", {}).get(p, 0.0) for n in names]
        ax.bar(names, v, bottom=bottom, label=p.split("::")[-1])
        bottom = [x + y for x, y in zip(bottom, v)]
    tot = [1e3 * b.backend(n)["seconds_per_unit"] for n in names]
    ax.plot(names, tot, "k_", markersize=30, label="total")
    ax.set_ylabel(f"ms per {unit}")
    ax.set_title(f"{os.path.basename(j['deck'])}: {j['bricks']} bricks, phases by backend")
    ax.legend(fontsize=7, ncol=2)
    key = "brick_steps_per_second" if j["solver"] == "dynamics" else "trials_per_second"
    thr = [b.backend(n)[key] for n in names]
    ax2.bar(names, thr, color="tab:blue")
    for i, n in enumerate(names):
        e = b.backend(n)
        f = e.get("fraction_of_triad")
        fma = e.get("fraction_of_fma")
        note = f"x{e['speedup_over_reference']:.2f}" + (f", {100 * f:.0f}% of triad" if f else "")
        note += f", {100 * fma:.0f}% of FMA" if fma else ""
        if e.get("rng_gbit_per_s"):
            note += f"\nrng {e['rng_gbit_per_s']:.3g} Gbit/s"
        note += "\n" + ("bit-identical" if e.get("bit_identical_to_" + names[0], False)
                        else "not judged" if not e.get("agreement_judged", True)
                        else "within tolerance" if e.get("agrees", False) else "DIFFERS")
        ax2.text(i, thr[i], note, ha="center", va="bottom", fontsize=8)
    ax2.set_ylim(0, 1.25 * max(thr))  # room for the notes above the bars
    ax2.set_ylabel("brick-steps per second" if j["solver"] == "dynamics" else "brick trials per second")
    ax2.set_title(f"throughput; speed-up over {j['reference_backend']}; agreement {j['agreement']}")
    gpu = j["machine"].get("gpu")
    fig.suptitle(f"{j['machine']['cpu']}" + (f", {gpu['name']}" if gpu else "") +
                 f", Kokkos {j['machine']['kokkos_version']}", fontsize=9)
    fig.tight_layout()
    save_png(fig, os.path.join(d, "bench.png"), dpi=110)
    plt.close(fig)
    if "--quiet" not in flags:
        print(f"nacre.charts.bench: {os.path.join(d, 'bench.png')}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
