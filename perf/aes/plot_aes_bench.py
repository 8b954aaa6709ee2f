#!/usr/bin/env python3
"""Chart, JSON and summary of perf/aes/run_aes_bench.sh: plot_aes_bench.py OUTDIR."""
import csv
import json
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    out = Path(sys.argv[1])
    rows = list(csv.DictReader(open(out / "aes_bench.csv")))
    for r in rows:
        r["threads"] = int(r["threads"])
        r["size_bytes"] = int(r["size_bytes"])
        r["rate"] = float(r["rate"])
        r["seconds"] = float(r["seconds"])
        r["count"] = int(r["count"])
    machine = {}
    mt = out / "machine.txt"
    if mt.exists():
        for line in mt.read_text().splitlines():
            k, _, v = line.partition(":")
            machine[k.strip()] = v.strip()

    cipher = [r for r in rows if r["kind"] == "cipher"]
    rng = [r for r in rows if r["kind"] == "rng"]
    series = {}
    for r in cipher:
        series.setdefault((r["impl"], r["threads"]), []).append(r)

    # Summary: median over sizes >= 1 MiB, total and per core.
    summary = []
    for (impl, t), rs in sorted(series.items()):
        big = sorted(x["rate"] for x in rs if x["size_bytes"] >= (1 << 20)) or sorted(x["rate"] for x in rs)
        med = big[len(big) // 2]
        summary.append({"impl": impl, "threads": t, "gbit_s": med, "gbit_s_per_core": med / t,
                        "peak_gbit_s": max(x["rate"] for x in rs)})
    rng_summary = [{"impl": r["impl"], "threads": r["threads"], "numbers_per_s": r["rate"]} for r in rng]
    json.dump({"machine": machine, "cipher": cipher, "rng": rng, "cipher_summary": summary,
               "rng_summary": rng_summary}, open(out / "aes_bench.json", "w"), indent=1)

    md = ["| AES-128-ECB | threads | Gbit/s (median, >= 1 MiB) | Gbit/s per core | peak Gbit/s |",
          "|---|---|---|---|---|"]
    for s in summary:
        md.append(f"| {s['impl']} | {s['threads']} | {s['gbit_s']:.2f} | {s['gbit_s_per_core']:.2f} | {s['peak_gbit_s']:.2f} |")
    md += ["", "| generator | threads | random doubles / s |", "|---|---|---|"]
    for s in rng_summary:
        md.append(f"| {s['impl']} | {s['threads']} | {s['numbers_per_s']:.3g} |")
    md += ["", "machine: " + ", ".join(f"{k}: {v}" for k, v in machine.items())]
    (out / "aes_bench.md").write_text("\n".join(md) + "\n")
    print("\n".join(md))

    fig, (a1, a2) = plt.subplots(1, 2, figsize=(13, 5), gridspec_kw={"width_ratios": [3, 2]})
    styles = {"nacre": "o-", "openssl-aesni": "s--", "openssl-no-aesni": "^--"}
    for (impl, t), rs in sorted(series.items()):
        rs = sorted(rs, key=lambda x: x["size_bytes"])
        a1.plot([x["size_bytes"] for x in rs], [x["rate"] / t for x in rs], styles.get(impl, "x-"),
                label=f"{impl}, {t} thread{'s' if t > 1 else ''}")
    a1.set_xscale("log", base=2)
    a1.set_yscale("log")
    a1.set_xlabel("buffer size (bytes)")
    a1.set_ylabel("Gbit/s per core")
    a1.set_title("AES-128-ECB throughput per core")
    a1.grid(True, which="both", alpha=0.3)
    a1.legend(fontsize=8)
    impls = sorted({r["impl"] for r in rng})
    threads = sorted({r["threads"] for r in rng})
    w = 0.8 / max(1, len(threads))
    for k, t in enumerate(threads):
        vals = [next((r["rate"] for r in rng if r["impl"] == i and r["threads"] == t), 0) for i in impls]
        a2.bar([x + k * w for x in range(len(impls))], [v / 1e6 for v in vals], w,
               label=f"{t} thread{'s' if t > 1 else ''}")
    a2.set_xticks([x + w * (len(threads) - 1) / 2 for x in range(len(impls))])
    a2.set_xticklabels(impls, rotation=20, fontsize=8)
    a2.set_ylabel("million random doubles / s")
    a2.set_title("Random numbers (4 per stream and draw)")
    a2.legend(fontsize=8)
    a2.grid(True, axis="y", alpha=0.3)
    fig.suptitle(f"nacre AES benchmark — {machine.get('cpu', '')}", fontsize=10)
    fig.tight_layout()
    fig.savefig(out / "aes_bench.png", dpi=120)


if __name__ == "__main__":
    main()
