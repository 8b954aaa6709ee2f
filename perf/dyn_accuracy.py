#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""The dynamics' speed-versus-accuracy front (docs/methods.md "Accuracy where it matters").

On the README BIE deck (inputs/dynamic_bie.toml: stiff bricks, r = 500, Table 4.2's alpha_d),
UE, BE and BIE each run at fractions of their own estimated critical step (and BIE at the deck's
40 ns) and are compared with a converged BE reference on what a fracture study reads: the peak
reaction, its time, the time of the first rupture and the crack-tip speed. The reference's step
is halved from half BE's critical step until all four move by less than 0.1 % (the times
relative to themselves). Rows every `sample` seconds of simulated time, so the peak is resolved.

Crack-tip speed: the series' crack_extension (fracture/crack.hpp) is read at the first times it
reaches 25 % and 75 % of the reference's final extension (linear between rows); the speed is the
extension between those levels over the time between them, the mean speed of the crack's middle
half.

  dyn_accuracy.py NACRE OUT_DIR [--sample 1e-8] [--no-ue] [--chart-only]

Writes OUT_DIR/accuracy.csv, accuracy.md and accuracy.png (error against wall time per method
and step). Every run must end "done" with closed books; the script exits 1 otherwise.
"""
import csv
import math
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "python"))
from nacre import Run, read_json  # noqa: E402  (the reader of nacre's outputs, python/nacre)


def write_deck(out, name, method, dt, sample, end_time=None, every=None):
    lines = []
    for line in open(os.path.join(ROOT, "inputs", "dynamic_bie.toml")):
        k = line.split("=")[0].strip()
        if k in ("dt", "dt_fraction", "csv_interval", "dump_interval") or (end_time and k == "end_time"):
            continue
        if k == "bie_solve" and method != "bie":
            continue
        if k == "method":
            line = f'method = "{method}"\n'
        if k == "directory":
            line = f'directory = "{os.path.join(out, name)}"\n'
        lines.append(line)
        if line.strip() == "[dynamics]":
            every = every or max(1, round(sample / dt))
            lines.append(f"dt = {dt!r}\ncsv_interval = {every}\ndump_interval = 0\n")
            if end_time:
                lines.append(f"end_time = {end_time!r}\n")
    deck = os.path.join(out, name + ".toml")
    open(deck, "w").write("".join(lines))
    return deck


def run(exe, out, name, method, dt, sample, end_time=None, fraction=None, timed=True):
    deck = write_deck(out, name, method, dt, sample, end_time)
    p = subprocess.run([exe, deck, "--overwrite", "-q"], capture_output=True, text=True)
    d = os.path.join(out, name)
    # the wall time of a production run: the same deck with a row (and its stability check)
    # every 100 steps, as the README decks; the finely sampled run checks at every row, which
    # costs each method in proportion to its rows per step, not to its work
    seconds = math.nan
    if timed:
        tdeck = write_deck(out, name + "_timing", method, dt, sample, end_time, every=100)
        subprocess.run([exe, tdeck, "--overwrite", "-q"], capture_output=True, text=True)
        seconds = read_json(os.path.join(out, name + "_timing", "summary.json"))["seconds"]
    run_ = Run(d)
    summ, rows = run_.summary, run_.rows()
    F = [float(r["reaction"]) for r in rows]
    t = [float(r["time"]) for r in rows]
    k = max(range(len(F)), key=lambda i: F[i])
    first = next((float(r["time"]) for r in rows if int(r["ruptured"]) > 0), math.nan)
    worst = max((abs(float(r["balance_residual"])) for r in rows if int(r["step"]) >= 32), default=0.0)
    ext = [float(r["crack_extension"]) for r in rows]
    return dict(run=name, method=method, dt=dt, dt_fraction=fraction, exit=p.returncode, status=summ["status"],
                steps=summ["steps"], seconds=seconds, seconds_sampled=summ["seconds"], seconds_per_step=summ["seconds_per_step"], peak=F[k],
                t_peak=t[k], first_rupture=first, ruptured=summ["ruptured"], worst_balance=worst,
                critical_estimate=summ["step_bound_start"], final_extension=ext[-1], _t=t, _ext=ext,
                why=(p.stderr.strip().splitlines() or [""])[0])


def level_time(r, level):
    """First time the crack extension reaches `level` (linear between rows), NaN if never."""
    t, e = r["_t"], r["_ext"]
    for i in range(1, len(e)):
        if e[i] >= level:
            if e[i - 1] >= level:
                return t[i - 1]
            return t[i - 1] + (level - e[i - 1]) / (e[i] - e[i - 1]) * (t[i] - t[i - 1])
    return math.nan


def crack_speed(r, L):
    t25, t75 = level_time(r, 0.25 * L), level_time(r, 0.75 * L)
    return 0.5 * L / (t75 - t25) if t75 > t25 else math.nan


def say(r):
    print(f"{r['run']:16s} dt {r['dt']:.3g} peak {r['peak']:.5f} N at {r['t_peak'] * 1e6:.3f} us, first rupture "
          f"{r['first_rupture'] * 1e6:.3f} us, extension {r['final_extension']:.3f} mm, {r['seconds']:.1f} s, "
          f"status {r['status']}", flush=True)


def chart(runs, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    colours = {"ue": "tab:green", "be": "tab:blue", "bie": "tab:red"}
    floor = 1e-4  # % : errors below it are drawn on it
    for ax, key, title in ((axes[0], "peak_error", "peak reaction"), (axes[1], "crack_speed_error", "crack-tip speed")):
        for m in ("ue", "be", "bie"):
            # the reference's halvings are runs of the BE fractions again: drawn once, as those
            rs = sorted((r for r in runs if r["method"] == m and not r["run"].startswith("ref_")),
                        key=lambda r: r["seconds"])
            if not rs:
                continue
            x = [r["seconds"] for r in rs]
            y = [max(floor, 100 * abs(r[key])) if math.isfinite(r[key]) else math.nan for r in rs]
            ax.plot(x, y, "o-", color=colours[m], label=m.upper())
            for xi, yi, r in zip(x, y, rs):
                lab = f"{r['dt_fraction']:g}" if r["dt_fraction"] else f"{r['dt'] * 1e9:.0f} ns"
                ax.annotate(lab, (xi, yi), textcoords="offset points", xytext=(4, 4), fontsize=7)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("wall time of the run (rows every 100 steps), s, 2 cores")
        ax.set_ylabel(f"|error| of the {title}, % (floor {floor:g} %)")
        ax.set_title(f"{title} against the converged BE reference")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(title="labels: dt / critical")
    fig.tight_layout()
    tmp = path + ".tmp.png"
    fig.savefig(tmp, dpi=110)
    os.replace(tmp, path)


def main():
    if len(sys.argv) < 3:
        print(__doc__)
        return 2
    exe, out = sys.argv[1], sys.argv[2]
    if "--chart-only" in sys.argv:  # redraw accuracy.png from accuracy.csv
        def num(v):
            try:
                return float(v)
            except ValueError:
                return None if v in ("", "None") else v
        runs = [{k: (v if k in ("run", "method", "status", "why") else num(v)) for k, v in r.items()}
                for r in csv.DictReader(open(os.path.join(out, "accuracy.csv")))]
        chart(runs, os.path.join(out, "accuracy.png"))
        return 0
    sample = float(sys.argv[sys.argv.index("--sample") + 1]) if "--sample" in sys.argv else 1e-8
    with_ue = "--no-ue" not in sys.argv
    os.makedirs(out, exist_ok=True)
    # each method's estimated critical step on this deck (a 2 us probe: only its summary is read)
    crit = {m: run(exe, out, f"probe_{m}", m, 1e-9, 1e-6, end_time=2e-6, timed=False)["critical_estimate"]
            for m in (("ue", "be", "bie") if with_ue else ("be", "bie"))}
    print("estimated critical steps:", {m: f"{h:.4g} s" for m, h in crit.items()}, flush=True)
    runs = []
    # BE reference: from half the critical step, halved until peak, t_peak, first rupture and the
    # crack speed all move < 0.1 %
    h = 0.5 * crit["be"]
    ref = None
    for k in range(5):
        r = run(exe, out, f"ref_be_{h:.3g}", "be", h, sample)
        say(r)
        if ref is not None:
            L = r["final_extension"]
            moved = [abs(r["peak"] / ref["peak"] - 1), abs(r["t_peak"] / ref["t_peak"] - 1),
                     abs(r["first_rupture"] / ref["first_rupture"] - 1),
                     abs(crack_speed(r, L) / crack_speed(ref, L) - 1)]
            print(f"  moved on halving: peak {moved[0]:.2g}, t_peak {moved[1]:.2g}, first rupture {moved[2]:.2g}, "
                  f"crack speed {moved[3]:.2g}", flush=True)
            runs.append(ref)
            if max(moved) < 1e-3:
                ref = r
                break
        ref = r
        h *= 0.5
    runs.append(ref)
    fractions = {"be": (0.9, 0.5, 0.25), "bie": (0.9, 0.5, 0.25), "ue": (0.9, 0.5)}
    for m in crit:
        for f in fractions[m]:
            r = run(exe, out, f"{m}_{f:g}", m, f * crit[m], sample, fraction=f)
            say(r)
            runs.append(r)
    r = run(exe, out, "bie_deck_40ns", "bie", 4e-8, sample)  # the README deck's step
    say(r)
    runs.append(r)
    L = ref["final_extension"]
    v_ref = crack_speed(ref, L)
    rayleigh = read_json(os.path.join(out, ref["run"], "summary.json"))["crack"]["rayleigh_speed"]
    for r in runs:
        r["reference"] = r is ref
        r["peak_error"] = (r["peak"] - ref["peak"]) / ref["peak"]
        r["t_peak_error"] = r["t_peak"] - ref["t_peak"]
        r["first_rupture_error"] = r["first_rupture"] - ref["first_rupture"]
        r["crack_speed"] = crack_speed(r, L)
        r["crack_speed_error"] = (r["crack_speed"] - v_ref) / v_ref
    fields = [k for k in runs[0] if not k.startswith("_")]
    with open(os.path.join(out, "accuracy.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields, extrasaction="ignore")
        w.writeheader()
        w.writerows(runs)
    with open(os.path.join(out, "accuracy.md"), "w") as f:
        f.write(f"Reference: {ref['run']} (peak, its time, the first rupture and the crack speed moved < 0.1 % on "
                f"the last halving). Rows every {sample:g} s. Crack speed: mean over the middle half of the "
                f"reference's final extension {L:.3f} mm; reference {v_ref / 1e3:.1f} m/s = "
                f"{v_ref / rayleigh:.3f} of the bricks' Rayleigh speed {rayleigh / 1e3:.0f} m/s.\n\n")
        f.write("| run | dt s | dt / critical | steps | wall s | peak N | peak error | t_peak us | first rupture us "
                "| crack speed m/s | speed error | worst balance | status |\n")
        f.write("|---|---|---|---|---|---|---|---|---|---|---|---|---|\n")
        for r in runs:
            frac = r["dt"] / crit[r["method"]]
            f.write(f"| {r['run']} | {r['dt']:.3g} | {frac:.2f} | {r['steps']} | {r['seconds']:.2f} | {r['peak']:.4f} | "
                    f"{100 * r['peak_error']:+.3f} % | {r['t_peak'] * 1e6:.3f} | {r['first_rupture'] * 1e6:.3f} | "
                    f"{r['crack_speed'] / 1e3:.1f} | {100 * r['crack_speed_error']:+.2f} % | "
                    f"{r['worst_balance']:.2g} | {r['status']} |\n")
    chart(runs, os.path.join(out, "accuracy.png"))
    bad = [r["run"] for r in runs if r["exit"] != 0 or r["status"] != "done"]
    if bad:
        print("NOT DONE:", ", ".join(bad))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
