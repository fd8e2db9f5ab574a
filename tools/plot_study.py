#!/usr/bin/python3
"""Plots of a `descent study` output folder (study.csv, pareto.csv): the
relative error e_k against iterations and against milliseconds (log scale),
one line per case, one figure per (ranks, frame) or, with --frames, the
error at the end of the step per measured frame; and the Pareto front as a
Markdown table.

  tools/plot_study.py DIR [DIR ...] [--title TEXT] [--frames] [--cases A B ...]
                      [--name NAME] [--out DIR]
writes NAME.png (default study.png, or frames.png with --frames) and
NAME_pareto.md (over the plotted cases) in the first DIR or --out.
Needs matplotlib (Debian: /usr/bin/python3 with python3-matplotlib).
"""
import argparse
import sys
from collections import defaultdict
from pathlib import Path

from study_csv import read_study

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError as e:
    sys.exit(f"plot_study.py needs matplotlib (use /usr/bin/python3 or install "
             f"python3-matplotlib): {e}")

# Errors at or below this are the round-off floor of eps: drawn at the floor.
FLOOR = 1e-12


def curves(rows, time_column):
    """{(ranks, frame): {case: [(k, ms, e, collectives, reduce_ms)]}} in file order."""
    out = defaultdict(lambda: defaultdict(list))
    for r in rows:
        out[(int(r["ranks"]), int(r["frame"]))][r["case"]].append(
            (int(r["k"]), float(r[time_column]), max(float(r["rel_error"]), FLOOR),
             int(r["collectives"]), float(r["reduce_ms"])))
    return out


def plot_steps(data, title, target, time_label):
    keys = sorted(data)
    fig, axes = plt.subplots(len(keys), 2, figsize=(12, 4.2 * len(keys)), squeeze=False)
    for row, key in enumerate(keys):
        for case, points in data[key].items():
            k = [p[0] for p in points]
            ms = [p[1] for p in points]
            e = [p[2] for p in points]
            axes[row][0].semilogy(k, e, label=case)
            axes[row][1].loglog([max(m, 1e-3) for m in ms], e, label=case)
        ranks, frame = key
        axes[row][0].set_title(f"{title}: {ranks} rank(s), frame {frame}")
        axes[row][0].set_xlabel("iteration k")
        axes[row][1].set_xlabel(time_label)
        for ax in axes[row]:
            ax.set_ylabel("relative error e_k")
            ax.grid(True, which="both", alpha=0.3)
        axes[row][0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(target, dpi=110)


def plot_frames(rows, title, target, relative):
    """End-of-step error per measured frame, per case (Fig. 6 style). The
    relative error is normalised by each case's own eps(q_0), which differs
    between initialisations, so by default the absolute error eps(q) - eps*
    (J) is drawn; eps* follows from any row with e != 1: (E_k - e_k E_0) /
    (1 - e_k). With `relative` (cases that share their initial guess) e
    itself is drawn."""
    steps = defaultdict(list)
    for r in rows:
        steps[(r["case"], int(r["frame"]))].append(r)
    per_case = defaultdict(list)
    for (case, frame), rs in sorted(steps.items(), key=lambda t: t[0][1]):
        e0, last = float(rs[0]["energy"]), rs[-1]
        ek, rel = float(last["energy"]), float(last["rel_error"])
        if rel == 1 or rel != rel:
            continue
        star = (ek - rel * e0) / (1 - rel)
        per_case[case].append((frame, max(rel if relative else ek - star, FLOOR)))
    fig, ax = plt.subplots(figsize=(10, 4.5))
    for case, points in per_case.items():
        ax.semilogy([p[0] for p in points], [p[1] for p in points], marker=".", label=case)
    ax.set_xlabel("frame")
    ax.set_ylabel("e at the end of the step" if relative else
                  "eps(q) - eps* at the end of the step (J)")
    ax.set_title(title)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(target, dpi=110)


LEVELS = (1e-1, 1e-2, 1e-3, 1e-4, 1e-6, 1e-8)


def pareto_front(rows, time_column):
    """Per (ranks, frame) and error level: the case and iteration reaching
    that level in the least wall time (NaN errors never reach a level)."""
    out = []
    groups = defaultdict(list)
    for r in rows:
        groups[(int(r["ranks"]), int(r["frame"]))].append(r)
    for (ranks, frame), group in sorted(groups.items()):
        for level in LEVELS:
            hits = [r for r in group if float(r["rel_error"]) <= level]
            best = min(hits, key=lambda r: float(r[time_column])) if hits else None
            out.append({"ranks": ranks, "frame": frame, "level": level,
                        "case": best["case"] if best else "none",
                        "k": best["k"] if best else "",
                        "ms": best[time_column] if best else ""})
    return out


def pareto_table(rows, time="wall"):
    lines = [f"| ranks | frame | error level | cheapest case | iterations | {time} ms |",
             "| --- | --- | --- | --- | --- | --- |"]
    for r in rows:
        lines.append(f"| {r['ranks']} | {r['frame']} | {float(r['level']):.0e} | {r['case']} "
                     f"| {r['k']} | {float(r['ms']):.1f} |" if r["k"] else
                     f"| {r['ranks']} | {r['frame']} | {float(r['level']):.0e} | none reached | | |")
    return "\n".join(lines) + "\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("dirs", nargs="+", type=Path,
                        help="study output folder(s); several are merged (e.g. 1, 2, 4 ranks)")
    parser.add_argument("--title", default="descent study")
    parser.add_argument("--frames", action="store_true",
                        help="plot the end-of-step error per frame instead")
    parser.add_argument("--relative", action="store_true",
                        help="with --frames: the relative error e (cases with one initial guess)")
    parser.add_argument("--out", type=Path, help="output folder (default: the first DIR)")
    parser.add_argument("--cases", nargs="+", help="only these cases (default: all)")
    parser.add_argument("--name", help="file name stem (default: study or frames)")
    parser.add_argument("--time", choices=("wall", "cpu"), default="wall",
                        help="time axis and Pareto cost: rank 0's wall or processor time")
    args = parser.parse_args()
    out = args.out or args.dirs[0]
    name = args.name or ("frames" if args.frames else "study")
    rows = []
    for d in args.dirs:
        rows += read_study(d)
    if args.cases:
        rows = [r for r in rows if r["case"] in args.cases]
    if not rows:
        sys.exit(f"no rows in {args.dirs} for cases {args.cases}")
    if args.frames:
        plot_frames(rows, args.title, out / f"{name}.png", args.relative)
    else:
        column = "ms" if args.time == "wall" else "cpu_ms"
        if column not in rows[0]:
            sys.exit(f"{column} is not in study.csv (written by an older descent)")
        plot_steps(curves(rows, column), args.title, out / f"{name}.png",
                   "wall time (ms)" if args.time == "wall" else "processor time, rank 0 (ms)")
    print(f"wrote {out / (name + '.png')}")
    column = "ms" if args.time == "wall" else "cpu_ms"
    (out / f"{name}_pareto.md").write_text(pareto_table(pareto_front(rows, column), args.time))
    print(f"wrote {out / (name + '_pareto.md')}")


if __name__ == "__main__":
    main()
