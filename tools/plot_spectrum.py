#!/usr/bin/python3
"""The spectrum estimates of the automatic Chebyshev parameters over runs
(the `spectrum` part of jobs/study/automatic.sh): DIR/<scene>/interval1/
stats.csv estimates every step (the drift), DIR/<scene>/interval20/ at the
default interval (the cost, from the run's summary line in progress.log).

  tools/plot_spectrum.py DIR [--out OUT]

Writes OUT/spectrum.md and OUT/spectrum.png. Needs matplotlib.
"""
import argparse
import csv
import re
import statistics
import sys
from pathlib import Path

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError as e:
    sys.exit(f"plot_spectrum.py needs matplotlib (python3-matplotlib): {e}")


def rows_of(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def estimate_cost(folder):
    """(estimates, ms, % of step time) from the run's summary line."""
    log = folder / "progress.log"
    if not log.exists():
        return None
    m = re.search(r"(\d+) spectrum estimate\(s\) ([0-9.]+)% \(([0-9.]+) ms\)", log.read_text())
    return (int(m.group(1)), float(m.group(3)), float(m.group(2))) if m else None


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("root", type=Path)
    p.add_argument("--out", type=Path)
    a = p.parse_args()
    out = a.out or a.root
    scenes = sorted(d for d in a.root.iterdir() if (d / "interval1/stats.csv").exists())
    if not scenes:
        sys.exit(f"no <scene>/interval1/stats.csv under {a.root}")
    lines = ["| scene | lambda_min (first, min, max) | lambda_max without margin (first, min, max) "
             "| kappa (first, max) | estimates at interval 20 | Lanczos steps | allreduces per estimate "
             "| % of step time | rollbacks (interval 1, 20) |",
             "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    for i, d in enumerate(scenes):
        rows = [r for r in rows_of(d / "interval1/stats.csv") if int(r["spectrum_steps"]) > 0]
        frames = [int(r["frame"]) for r in rows]
        # The estimate before any rollback widened it: rows whose step did not roll back.
        clean = [r for r in rows if int(r["rollbacks"]) == 0] or rows
        lmin = [float(r["lambda_min"]) for r in clean]
        lmax = [float(r["lambda_max"]) / 1.1 for r in clean]  # the Ritz value: b / (1 + margin)
        kappa = [b / a for a, b in zip(lmin, lmax)]
        steps = [int(r["spectrum_steps"]) for r in rows]
        default = d / "interval20"
        cost = estimate_cost(default)
        rb20 = sum(int(r["rollbacks"]) for r in rows_of(default / "stats.csv")) if (default / "stats.csv").exists() else "-"
        rb1 = sum(int(r["rollbacks"]) for r in rows_of(d / "interval1/stats.csv"))
        lines.append(
            f"| {d.name} | {lmin[0]:.3e}, {min(lmin):.3e}, {max(lmin):.3e} | {lmax[0]:.3f}, {min(lmax):.3f}, "
            f"{max(lmax):.3f} | {kappa[0]:.3g}, {max(kappa):.3g} | "
            f"{cost[0] if cost else '-'} | {statistics.median(steps):.0f} | {2 + 2 * statistics.median(steps):.0f} | "
            f"{cost[2] if cost else '-'} | {rb1}, {rb20} |")
        cf = [int(r["frame"]) for r in clean]
        axes[0].plot(cf, lmin, color=f"C{i}", label=d.name)
        axes[1].plot(cf, lmax, color=f"C{i}", label=d.name)
    axes[0].set_yscale("log")
    axes[0].set_title("lambda_min of D^-1 H (estimated every step)")
    axes[1].set_title("lambda_max (the Ritz value, before the margin)")
    for ax in axes:
        ax.set_xlabel("frame")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "spectrum.png", dpi=110)
    (out / "spectrum.md").write_text("\n".join(lines) + "\n")
    print(f"wrote {out / 'spectrum.md'} and {out / 'spectrum.png'}")


if __name__ == "__main__":
    main()
