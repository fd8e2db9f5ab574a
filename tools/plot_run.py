#!/usr/bin/python3
"""Pictures of a `descent run` output folder: the body at a few frames (side
view of every vertex) and the per-frame stats (time, iterations, alpha,
rollbacks, energy), in one PNG.

  tools/plot_run.py out/helix              # writes out/helix/run.png
Needs Debian's python3-h5py and python3-matplotlib (Debian's own python3).
"""
import argparse
import csv
import sys
from pathlib import Path

try:
    import h5py
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError as e:
    sys.exit(f"plot_run.py needs python3-h5py and python3-matplotlib (apt-get install them): {e}")


def read_stats(path):
    """The numeric columns of stats.csv (`status` and the like are left out)."""
    with open(path) as f:
        rows = list(csv.DictReader(f))
    out = {}
    for k in rows[0] if rows else []:
        try:
            out[k] = [float(r[k]) for r in rows]
        except ValueError:
            continue
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("run_dir", type=Path)
    parser.add_argument("--output", type=Path)
    parser.add_argument("--views", type=int, default=4, help="frames to draw")
    args = parser.parse_args()
    out = args.output or args.run_dir / "run.png"

    with h5py.File(args.run_dir / "frames.h5", "r") as f:
        names = sorted(f["frames"].keys())
        picks = [names[round(i * (len(names) - 1) / max(1, args.views - 1))] for i in range(args.views)]
        frames = [(n, f["frames"][n].attrs["time"], f["frames"][n]["positions"][()]) for n in picks]
    stats = read_stats(args.run_dir / "stats.csv")

    fig = plt.figure(figsize=(4 * args.views, 8))
    for i, (name, time, x) in enumerate(frames):
        ax = fig.add_subplot(2, args.views, i + 1)
        ax.scatter(x[:, 0], x[:, 1], s=0.2, c=x[:, 2], cmap="viridis", rasterized=True)
        ax.set_title(f"frame {int(name)}  t = {time:.2f} s")
        ax.set_aspect("equal")
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
    if stats:
        panels = [("wall_ms", "ms per frame"), ("iterations", "iterations per step"),
                  ("alpha", "alpha at step end"), ("rollbacks", "rollbacks per step"),
                  ("energy", "energy at last check [J]")]
        panels = [p for p in panels if p[0] in stats]  # what this file's build wrote
        for i, (key, label) in enumerate(panels):
            ax = fig.add_subplot(2, len(panels), len(panels) + i + 1)
            ax.plot(stats["frame"], stats[key], lw=1)
            ax.set_xlabel("frame")
            ax.set_title(label)
    fig.tight_layout()
    fig.savefig(out, dpi=80)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
