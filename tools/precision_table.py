#!/usr/bin/python3
"""Float against double at each accuracy target (issue 22 part 3): reads
DIR/double/ and DIR/float/ as jobs/study/precision.sh leaves them (descent
study's accuracy.csv and the steps' last records in ends.csv) and prints a
Markdown table: per target and precision the steps that ended at e <= TOL, the
worst and median e / TOL, the median iterations and ms per step, and float's
speed against double (median ms of double over median ms of float, both from
the same script run).

  tools/precision_table.py DIR
"""
import csv
import statistics
import sys
from pathlib import Path


def read(folder):
    """case label -> (accuracy.csv row, [ends.csv rows])"""
    with open(folder / "accuracy.csv", newline="") as f:
        summary = {r["case"]: r for r in csv.DictReader(f)}
    with open(folder / "ends.csv", newline="") as f:
        ends = list(csv.DictReader(f))
    return {case: (row, [e for e in ends if e["case"] == case]) for case, row in summary.items()}


def describe(row, ends):
    errors = [float(e["rel_error"]) for e in ends]
    return (f"{row['met']}/{row['steps']} | {float(row['worst_ratio']):.2f} | "
            f"{statistics.median(errors):.1e} | {statistics.median(int(e['k']) for e in ends):.0f} | "
            f"{statistics.median(float(e['ms']) for e in ends):.1f}")


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    root = Path(sys.argv[1])
    double, single = read(root / "double"), read(root / "float")
    print("| target | double: e <= TOL | worst e / TOL | median e | iterations | ms | "
          "float: e <= TOL | worst e / TOL | median e | iterations | ms | float speed-up | "
          "float meets the target |")
    print("|" + " --- |" * 13)
    for case in sorted(double, key=lambda c: -float(double[c][0]["target"])):
        d_row, d_ends = double[case]
        f_row, f_ends = single[case]
        speed = (statistics.median(float(e["ms"]) for e in d_ends) /
                 statistics.median(float(e["ms"]) for e in f_ends))
        print(f"| {float(d_row['target']):.0e} | {describe(d_row, d_ends)} | "
              f"{describe(f_row, f_ends)} | {speed:.2f}x | {f_row['criterion']} |")


if __name__ == "__main__":
    main()
