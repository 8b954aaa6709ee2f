#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Scaling of total time with the number of bricks (perf/run_scaling.sh): fits time = a N^p by
least squares in log-log, for the solve (CPU time minus initialisation; wall time minus
initialisation for a study run on more threads, perf/app_runs.sh's NACRE_APP_THREADS, where idle
threads spinning at barriers would count as CPU time), the initialisation, and
the iteration counts that explain the exponent (Monte Carlo cycles; Newton steps and CG
iterations; FIRE steps); writes OUTDIR/scaling.csv, scaling.md and scaling.png.

    perf/plot_scaling.py OUTDIR
    perf/plot_scaling.py --compare OUT DIR1 DIR2 ...   (one study per relaxation, e.g.
        perf/run_scaling_methods.sh's: OUT/scaling_methods.md and .png, exponents side by side)"""
import csv
import math
import os
import re
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "python"))
from nacre import Run  # noqa: E402  (the reader of nacre's outputs, python/nacre)


def relaxation_of(run_dir):
    m = re.search(r'^relaxation = "([\w-]+)"', open(os.path.join(run_dir, "deck.toml")).read(), flags=re.M)
    return m.group(1) if m else "monte-carlo"


def load(out):
    rows = []
    for d in sorted(os.listdir(out)):
        p = os.path.join(out, d)
        if not (d.startswith("n") and os.path.exists(os.path.join(p, "time.txt"))
                and os.path.exists(os.path.join(p, "summary.json"))):
            continue
        user, sysc, wall = (float(x) for x in open(os.path.join(p, "time.txt")).read().split()[-3:])
        run = Run(p)
        s = run.summary
        m = re.search(r"bricks, \d+ interfaces \(([0-9.eE+-]+) s\)", open(os.path.join(p, "log.txt")).read())
        init = float(m.group(1)) if m else float("nan")
        steps = run.rows()
        tp = os.path.join(p, "threads")
        threads = int(open(tp).read()) if os.path.exists(tp) else 1
        rows.append(dict(bricks=s["bricks"], free=s["free_bricks"], steps=s["steps"], cycles=s["cycles"],
                         polish_iterations=s["polish_iterations"], cg_iterations=s.get("cg_iterations", 0),
                         cpu=user + sysc, wall=wall, init=init, threads=threads,
                         solve=(user + sysc if threads == 1 else wall) - init,
                         max_residual=max(float(r["residual"]) for r in steps), relaxation=relaxation_of(p)))
    rows.sort(key=lambda r: r["bricks"])
    if len({r["threads"] for r in rows}) > 1:
        sys.exit(f"plot_scaling: {out} mixes thread counts; one study is one thread count")
    return rows


def time_unit(rows):
    t = rows[0]["threads"]
    return "CPU s, 1 thread" if t == 1 else f"wall s, {t} threads"


def fit(xs, ys):
    """p, a of y = a x^p (least squares in log-log); None where a value is not positive."""
    if len(xs) < 2 or min(ys) <= 0:
        return None
    lx, ly = [math.log(x) for x in xs], [math.log(y) for y in ys]
    n = len(lx)
    mx, my = sum(lx) / n, sum(ly) / n
    sxx = sum((a - mx) ** 2 for a in lx)
    p = sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / sxx
    return p, math.exp(my - p * mx)


def exponent(f):
    return f"N^{f[0]:.2f}" if f else "-"


def fits(rows):
    N = [r["bricks"] for r in rows]
    return {k: fit(N, [max(r[k], 1e-6) if k == "init" else r[k] for r in rows])
            for k in ("solve", "init", "cycles", "polish_iterations", "cg_iterations")}


