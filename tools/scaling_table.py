#!/usr/bin/python3
"""Strong- or weak-scaling table and plot of `descent run` output folders,
one per rank count (jobs/slurm/strong_scaling.sbatch, weak_scaling.sbatch):

  tools/scaling_table.py strong runs/descent-strong-82k-np*
  tools/scaling_table.py weak runs/descent-weak-r2.42-np* --out weak

Reads each folder's stats.csv (src/io/stats_writer.cpp) and takes its rank
count from the folder's name (...-npRANKS). The time per step is the median
wall_ms over the frames (a restarted run's rows included: each is one step);
halo and allreduce are the medians of their columns. Efficiency against the
smallest rank count B with time T_B: strong T_B B / (T_P P), weak T_B / T_P.
Writes OUT.csv, OUT.md and OUT.png (default OUT: scaling-MODE).
Needs Debian's python3-matplotlib (Debian's own python3).
"""
import argparse
import csv
import re
import statistics
import sys
from pathlib import Path


def read_run(folder):
    match = re.search(r"-np(\d+)$", folder.name)
    if not match:
        sys.exit(f"{folder}: the name does not end in -npRANKS")
    stats = folder / "stats.csv"
    try:
        with stats.open(newline="") as f:
            rows = list(csv.DictReader(f))
    except OSError as error:
        sys.exit(f"{stats}: {error.strerror}")
    if not rows:
        sys.exit(f"{stats}: no frames")
    median = lambda column: statistics.median(float(r[column]) for r in rows)
    return {
        "ranks": int(match.group(1)),
        "frames": len(rows),
        "iterations": median("iterations"),
        "ms_per_step": median("wall_ms"),
        "halo_ms": median("halo_ms"),
        "allreduce_ms": median("allreduce_ms"),
        "run": str(folder),
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("mode", choices=["strong", "weak"])
    parser.add_argument("runs", nargs="+", type=Path, help="output folders, one per rank count")
    parser.add_argument("--out", help="prefix of the files written (default: scaling-MODE)")
    args = parser.parse_args()
    out = args.out or f"scaling-{args.mode}"

    runs = sorted((read_run(folder) for folder in args.runs), key=lambda r: r["ranks"])
    counts = [r["ranks"] for r in runs]
    if len(set(counts)) != len(counts):
        sys.exit(f"two runs of the same rank count: {counts}")
    base = runs[0]
    for r in runs:
        ratio = base["ms_per_step"] / r["ms_per_step"]
        if args.mode == "strong":
            r["speedup"] = ratio
            r["efficiency"] = ratio * base["ranks"] / r["ranks"]
        else:
            r["efficiency"] = ratio

    columns = ["ranks", "frames", "iterations", "ms_per_step", "halo_ms", "allreduce_ms"]
    columns += ["speedup"] if args.mode == "strong" else []
    columns += ["efficiency", "run"]
    with open(f"{out}.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=columns)
        writer.writeheader()
        writer.writerows(runs)
    cell = lambda v: f"{v:.3g}" if isinstance(v, float) else str(v)
    lines = [f"{args.mode} scaling, efficiency against {base['ranks']} rank(s)", "",
             "| " + " | ".join(columns) + " |", "|" + "---|" * len(columns)]
    lines += ["| " + " | ".join(cell(r[c]) for c in columns) + " |" for r in runs]
    Path(f"{out}.md").write_text("\n".join(lines) + "\n")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (time_axes, efficiency_axes) = plt.subplots(1, 2, figsize=(10, 4))
    time_axes.loglog(counts, [r["ms_per_step"] for r in runs], "o-", label="step")
    time_axes.loglog(counts, [r["halo_ms"] + r["allreduce_ms"] for r in runs], "s--",
                     label="halo + allreduce")
    if args.mode == "strong":
        ideal = [base["ms_per_step"] * base["ranks"] / p for p in counts]
        time_axes.loglog(counts, ideal, ":", color="grey", label="ideal")
    time_axes.set(xlabel="ranks", ylabel="ms per step (median)", title=f"{args.mode} scaling")
    time_axes.legend()
    efficiency_axes.semilogx(counts, [r["efficiency"] for r in runs], "o-")
    efficiency_axes.axhline(1, color="grey", linestyle=":")
    efficiency_axes.set(xlabel="ranks", ylabel="parallel efficiency", ylim=(0, 1.1 * max(
        1, max(r["efficiency"] for r in runs))))
    for axes in (time_axes, efficiency_axes):
        axes.set_xticks(counts, [str(p) for p in counts])
        axes.minorticks_off()
    fig.tight_layout()
    fig.savefig(f"{out}.png", dpi=120)
    print(f"wrote {out}.csv, {out}.md, {out}.png")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
