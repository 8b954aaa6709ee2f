# SPDX-License-Identifier: BSD-3-Clause
"""python3 -m nacre DIR [DIR ...]: what nacre output directories hold (a run of either family,
a sweep, a bench)."""
import sys

from .results import Bench, Run, Sweep, kind


def _rows(t):
    return 0 if not t else len(next(iter(t.values())))


def describe_run(run, out=print):
    t = run.table()
    out(f"{run.directory}: solver {run.solver}, status {run.summary.get('status', 'done' if run.summary else '?')}, "
        f"{_rows(t)} rows of {run.table_name}, dumps at steps {run.steps()}")
    if t is not None:
        out("columns: " + ", ".join(k + (" (text)" if v.dtype.kind == "U" else "") for k, v in t.items()))
    r = run.r_curve()
    if r is not None:
        ratio = run.toughening_ratio
        out(f"r_curve.csv: {_rows(r)} points, toughening ratio {'n/a' if ratio is None else f'{ratio:.4g}'}")
    m = run.mesh()
    if m:
        out("mesh.h5: " + ", ".join(f"{k} {v.shape}" for k, v in m.items()))
    d = run.dump()
    if d:
        out(f"last dump (attributes {d.attrs}): " + ", ".join(f"{k} {v.shape}" for k, v in d.items()))


def describe_sweep(sw, out=print):
    out(f"{sw.directory}: sweep of {sw.deck} over {', '.join(sw.keys)}: {len(sw)} runs")
    for e in sw.runs:
        vals = ", ".join(f"{k}={v}" for k, v in e.values.items())
        if e.has_outputs():
            run = e.run()
            t = run.table()
            what = f"solver {run.solver}, status {run.summary.get('status', 'done')}, {_rows(t)} rows"
        else:
            what = "no outputs"
        out(f"  {e.name}: {vals}; exit {e.exit} ({e.how}); {what}")
    t = sw.table()
    out(f"sweep.csv: {_rows(t)} rows; columns {', '.join(t)}" if t is not None else "sweep.csv: none")


def describe_bench(b, out=print):
    j = b.json
    out(f"{b.directory}: bench of {j.get('deck')} ({b.solver}, {j.get('bricks')} bricks), "
        f"{j.get('repeats')} repeats of {j.get('units_per_repeat')} {b.unit}s; agreement {j.get('agreement')}")
    for name in b.backends:
        e = b.backend(name)
        out(f"  {name}: {e.get('threads')} threads, {e.get('seconds_per_unit', float('nan')):.4g} s per {b.unit}, "
            f"speed-up {e.get('speedup_over_reference', float('nan')):.3g}, phases {', '.join(e.get('phases', {}))}")
    t = b.table()
    out(f"bench.csv: {_rows(t)} rows; columns {', '.join(t)}" if t is not None else "bench.csv: none")


def main(argv=None):
    args = sys.argv[1:] if argv is None else argv
    if not args or any(a in ("-h", "--help") for a in args):
        print(__doc__.strip(), file=sys.stdout if args else sys.stderr)
        return 0 if args else 2
    status = 0
    for d in args:
        try:
            k = kind(d)
            if k == "sweep":
                describe_sweep(Sweep(d))
            elif k == "bench":
                describe_bench(Bench(d))
            else:
                describe_run(Run(d))
        except (OSError, ValueError) as e:
            print(f"nacre: error: {e}", file=sys.stderr)
            status = 1
    return status


if __name__ == "__main__":
    sys.exit(main())
