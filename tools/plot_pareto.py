#!/usr/bin/python3
"""The Pareto front of issue 11: per scene and rank count, the wall time and
rank 0's processor time each method needs to reach e <= 1e-1 .. 1e-5, from
`descent study` folders laid out as DIR/<scene>/np<ranks>/study.csv (the
`pareto` part of jobs/study/automatic.sh).

  tools/plot_pareto.py DIR [--out OUT] [--reference automatic]

Writes OUT/pareto.md (the times, and whether the reference method reaches
every level NCG or L-BFGS reaches in less time than either) and
OUT/pareto.png. Needs matplotlib (Debian: python3-matplotlib).
"""
import argparse
import math
import sys
from pathlib import Path

from study_csv import read_study

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError as e:
    sys.exit(f"plot_pareto.py needs matplotlib (python3-matplotlib): {e}")

LEVELS = (1e-1, 1e-2, 1e-3, 1e-4, 1e-5)
PEERS = ("ncg", "lbfgs")


def first_reach(rows, level):
    """The first record (in iteration order) with e <= level, or None."""
    for r in rows:
        if float(r["rel_error"]) <= level:
            return r
    return None


def load(root):
    """{(scene, ranks): {case: [rows]}} for every study folder under root."""
    data = {}
    for scene_dir in sorted(p for p in root.iterdir() if p.is_dir()):
        for np_dir in sorted(scene_dir.glob("np*")):
            rows = read_study(np_dir)
            if not rows:
                continue
            cases = {}
            for r in rows:
                cases.setdefault(r["case"], []).append(r)
            data[(scene_dir.name, int(np_dir.name[2:]))] = cases
    return data


def table(data, reference):
    lines = []
    verdicts = []
    for (scene, ranks), cases in data.items():
        names = sorted(cases, key=lambda c: (c != reference, c))
        lines += [f"### {scene}, {ranks} rank(s)", "",
                  "| e <= | " + " | ".join(f"{c}: k, wall ms, cpu ms" for c in names) + " |",
                  "| --- |" + " --- |" * len(names)]
        for level in LEVELS:
            cells = []
            hit = {}
            for c in names:
                r = first_reach(cases[c], level)
                hit[c] = r
                cells.append(f"{r['k']}, {float(r['ms']):.0f}, {float(r['cpu_ms']):.0f}" if r else "not reached")
            lines.append(f"| {level:.0e} | " + " | ".join(cells) + " |")
            peers = [c for c in PEERS if c in hit and hit[c]]
            if reference in hit and peers:
                ref = hit[reference]
                if ref is None:
                    verdicts.append((scene, ranks, level, False, "not reached by " + reference))
                    continue
                faster = all(float(ref["ms"]) < float(hit[p]["ms"]) and
                             float(ref["cpu_ms"]) < float(hit[p]["cpu_ms"]) for p in peers)
                ratio = min(min(float(hit[p]["ms"]), float(hit[p]["cpu_ms"])) /
                            max(float(ref["ms"]), float(ref["cpu_ms"])) for p in peers)
                verdicts.append((scene, ranks, level, faster,
                                 f"{reference} {float(ref['ms']):.0f} ms wall, best of "
                                 f"{'/'.join(peers)} {min(float(hit[p]['ms']) for p in peers):.0f} ms "
                                 f"(x{ratio:.2f})"))
        final = {c: cases[c][-1] for c in names}
        lines += ["", "collectives per step: " + ", ".join(
            f"{c} {final[c]['collectives']} in {final[c]['k']} iterations" for c in names), ""]
    summary = ["| scene | ranks | e <= | reference faster than every peer that reaches it | |",
               "| --- | --- | --- | --- | --- |"]
    for scene, ranks, level, ok, text in verdicts:
        summary.append(f"| {scene} | {ranks} | {level:.0e} | {'yes' if ok else 'NO'} | {text} |")
    return summary + [""] + lines


def plot(data, target):
    scenes = sorted({s for s, _ in data})
    fig, axes = plt.subplots(1, len(scenes), figsize=(4.6 * len(scenes), 4.2), squeeze=False)
    for ax, scene in zip(axes[0], scenes):
        for (s, ranks), cases in sorted(data.items()):
            if s != scene:
                continue
            for i, (c, rows) in enumerate(sorted(cases.items())):
                pts = [(lv, float(r["ms"])) for lv in LEVELS if (r := first_reach(rows, lv))]
                if not pts:
                    continue
                ax.plot([p[0] for p in pts], [p[1] for p in pts],
                        marker="o", linestyle="-" if ranks == 1 else "--", color=f"C{i}",
                        label=f"{c}, {ranks} rank(s)")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.invert_xaxis()
        ax.set_xlabel("relative error e reached")
        ax.set_ylabel("wall time to reach it (ms)")
        ax.set_title(scene)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(target, dpi=110)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("root", type=Path)
    p.add_argument("--out", type=Path)
    p.add_argument("--reference", default="automatic")
    a = p.parse_args()
    out = a.out or a.root
    data = load(a.root)
    if not data:
        sys.exit(f"no study.csv under {a.root}/<scene>/np<ranks>/")
    (out / "pareto.md").write_text("\n".join(table(data, a.reference)) + "\n")
    plot(data, out / "pareto.png")
    print(f"wrote {out / 'pareto.md'} and {out / 'pareto.png'}")


if __name__ == "__main__":
    main()
