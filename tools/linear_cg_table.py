#!/usr/bin/python3
"""Paper 2's Table 1 from the runs of jobs/study/linear_cg.sh.

Reads DIR/{zero,velocity,euler}_{1,2,5,10,conv}/ (stats.csv and frames.h5 of
`descent run`) and DIR/chebyshev/ when present; prints markdown: ms/frame
(median over the frames, stats.csv wall_ms), the mean CG iterations per frame
of the converged runs, and each run's largest distance from the converged run
with guess v_t over every frame, as a fraction of the rest bounding-box
diagonal. Needs Debian's python3-h5py and python3-numpy.

    /usr/bin/python3 tools/linear_cg_table.py DIR > DIR/table1.md
"""
import argparse
import csv
import pathlib
import statistics
import sys

try:
    import h5py
    import numpy as np
except ImportError as e:
    sys.exit(f"linear_cg_table.py needs python3-h5py and python3-numpy: {e}")

GUESSES = [("zero", "0"), ("velocity", "v(t)"), ("euler", "v(t) + h M^-1 f")]
BUDGETS = ["1", "2", "5", "10", "conv"]


def stats(run):
    with open(run / "stats.csv") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"{run}/stats.csv has no frames")
    return rows


def trajectory(run):
    """{frame group name: positions [n, 3]} and the rest positions."""
    with h5py.File(run / "frames.h5", "r") as f:
        frames = {name: f["frames"][name]["positions"][()] for name in f["frames"]}
        rest = f["mesh"]["rest_positions"][()]
    return frames, rest


def distance(run, reference, diagonal):
    frames, _ = trajectory(run)
    worst = 0.0
    for name, q in frames.items():
        if name not in reference:
            continue
        if not np.all(np.isfinite(q)):
            return float("inf")
        worst = max(worst, float(np.max(np.linalg.norm(q - reference[name], axis=1))))
    return worst / diagonal


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("dir", type=pathlib.Path)
    args = parser.parse_args()
    reference_run = args.dir / "velocity_conv"
    if not (reference_run / "frames.h5").is_file():
        sys.exit(f"{reference_run}/frames.h5 not found: run jobs/study/linear_cg.sh first")
    reference, rest = trajectory(reference_run)
    diagonal = float(np.linalg.norm(rest.max(axis=0) - rest.min(axis=0)))
    frames = len(stats(reference_run))

    print(f"# Paper 2, Table 1, our numbers: {args.dir}\n")
    print(f"{frames} frames; Jacobi preconditioner; conv: r.r <= 1e-10 b.b. ms/frame is the "
          "median over the frames of the run's wall time per frame (stats.csv wall_ms, the "
          "whole step: rotations, forces, CG, energy). Distance: the largest over all frames "
          "and vertices of |q - q_ref|, q_ref the converged run with guess v(t), as a "
          f"fraction of the rest bounding-box diagonal ({diagonal:.3f} m).\n")
    print("| guess | " + " | ".join(f"{b} ms/frame" for b in BUDGETS) +
          " | conv iterations (mean) | " + " | ".join(f"{b} distance" for b in BUDGETS) + " |")
    print("|" + " --- |" * (2 + 2 * len(BUDGETS)))
    for guess, label in GUESSES:
        ms, dist = [], []
        iterations = "-"
        for budget in BUDGETS:
            run = args.dir / f"{guess}_{budget}"
            if not (run / "stats.csv").is_file():
                ms.append("-")
                dist.append("-")
                continue
            rows = stats(run)
            ms.append(f"{statistics.median(float(r['wall_ms']) for r in rows):.2f}")
            if len(rows) < frames:  # the run stopped: no finite state at the next frame
                dist.append(f"non-finite at frame {len(rows) + 1}")
            else:
                dist.append(f"{distance(run, reference, diagonal):.1e}")
            if budget == "conv":
                iterations = f"{statistics.mean(int(r['iterations']) for r in rows):.1f}"
        print(f"| {label} | " + " | ".join(ms) + f" | {iterations} | " + " | ".join(dist) + " |")

    cheb = args.dir / "chebyshev"
    if (cheb / "stats.csv").is_file():
        rows = stats(cheb)
        ms = statistics.median(float(r["wall_ms"]) for r in rows)
        print(f"\nchebyshev (paper 1, 96 iterations, same scene): {ms:.2f} ms/frame, distance "
              f"{distance(cheb, reference, diagonal):.1e}.")


if __name__ == "__main__":
    main()
