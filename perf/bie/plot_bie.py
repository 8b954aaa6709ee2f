#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Charts and headline numbers of the issue-8 experiments (perf/bie/run_bie_bench.sh).

usage: plot_bie.py OUTDIR EXPERIMENT   (critical|timing|speedup|speedup_damped|accuracy|accuracy_damped|fail|memory)
Reads OUTDIR/<experiment>*.csv, writes OUTDIR/<experiment>.png and OUTDIR/<experiment>.json.
"""
import csv
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

COL = {"ue": "tab:red", "be": "tab:blue", "bie": "tab:green", "bie_split": "tab:purple"}


def rows(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def fit_order(hs, es):
    pts = [(math.log(h), math.log(e)) for h, e in zip(hs, es) if e > 0 and math.isfinite(e)]
    n = len(pts)
    if n < 2:
        return float("nan")
    sx = sum(p[0] for p in pts); sy = sum(p[1] for p in pts)
    sxx = sum(p[0] ** 2 for p in pts); sxy = sum(p[0] * p[1] for p in pts)
    return (n * sxy - sx * sy) / (n * sxx - sx * sx)


def save(out, name, fig, data):
    fig.tight_layout()
    fig.savefig(os.path.join(out, name + ".png"), dpi=120)
    with open(os.path.join(out, name + ".json"), "w") as f:
        json.dump(data, f, indent=1, sort_keys=True)
    print(json.dumps(data, indent=1, sort_keys=True))


def critical(out):
    r = rows(os.path.join(out, "critical.csv"))
    fig, ax = plt.subplots(figsize=(6, 4))
    data = {}
    for m in ("ue", "be", "bie"):
        rs = [x for x in r if x["method"] == m]
        x = [float(a["ratio"]) for a in rs]; y = [float(a["critical_step_s"]) for a in rs]
        ax.loglog(x, y, "o-", color=COL[m], label=m.upper())
        data[m] = dict(zip([str(int(v)) for v in x], y))
    data["bie_over_be"] = {k: data["bie"][k] / data["be"][k] for k in data["be"]}
    data["be_over_ue"] = {k: data["be"][k] / data["ue"][k] for k in data["be"]}
    data["bricks"] = int(r[0]["bricks"])
    ax.set_xlabel("stiffness ratio E / (k L)"); ax.set_ylabel("critical step (s)")
    ax.set_title("Critical step (Fig. 4.6/4.7), %d bricks" % data["bricks"]); ax.legend(); ax.grid(True, which="both", alpha=.3)
    save(out, "critical", fig, data)


def timing(out):
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(12, 4.5))
    data = {}
    for nt, ls in (("1t", "--"), ("2t", "-")):
        p = os.path.join(out, "timing_%s.csv" % nt)
        if not os.path.exists(p):
            continue
        r = rows(p)
        labels = sorted(set(x["label"] for x in r))
        for lab in labels:
            rs = [x for x in r if x["label"] == lab]
            b = [int(x["bricks"]) for x in rs]; t = [float(x["s_per_step"]) * 1e3 for x in rs]
            m = rs[0]["method"]
            ax.loglog(b, t, ls, marker="o", color=COL[m] if lab in ("ue", "be", "bie_shared_gemm") else None,
                      label="%s %s" % (lab, nt), ms=3)
            data.setdefault(nt, {})[lab] = {"bricks": b, "ms_per_step": t,
                                            "us_per_step_per_1k_bricks": [1e3 * tt / bb * 1e3 / 1e3 for tt, bb in zip(t, b)]}
            if m == "bie":
                g = [float(x["solve_gflops"]) for x in rs]; s = [float(x["solve_s_per_apply"]) * 1e3 for x in rs]
                ax2.semilogx(b, g, ls, marker="o", label="%s %s" % (lab, nt), ms=3)
                data[nt][lab]["solve_ms_per_apply"] = s
                data[nt][lab]["solve_gflops"] = g
        data.setdefault("triad_gbs", {})[nt] = float(r[0]["triad_gbs"])
    ax.set_xlabel("bricks"); ax.set_ylabel("ms per step"); ax.set_title("Time per step (Fig. 4.8), ratio 500")
    ax.legend(fontsize=6, ncol=2); ax.grid(True, which="both", alpha=.3)
    ax2.set_xlabel("bricks"); ax2.set_ylabel("GFLOP/s of the J^-1 apply alone"); ax2.set_title("J^-1 apply variants")
    ax2.legend(fontsize=6, ncol=2); ax2.grid(True, which="both", alpha=.3)
    save(out, "timing", fig, data)


def speedup(out, name="speedup"):
    r = rows(os.path.join(out, name + ".csv"))
    fig, ax = plt.subplots(figsize=(6, 4))
    data = {}
    damped = float(r[0].get("beta_d", 0) or 0) > 0
    for m in [m for m in ("be", "bie", "bie_split") if any(x["method"] == m for x in r)]:
        rs = [x for x in r if x["method"] == m]
        x = [float(a["ratio"]) for a in rs]; y = [float(a["speedup_vs_ue"]) for a in rs]
        ax.loglog(x, y, "o-", color=COL[m], label=m.upper() + " vs UE")
        data[m + "_vs_ue"] = dict(zip([str(int(v)) for v in x], y))
        if m != "be":
            data[m + "_vs_be"] = {str(int(float(a["ratio"]))): float(a["speedup_vs_be"]) for a in rs}
    data["wall_s"] = {"%s_%d" % (a["method"], int(float(a["ratio"]))): float(a["wall_s"]) for a in r}
    data["steps"] = {"%s_%d" % (a["method"], int(float(a["ratio"]))): int(a["steps"]) for a in r}
    data["stable"] = all(a["stable"] == "1" for a in r)
    data["bricks"] = int(r[0]["bricks"])
    ax.axhline(100, color="gray", ls=":"); ax.axhline(15, color="gray", ls=":")
    ax.set_xlabel("stiffness ratio"); ax.set_ylabel("speed-up vs UE (same simulated time)")
    ax.set_title("Total speed-up (Fig. 4.9), %d bricks%s" % (data["bricks"], ", Table 4.2 damping" if damped else ""))
    ax.legend(); ax.grid(True, which="both", alpha=.3)
    save(out, name, fig, data)


def speedup_damped(out):
    speedup(out, "speedup_damped")


def pareto(points):
    pts = sorted(points)
    front, best = [], float("inf")
    for t, e in pts:
        if e < best:
            front.append((t, e)); best = e
    return front


def accuracy(out, name="accuracy"):
    r = rows(os.path.join(out, name + ".csv"))
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(12, 4.5))
    data = {"order": {}, "bricks": int(r[0]["bricks"])}
    damped = float(r[0].get("beta_d", 0) or 0) > 0
    if damped:
        data["alpha_d"], data["beta_d"] = float(r[0]["alpha_d"]), float(r[0]["beta_d"])
    allpts = []
    for m in [m for m in ("ue", "be", "bie", "bie_split") if any(x["method"] == m for x in r)]:
        rs = [x for x in r if x["method"] == m and x["stable"] == "1"]
        data.setdefault("unstable", {})[m] = [float(x["step_over_critical"]) for x in r if x["method"] == m and x["stable"] != "1"]
        h = [float(a["step_s"]) for a in rs]; e = [float(a["err_own_ref"]) for a in rs]
        ax.loglog(h, e, "o-", color=COL[m], label=m.upper())
        # fitted order over the three smallest steps (the asymptotic range)
        data["order"][m] = fit_order(h[-3:], e[-3:])
        data.setdefault("order_all_steps", {})[m] = fit_order(h, e)
        data.setdefault("errors", {})[m] = dict(zip(["%.4g" % v for v in h], e))
        t = [float(a["wall_s"]) for a in rs]; eb = [float(a["err_bolted_ref"]) for a in rs]
        ax2.loglog(t, eb, "o", color=COL[m], label=m.upper())
        allpts += [(tt, ee) for tt, ee in zip(t, eb) if ee > 0]
    front = pareto(allpts)
    ax2.loglog([p[0] for p in front], [p[1] for p in front], "k--", lw=1, label="Pareto front")
    data["pareto"] = front
    ax.set_xlabel("step (s)"); ax.set_ylabel("strain-energy history error (vs own tiny-step reference)")
    ax.set_title("Order: " + ", ".join("%s %.2f" % (k.upper(), v) for k, v in data["order"].items()))
    ax.legend(); ax.grid(True, which="both", alpha=.3)
    ax2.set_xlabel("wall time (s)"); ax2.set_ylabel("strain-energy history error (vs bolted reference)")
    ax2.set_title("Accuracy against time, ratio 500, %d bricks%s" % (data["bricks"], ", Table 4.2 damping" if damped else ""))
    ax2.legend(); ax2.grid(True, which="both", alpha=.3)
    save(out, name, fig, data)


def accuracy_damped(out):
    accuracy(out, "accuracy_damped")


def fail(out):
    r = rows(os.path.join(out, "fail.csv"))
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    data = {}
    for ratio in sorted(set(float(x["ratio"]) for x in r)):
        rs = [x for x in r if float(x["ratio"]) == ratio]
        f = [float(a["step_over_be_critical"]) for a in rs]
        e = [float(a["err_bolted_ref"]) if a["stable"] == "1" else float("nan") for a in rs]
        nr = [float(a["newton_residual"]) for a in rs]
        line, = ax.loglog(f, e, "o-", label="error, ratio %g" % ratio)
        ax.loglog(f, nr, "x:", color=line.get_color(), label="Newton residual, ratio %g" % ratio)
        unstable = [ff for ff, a in zip(f, rs) if a["stable"] != "1"]
        inacc = [ff for ff, ee in zip(f, e) if not (ee < 0.05)]
        data[str(int(ratio))] = {"first_unstable_over_be_crit": min(unstable) if unstable else None,
                                 "first_error_above_5pct_over_be_crit": min(inacc) if inacc else None,
                                 "bie_critical_over_be_crit": float(rs[0]["step_over_be_critical"]) / float(rs[0]["step_over_bie_critical"])}
        for ff in unstable:
            ax.axvline(ff, color=line.get_color(), alpha=.15)
    ax.axhline(0.05, color="gray", ls=":")
    ax.set_xlabel("step / BE critical step"); ax.set_ylabel("energy-history error / Newton residual")
    ax.set_title("Where BIE fails (shaded: unstable)"); ax.legend(fontsize=7); ax.grid(True, which="both", alpha=.3)
    save(out, "fail", fig, data)


def memory(out):
    r = rows(os.path.join(out, "memory.csv"))
    fig, ax = plt.subplots(figsize=(6, 4))
    data = {}
    for m in ("ue", "be", "bie"):
        for sh, ls in (("1", "-"), ("0", "--")):
            rs = [x for x in r if x["method"] == m and x["shared"] == sh]
            b = [int(a["bricks"]) for a in rs]; y = [float(a["bytes_per_brick"]) for a in rs]
            ax.semilogx(b, y, ls, marker="o", color=COL[m], label="%s %s" % (m.upper(), "shared" if sh == "1" else "per element"))
            data["%s_%s" % (m, "shared" if sh == "1" else "per_element")] = dict(zip([str(v) for v in b], y))
    ax.axhline(1024, color="gray", ls=":")
    ax.set_xlabel("bricks"); ax.set_ylabel("bytes per brick"); ax.set_title("Memory (Fig. 4.11)")
    ax.legend(fontsize=7); ax.grid(True, which="both", alpha=.3)
    save(out, "memory", fig, data)


if __name__ == "__main__":
    globals()[sys.argv[2]](sys.argv[1])
