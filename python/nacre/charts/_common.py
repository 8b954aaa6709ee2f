# SPDX-License-Identifier: BSD-3-Clause
"""What the chart modules share: matplotlib (or the warning that it is missing), the atomic PNG
writer, the R-curve chart of both solver families, warnings."""
import os
import sys

MISSING_MATPLOTLIB = "nacre: warning: matplotlib not found; charts skipped"


def warn(msg):
    print(f"nacre: warning: {msg}", file=sys.stderr)


def pyplot():
    """matplotlib.pyplot, on the Agg backend where nothing imported pyplot before (a script or
    notebook that did keeps its backend); None when matplotlib is not installed."""
    try:
        import matplotlib
        if "matplotlib.pyplot" not in sys.modules:
            matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return None
    return plt


def have_matplotlib():
    """True when matplotlib imports; else the one-line warning on stderr and False (the chart
    module then exits 0: the results are complete without their pictures)."""
    if pyplot() is None:
        print(MISSING_MATPLOTLIB, file=sys.stderr)
        return False
    return True


def save_png(fig, path, **kw):
    """Write the chart to a temporary sibling and rename it: a failure (a full disk) leaves no
    truncated PNG under the final name, and the module exits non-zero."""
    tmp = os.path.join(os.path.dirname(path) or ".", "." + os.path.basename(path) + ".tmp%d" % os.getpid())
    try:
        fig.savefig(tmp, format="png", **kw)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.remove(tmp)
        raise


def split_args(argv, usage, flags=("--quiet",)):
    """(positional arguments, set of flags given) of a chart module's command line; exits with the
    usage on an unknown option."""
    pos, seen = [], set()
    for a in argv:
        if a.startswith("--"):
            if a not in flags:
                sys.exit(f"nacre: unknown option {a}\n{usage}")
            seen.add(a)
        else:
            pos.append(a)
    return pos, seen


def command_line(argv, usage, positional=1):
    """A chart module's start: (positional arguments, flags) from argv (None: sys.argv[1:]),
    exiting with the usage unless there is exactly `positional` of them; None when matplotlib is
    missing (the warning is printed: the caller returns 0, the data are complete)."""
    args, flags = split_args(sys.argv[1:] if argv is None else argv, usage)
    if len(args) != positional:
        sys.exit(usage)
    if not have_matplotlib():
        return None
    return args, flags


def r_curve_chart(run, quiet=False):
    """r_curve.png of a run directory (both solver families) from the program's r_curve.csv and
    summary.json's crack.toughening_ratio; a run without r_curve.csv gets a one-line warning and
    no chart. Returns the toughening ratio (None: n/a or no R-curve)."""
    r = run.r_curve()
    if r is None:
        warn(f"{os.path.join(run.directory, 'r_curve.csv')} not found (the nacre program writes it); r_curve.png skipped")
        return None
    plt = pyplot()
    crack = run.crack
    gc = crack.get("bed_work_of_fracture")
    ratio = run.toughening_ratio
    fig, ax = plt.subplots(figsize=(6.5, 4.2))
    if len(r["extension"]):
        ax.step(r["extension"], r["G_R"], where="pre", color="C0",
                label="G_R (energy of fracture gained / extension gained)")
    if gc is not None:
        ax.axhline(gc, color="gray", ls="--", label=f"mortar's work of fracture k x1 x2 = {gc:.4g}")
    ax.set_xlabel("crack extension (along the ligament)")
    ax.set_ylabel("G_R (energy per unit crack area)")
    ax.set_ylim(bottom=0)
    said = f"{ratio:.3g}" if ratio is not None and ratio == ratio else "n/a (the crack grew at fewer than 2 rows)"
    ax.set_title(f"R-curve: toughening ratio {said}\n(mean G_R over the second half of the extension / k x1 x2)", fontsize=10)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=8)
    fig.tight_layout()
    save_png(fig, os.path.join(run.directory, "r_curve.png"), dpi=120)
    plt.close(fig)
    if not quiet:
        print(f"crack: extension {crack.get('extension', 0):.4g} to tip x = {crack.get('tip_x', 0):.4g}, "
              f"deflection {crack.get('deflection', 0):.3f}, toughening ratio {said} (r_curve.csv)")
    return ratio
