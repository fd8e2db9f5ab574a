#!/usr/bin/python3
"""Simulated force-stretch points of a box under uniaxial load against the
analytic curves of tools/uniaxial_reference.py (the paper's Fig. 11).

Reads one or more CSV files with columns model,force,area,stretch (force: total
applied force in N; area: undeformed loaded-face area in m^2; stretch: measured
mean stretch along the load axis), prints per model the largest relative force
error |F - A P(s)| / |F| against the analytic nominal stress P at the simulated
stretch s (points with zero force or at a stretch where the model is not
well-defined are left out), and draws one panel per model: the simulated
nominal stress F/A over the analytic curve (dashed grey where not well-defined).

  /usr/bin/python3 tools/plot_force_stretch.py sim_*.csv --young 1e5 --poisson 0.3 \\
      [--c2 X --c3 Y] [--output force_stretch.png]

The table needs only the standard library; the PNG needs matplotlib (Debian's
python3-matplotlib) and is skipped with a message where it is missing.
"""
import argparse
import csv
import math
import sys
from collections import defaultdict
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from uniaxial_reference import MODELS, Material, uniaxial_point  # noqa: E402

CURVE_POINTS = 200


def read_simulations(paths):
    """{model: [(stretch, force, area), ...]} from all files, sorted by stretch."""
    runs = defaultdict(list)
    for path in paths:
        with open(path, newline="") as f:
            for row in csv.DictReader(f):
                runs[row["model"].strip()].append((float(row["stretch"]), float(row["force"]), float(row["area"])))
    return {model: sorted(points) for model, points in runs.items()}


def worst_error(model, points, m):
    """(compared points, max relative force error, its stretch) over the comparable points."""
    compared, worst, worst_at = 0, math.nan, math.nan
    for s, force, area in points:
        if s <= 0:  # the box went through itself: off the uniaxial branch
            continue
        ref = uniaxial_point(model, s, m)
        if force == 0 or not ref.well_defined:
            continue
        compared += 1
        error = abs(force - area * ref.nominal_stress) / abs(force)
        if not error <= worst:  # also takes the first one, when worst is nan
            worst, worst_at = error, s
    return compared, worst, worst_at


def analytic_curve(model, points, m):
    """Stretches over the simulated range (and s = 1) with P split into well-defined and not."""
    lo, hi = min(points[0][0], 1.0), max(points[-1][0], 1.0)
    pad = 0.05 * max(hi - lo, 0.1)
    lo, hi = max(lo - pad, 1e-3), hi + pad
    curve = [uniaxial_point(model, lo + (hi - lo) * i / (CURVE_POINTS - 1), m) for i in range(CURVE_POINTS)]
    good = [p.nominal_stress if p.well_defined else math.nan for p in curve]
    bad = [math.nan if p.well_defined else p.nominal_stress for p in curve]
    return [p.stretch for p in curve], good, bad


def plot(runs, m, output):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError as e:
        print(f"plot_force_stretch.py: no PNG written, matplotlib is missing ({e}); "
              "run it with Debian's /usr/bin/python3 and python3-matplotlib", file=sys.stderr)
        return
    cols = min(3, len(runs))
    rows = math.ceil(len(runs) / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(4.5 * cols, 3.8 * rows), squeeze=False)
    for ax, (model, all_points) in zip(axes.flat, runs.items()):
        points = [p for p in all_points if p[0] > 0]
        inverted = len(all_points) - len(points)
        s, good, bad = analytic_curve(model, points, m)
        ax.plot(s, good, "-", color="C0", label="analytic")
        if any(not math.isnan(p) for p in bad):
            ax.plot(s, bad, "--", color="0.6", label="analytic, not well-defined")
        ax.plot([p[0] for p in points], [p[1] / p[2] for p in points], "o", color="C3", mfc="none",
                label="simulation")
        ax.axhline(0, color="0.85", lw=0.8, zorder=0)
        ax.axvline(1, color="0.85", lw=0.8, zorder=0)
        ax.set_title(model + (f" ({inverted} inverted, not shown)" if inverted else ""))
        ax.set_xlabel("stretch")
        ax.set_ylabel("nominal stress F/A (Pa)")
        ax.legend(fontsize=8)
    for ax in axes.flat[len(runs):]:
        ax.set_visible(False)
    fig.suptitle(f"uniaxial load, E = {m.young:g} Pa, nu = {m.poisson:g}"
                 + (f", c2 = {m.c2:g} Pa, c3 = {m.c3:g}" if m.c2 or m.c3 else ""))
    fig.tight_layout()
    fig.savefig(output, dpi=120)
    print(f"wrote {output}")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("csv", nargs="+", type=Path, help="simulation CSVs (model,force,area,stretch)")
    parser.add_argument("--young", type=float, required=True, help="Young's modulus E (Pa)")
    parser.add_argument("--poisson", type=float, required=True, help="Poisson ratio nu")
    parser.add_argument("--c2", type=float, default=0.0, help="mooney_rivlin / fung coefficient (Pa)")
    parser.add_argument("--c3", type=float, default=0.0, help="fung exponent coefficient")
    parser.add_argument("--output", type=Path, help="PNG (default: force_stretch.png beside the first CSV)")
    args = parser.parse_args()
    m = Material(args.young, args.poisson, args.c2, args.c3)

    runs = read_simulations(args.csv)
    for model in [name for name in runs if name not in MODELS]:
        print(f"warning: skipping unknown model '{model}'", file=sys.stderr)
        del runs[model]
    if not runs:
        sys.exit("plot_force_stretch.py: no rows of a known model")

    print(f"{'model':<14} {'points':>6} {'compared':>8} {'max rel force error':>20} {'at stretch':>10}")
    for model, points in runs.items():
        compared, worst, at = worst_error(model, points, m)
        print(f"{model:<14} {len(points):>6} {compared:>8} {worst:>20.3e} {at:>10.4f}")

    plot(runs, m, args.output or args.csv[0].parent / "force_stretch.png")


if __name__ == "__main__":
    main()
