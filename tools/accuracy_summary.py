#!/usr/bin/python3
"""How well `solver.accuracy` meets its target: per scene and target, over
the measured steps of `descent study` folders DIR/<scene>/ whose cases are
named tol_<TOL> (jobs/study/automatic.sh, part accuracy), the share of
steps with e <= TOL, the worst and median e / TOL and the iterations spent.
Prints a Markdown table (rows for the table of
bench/results/chebyshev_auto/README.md).

  tools/accuracy_summary.py DIR
"""
import statistics
import sys
from pathlib import Path

from study_csv import read_study


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    root = Path(sys.argv[1])
    print("| scene | target | steps | e <= TOL | worst e / TOL | median e / TOL | iterations |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for scene in sorted(d for d in root.iterdir() if d.is_dir()):
        last = {}  # (case, frame) -> the step's final record
        for r in read_study(scene):
            if r["case"].startswith("tol_"):
                last[(r["case"], r["frame"])] = r
        for case in sorted({c for c, _ in last}, key=lambda c: -float(c[4:])):
            tol = float(case[4:])
            ends = [r for (c, _), r in last.items() if c == case]
            ratios = [float(r["rel_error"]) / tol for r in ends]
            its = [int(r["k"]) for r in ends]
            print(f"| {scene.name} | {tol:.0e} | {len(ends)} | {sum(x <= 1 for x in ratios)}/{len(ends)} | "
                  f"{max(ratios):.2f} | {statistics.median(ratios):.2f} | {min(its)}-{max(its)} |")


if __name__ == "__main__":
    main()
