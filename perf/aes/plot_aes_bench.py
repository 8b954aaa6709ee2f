#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Chart, JSON and summary of perf/aes/run_aes_bench.sh: plot_aes_bench.py OUTDIR.

Two views of the cipher rows: the size sweep (kind cipher; median over buffers >= 1 MiB) and the
interleaved comparison (kind compare; per-round ratios nacre / OpenSSL, whose median is the
headline, with the range over rounds). Per-core rates are per CPU second of the process."""
import csv
import json
import statistics
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# The bitsliced OpenSSL reference (AES-NI masked off) that the target is stated against.
REF = "openssl-no-aesni-ctr"


def main():
    out = Path(sys.argv[1])
    rows = list(csv.DictReader(open(out / "aes_bench.csv")))
    for r in rows:
        r["threads"] = int(r["threads"])
        r["size_bytes"] = int(r["size_bytes"])
        r["count"] = int(r["count"])
        r["rep"] = int(r["rep"])
        for k in ("seconds", "cpu_seconds", "rate", "rate_per_cpu"):
            r[k] = float(r[k])
    machine = {}
    mt = out / "machine.txt"
    if mt.exists():
        for line in mt.read_text().splitlines():
            k, _, v = line.partition(":")
            machine[k.strip()] = v.strip()

    cipher = [r for r in rows if r["kind"] == "cipher"]
    compare = [r for r in rows if r["kind"] == "compare"]
    rng = [r for r in rows if r["kind"] == "rng"]

    # Size sweep: median over sizes >= 1 MiB.
    series = {}
    for r in cipher:
        series.setdefault((r["impl"], r["threads"]), []).append(r)
    sweep = []
    for (impl, t), rs in sorted(series.items()):
        big = [x for x in rs if x["size_bytes"] >= (1 << 20)] or rs
        sweep.append({"impl": impl, "threads": t,
                      "gbit_s": statistics.median(x["rate"] for x in big),
                      "gbit_s_per_cpu_s": statistics.median(x["rate_per_cpu"] for x in big),
                      "peak_gbit_s_per_cpu_s": max(x["rate_per_cpu"] for x in rs)})

    # Interleaved comparison: per implementation, per round; ratios within a round.
    reps = sorted({r["rep"] for r in compare})
    impls = sorted({(r["impl"], r["threads"]) for r in compare})
    by = {(r["impl"], r["threads"], r["rep"]): r for r in compare}
    comp = []
    for impl, t in impls:
        rs = [by[(impl, t, k)] for k in reps if (impl, t, k) in by]
        per_core = [x["rate_per_cpu"] for x in rs]  # per CPU second = per core
        comp.append({"impl": impl, "threads": t, "rounds": len(rs),
                     "gbit_s": statistics.median(x["rate"] for x in rs),
                     "gbit_s_per_cpu_s": statistics.median(per_core),
                     "min_per_cpu_s": min(per_core), "max_per_cpu_s": max(per_core)})
    ratios = []
    for impl, t in impls:
        if not impl.startswith("nacre"):
            continue
        for ref in sorted({i for i, _ in impls if not i.startswith("nacre")}):
            vals = [by[(impl, t, k)]["rate_per_cpu"] / by[(ref, 1, k)]["rate_per_cpu"]
                    for k in reps if (impl, t, k) in by and (ref, 1, k) in by]
            if vals:
                ratios.append({"nacre": impl, "threads": t, "vs": ref,
                               "median": statistics.median(vals), "min": min(vals), "max": max(vals),
                               "rounds": len(vals)})

    rng_summary = [{"impl": r["impl"], "threads": r["threads"], "numbers_per_s": r["rate"],
                    "numbers_per_cpu_s": r["rate_per_cpu"]} for r in rng]
    json.dump({"machine": machine, "cipher": cipher, "compare": compare, "rng": rng,
               "sweep_summary": sweep, "compare_summary": comp, "ratios": ratios,
               "rng_summary": rng_summary}, open(out / "aes_bench.json", "w"), indent=1)

    md = [f"Interleaved comparison: {len(reps)} rounds, each implementation once per round "
          "(8 MiB buffer, in-process EVP; `speed-*` = `openssl speed -evp`, 16 KiB blocks, "
          "wall time). Gbit/s per core = per CPU second of the process.", "",
          "| AES-128 | threads | Gbit/s (median) | Gbit/s per core (median) | per core, min - max |",
          "|---|---|---|---|---|"]
    for s in comp:
        md.append(f"| {s['impl']} | {s['threads']} | {s['gbit_s']:.2f} | "
                  f"{s['gbit_s_per_cpu_s']:.2f} | {s['min_per_cpu_s']:.2f} - {s['max_per_cpu_s']:.2f} |")
    md += ["", "| ratio (per core, same round) | median | min - max | rounds |", "|---|---|---|---|"]
    for q in ratios:
        md.append(f"| {q['nacre']} ({q['threads']} thr) / {q['vs']} | {q['median']:.2f} | "
                  f"{q['min']:.2f} - {q['max']:.2f} | {q['rounds']} |")
    md += ["", "Size sweep (median over buffers >= 1 MiB):", "",
           "| AES-128 | threads | Gbit/s | Gbit/s per core (CPU s) | peak per core |", "|---|---|---|---|---|"]
    for s in sweep:
        md.append(f"| {s['impl']} | {s['threads']} | {s['gbit_s']:.2f} | "
                  f"{s['gbit_s_per_cpu_s']:.2f} | {s['peak_gbit_s_per_cpu_s']:.2f} |")
    md += ["", "| generator | threads | random doubles / s (wall) | per CPU second |", "|---|---|---|---|"]
    for s in rng_summary:
        md.append(f"| {s['impl']} | {s['threads']} | {s['numbers_per_s']:.3g} | {s['numbers_per_cpu_s']:.3g} |")
    core_csv = out / "aes_core.csv"
    if core_csv.exists():
        core = list(csv.DictReader(open(core_csv)))
        names = list(dict.fromkeys(r["what"] for r in core))
        md += ["", "Bare cipher core, one thread, 512 blocks per chunk, L2-resident (nacre_aes_core_bench):", "",
               "| what | ns per 512 blocks (median) | Gbit/s per CPU second (median, min - max) |", "|---|---|---|"]
        for n in names:
            rs = [r for r in core if r["what"] == n]
            g = [float(r["gbit_per_cpu_s"]) for r in rs]
            md.append(f"| {n} | {statistics.median(float(r['ns_per_chunk']) for r in rs):.0f} | "
                      f"{statistics.median(g):.2f} ({min(g):.2f} - {max(g):.2f}) |")
    md += ["", "machine: " + "; ".join(f"{k}: {v}" for k, v in machine.items())]
    (out / "aes_bench.md").write_text("\n".join(md) + "\n")
    print("\n".join(md))

    fig, (a1, a3, a2) = plt.subplots(1, 3, figsize=(17, 5), gridspec_kw={"width_ratios": [3, 2, 2]})
    styles = {"nacre": "o-", "openssl-aesni-ecb": "s--", "openssl-no-aesni-ecb": "^--",
              "openssl-no-aesni-ctr": "v--"}
    for (impl, t), rs in sorted(series.items()):
        rs = sorted(rs, key=lambda x: x["size_bytes"])
        a1.plot([x["size_bytes"] for x in rs], [x["rate_per_cpu"] for x in rs],
                styles.get(impl, "x-"), label=f"{impl}, {t} thread{'s' if t > 1 else ''}")
    a1.set_xscale("log", base=2)
    a1.set_yscale("log")
    a1.set_xlabel("buffer size (bytes)")
    a1.set_ylabel("Gbit/s per core (per CPU second)")
    a1.set_title("AES-128 throughput per core, size sweep")
    a1.grid(True, which="both", alpha=0.3)
    a1.legend(fontsize=8)
    for impl, t in impls:
        if "aesni-ecb" in impl and "no-" not in impl:
            continue  # AES-NI is 10x off the scale of the bitsliced codes
        ys = [by[(impl, t, k)]["rate_per_cpu"] for k in reps if (impl, t, k) in by]
        a3.plot(reps[:len(ys)], ys, "o-" if impl.startswith("nacre") else "x--",
                label=f"{impl}{' x' + str(t) if t > 1 else ''}")
    a3.set_xlabel("round")
    a3.set_ylabel("Gbit/s per core")
    a3.set_title("interleaved rounds (8 MiB; AES-NI off the scale)")
    a3.grid(True, alpha=0.3)
    a3.legend(fontsize=7)
    rimpls = sorted({r["impl"] for r in rng})
    threads = sorted({r["threads"] for r in rng})
    w = 0.8 / max(1, len(threads))
    for k, t in enumerate(threads):
        vals = [next((r["rate_per_cpu"] for r in rng if r["impl"] == i and r["threads"] == t), 0)
                for i in rimpls]
        a2.bar([x + k * w for x in range(len(rimpls))], [v / 1e6 for v in vals], w,
               label=f"{t} thread{'s' if t > 1 else ''}")
    a2.set_xticks([x + w * (len(threads) - 1) / 2 for x in range(len(rimpls))])
    a2.set_xticklabels(rimpls, rotation=20, fontsize=8)
    a2.set_ylabel("million random doubles per CPU second")
    a2.set_title("Random numbers (4 per stream and draw)")
    a2.legend(fontsize=8)
    a2.grid(True, axis="y", alpha=0.3)
    fig.suptitle(f"nacre AES benchmark — {machine.get('cpu', '')}", fontsize=10)
    fig.tight_layout()
    fig.savefig(out / "aes_bench.png", dpi=120)


if __name__ == "__main__":
    main()
