#!/usr/bin/python3
"""Paper 2, Figs. 3 and 4: kinetic energy over the iterations of one solve.

Reads DIR/study.csv of `descent study` (its `kinetic` column: sum m|v_k|^2/2
with v_k = (q_k - q_t)/h) for cases named PRECONDITIONER_GUESS (as
jobs/study/linear_cg.sh names them) and draws one panel per preconditioner,
one line per guess, Newton's converged implicit step as a dashed line when a
newton case is present. Writes DIR/kinetic.png. Needs Debian's
python3-matplotlib.

    /usr/bin/python3 tools/plot_kinetic.py DIR [--title TEXT] [--frame F]
"""
import argparse
import collections
import csv
import pathlib
import sys

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError as e:
    sys.exit(f"plot_kinetic.py needs python3-matplotlib: {e}")

PRECONDITIONERS = ["identity", "mass", "jacobi"]
GUESSES = {"zero": "0", "velocity": "v(t)", "euler": "v(t) + h M^-1 f"}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("dir", type=pathlib.Path)
    parser.add_argument("--title", default="")
    parser.add_argument("--frame", type=int, help="frame to plot (default: the first)")
    args = parser.parse_args()
    with open(args.dir / "study.csv") as f:
        rows = list(csv.DictReader(f))
    if not rows or "kinetic" not in rows[0]:
        sys.exit(f"{args.dir}/study.csv has no kinetic column (written by descent study)")
    frame = args.frame if args.frame is not None else int(rows[0]["frame"])
    series = collections.defaultdict(list)
    for r in rows:
        if int(r["frame"]) == frame and int(r["ranks"]) == int(rows[0]["ranks"]):
            series[r["case"]].append((int(r["k"]), float(r["kinetic"])))
    newton = series.get("newton", [])

    fig, axes = plt.subplots(1, 3, figsize=(15, 4.2), sharey=True)
    for ax, p in zip(axes, PRECONDITIONERS):
        for guess, label in GUESSES.items():
            points = series.get(f"{p}_{guess}")
            if points:
                ax.plot([k for k, _ in points], [e for _, e in points], label=f"guess {label}")
        if newton:
            ax.axhline(newton[-1][1], color="k", ls="--", lw=0.8, label="Newton (implicit Euler)")
        ax.set_title(f"preconditioner: {p}")
        ax.set_xlabel("CG iteration")
        ax.set_xscale("symlog", linthresh=10)
        ax.set_xlim(left=0)
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("kinetic energy (J)")
    axes[0].legend(fontsize=8)
    fig.suptitle(args.title or f"kinetic energy over one solve, frame {frame}")
    fig.tight_layout()
    out = args.dir / "kinetic.png"
    fig.savefig(out, dpi=110)
    print(f"plot_kinetic.py: wrote {out}")


if __name__ == "__main__":
    main()
