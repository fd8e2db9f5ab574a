#!/usr/bin/python3
"""The distributed cost of a set of `descent study` folders (one per rank
count): per case and rank count, ms per iteration, MPI_Allreduce calls and
ms inside them per iteration, and the time to reach a relative error of
1e-3 (or "not reached"). Standard library only; prints Markdown.

  tools/distributed_summary.py DIR_np1 DIR_np2 ... [--level 1e-3]
"""
import argparse
import csv
from collections import defaultdict
from pathlib import Path


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("dirs", nargs="+", type=Path)
    parser.add_argument("--level", type=float, default=1e-3)
    args = parser.parse_args()
    runs = defaultdict(list)  # (case, ranks, frame) -> rows in order
    for d in args.dirs:
        with open(d / "study.csv") as f:
            for r in csv.DictReader(f):
                runs[(r["case"], int(r["ranks"]), int(r["frame"]))].append(r)
    print(f"| case | ranks | iterations | ms/iteration | cpu ms/iteration | allreduce/iteration | "
          f"allreduce ms/iteration | allreduce share | ms to e <= {args.level:g} |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for (case, ranks, frame), rows in sorted(runs.items()):
        last = rows[-1]
        k = max(int(last["k"]), 1)
        ms, reduce_ms = float(last["ms"]), float(last["reduce_ms"])
        reached = next((r for r in rows if float(r["rel_error"]) <= args.level), None)
        to_level = f"{float(reached['ms']):.1f} (k = {reached['k']})" if reached else "not reached"
        cpu = f"{float(last['cpu_ms']) / k:.2f}" if "cpu_ms" in last else "-"
        print(f"| {case} | {ranks} | {k} | {ms / k:.2f} | {cpu} | {int(last['collectives']) / k:.2f} | "
              f"{reduce_ms / k:.3f} | {100 * reduce_ms / ms:.1f}% | {to_level} |")


if __name__ == "__main__":
    main()
