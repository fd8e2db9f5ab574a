#!/usr/bin/python3
"""How well `solver.accuracy` meets its target: per scene, method and target,
over the measured steps of the `descent study` folders DIR/<scene>/, the share
of steps with e <= TOL, the worst and median e / TOL, the iterations spent,
the steps that ended at the cap and those the target ended above TOL, and
whether at least 90% of the steps
ended at or below TOL with all within 3 TOL (issues 11 and 24). Reads each
folder's accuracy.csv (descent study's own summary) where there is one,
else the cases named tol_<TOL> of its study.csv(.gz) (issue 11's folders,
jobs/study/automatic.sh part accuracy). Prints a Markdown table.

  tools/accuracy_summary.py DIR
"""
import csv
import statistics
import sys
from pathlib import Path

from study_csv import read_study

HEADER = ("| scene | method | target | steps | e <= TOL | worst e / TOL | median e / TOL | "
          "iterations | at the cap | stopped above TOL | 90% <= TOL, all <= 3 TOL |")


def from_accuracy_csv(scene, path):
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            steps, met = int(r["steps"]), int(r["met"])
            print(f"| {scene} | {r['method']} | {float(r['target']):.0e} | {steps} | {met}/{steps} | "
                  f"{float(r['worst_ratio']):.2f} | {float(r['median_ratio']):.2f} | "
                  f"{r['min_iterations']}-{r['max_iterations']} | {r['capped']} | {r['early_misses']} | "
                  f"{r['criterion']} |")


def from_study_csv(scene_dir):
    last = {}  # (case, frame) -> the step's final record
    for r in read_study(scene_dir):
        if r["case"].startswith("tol_"):
            last[(r["case"], r["frame"])] = r
    for case in sorted({c for c, _ in last}, key=lambda c: -float(c[4:])):
        tol = float(case[4:])
        ends = [r for (c, _), r in last.items() if c == case]
        ratios = [float(r["rel_error"]) / tol for r in ends]
        its = [int(r["k"]) for r in ends]
        met = sum(x <= 1 for x in ratios)
        criterion = "met" if met >= 0.9 * len(ends) and max(ratios) <= 3 else "missed"
        print(f"| {scene_dir.name} | {ends[0]['method']} | {tol:.0e} | {len(ends)} | {met}/{len(ends)} | "
              f"{max(ratios):.2f} | {statistics.median(ratios):.2f} | {min(its)}-{max(its)} | - | - | "
              f"{criterion} |")


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    root = Path(sys.argv[1])
    print(HEADER)
    print("|" + " --- |" * (HEADER.count("|") - 1))
    for scene in sorted(d for d in root.iterdir() if d.is_dir()):
        summary = scene / "accuracy.csv"
        if summary.exists():
            from_accuracy_csv(scene.name, summary)
        else:
            from_study_csv(scene)


if __name__ == "__main__":
    main()