def single(out):
    rows = load(out)
    with open(os.path.join(out, "scaling.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()) if rows else ["bricks"])
        w.writeheader()
        w.writerows(rows)
    if len(rows) < 2:
        sys.exit("plot_scaling: need at least two sizes")
    fs = fits(rows)
    with open(os.path.join(out, "scaling.md"), "w") as f:
        f.write("| bricks | relaxation | steps | MC cycles | polish / Newton it. | CG it. | max residual | init s | "
                f"solve ({time_unit(rows)}) | total CPU s | wall s |\n|---|---|---|---|---|---|---|---|---|---|---|\n")
        for r in rows:
            f.write(f"| {r['bricks']} | {r['relaxation']} | {r['steps']} | {r['cycles']} | {r['polish_iterations']} | "
                    f"{r['cg_iterations']} | {r['max_residual']:.1e} | {r['init']:.3f} | {r['solve']:.1f} | "
                    f"{r['cpu']:.1f} | {r['wall']:.1f} |\n")
        f.write(f"\nFitted (least squares, log-log, {len(rows)} sizes): solve time ~ {exponent(fs['solve'])}, "
                f"cycles ~ {exponent(fs['cycles'])}, polish / Newton iterations ~ "
                f"{exponent(fs['polish_iterations'])}, CG iterations ~ {exponent(fs['cg_iterations'])}, "
                f"initialisation ~ {exponent(fs['init'])}\n")
    print(open(os.path.join(out, "scaling.md")).read())
    plt = pyplot()
    if plt is None:
        return
    N = [r["bricks"] for r in rows]
    fig, ax = plt.subplots(figsize=(7, 5))
    ax.loglog(N, [r["solve"] for r in rows], "o", color="C0", label=f"solve ({time_unit(rows)})")
    ax.loglog(N, [r["init"] for r in rows], "s", color="C2", label="initialisation (s)")
    xs = [N[0], N[-1]]
    for key, colour in (("solve", "C0"), ("init", "C2")):
        if fs[key]:
            p, a = fs[key]
            ax.loglog(xs, [a * x ** p for x in xs], "-", color=colour, label=f"fit N^{p:.2f}")
    ax.loglog(xs, [rows[0]["solve"] * (x / N[0]) ** 1.5 for x in xs], ":", color="gray", label="N^1.5 (dissertation)")
    ax.set_xlabel("bricks")
    ax.set_ylabel("seconds")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title(f"Time to the same final displacement against specimen size ({rows[0]['relaxation']})", fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "scaling.png"), dpi=120)


def name_of(d, rows):
    """the study's relaxation, or its directory's name where that says more (newton-eigen: the
    same relaxation measured with another build)"""
    base = os.path.basename(os.path.normpath(d))
    return base if base.startswith(rows[0]["relaxation"]) else rows[0]["relaxation"]


def compare(out, dirs):
    studies = [(d, load(d)) for d in dirs]
    studies = [(d, rows) for d, rows in studies if rows]
    if not studies:
        sys.exit("plot_scaling --compare: no runs found")
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "scaling_methods.md"), "w") as f:
        f.write("| relaxation | sizes (bricks) | solve s | solve time | MC cycles | Newton / FIRE it. | CG it. |\n"
                "|---|---|---|---|---|---|---|\n")
        for d, rows in studies:
            fs = fits(rows)
            f.write(f"| {name_of(d, rows)} ({time_unit(rows)}) | {', '.join(str(r['bricks']) for r in rows)} | "
                    f"{', '.join(f'{r['solve']:.1f}' for r in rows)} | {exponent(fs['solve'])} | "
                    f"{exponent(fs['cycles'])} | {exponent(fs['polish_iterations'])} | "
                    f"{exponent(fs['cg_iterations'])} |\n")
        f.write("\n(least-squares exponents in log-log over each study's sizes; `-`: not used by that method; "
                f"studies: {', '.join(d for d, _ in studies)})\n")
    print(open(os.path.join(out, "scaling_methods.md")).read())
    plt = pyplot()
    if plt is None:
        return
    fig, ax = plt.subplots(figsize=(7, 5))
    for k, (d, rows) in enumerate(studies):
        N = [r["bricks"] for r in rows]
        fs = fits(rows)
        label = name_of(d, rows) + f" [{time_unit(rows)}]" + (f" (N^{fs['solve'][0]:.2f})" if fs["solve"] else "")
        ax.loglog(N, [r["solve"] for r in rows], "o-", color=f"C{k}", label=label)
    ax.set_xlabel("bricks")
    ax.set_ylabel("solve seconds (CPU s on 1 thread; wall s where a study ran on more)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title("Time to the same final displacement against specimen size, by relaxation", fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "scaling_methods.png"), dpi=120)


def pyplot():
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        return plt
    except ImportError:
        return None


if __name__ == "__main__":
    if len(sys.argv) >= 3 and sys.argv[1] == "--compare":
        compare(sys.argv[2], sys.argv[3:])
    elif len(sys.argv) == 2:
        single(sys.argv[1])
    else:
        sys.exit(__doc__)
