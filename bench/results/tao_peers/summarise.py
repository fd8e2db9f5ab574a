#!/usr/bin/python3
"""Table of a tao_peers study folder (or several): per case the iterations
run, wall and rank-0 processor ms per iteration, collectives per iteration,
and the iteration, wall ms and processor ms at which e_k first reaches 1e-2
and 1e-4 (the study's ms are medians of its repeats).

  bench/results/tao_peers/summarise.py DIR [DIR ...]   (Markdown on stdout)
"""
import sys
from collections import defaultdict
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[3] / "tools"))
from study_csv import read_study  # noqa: E402

LEVELS = (1e-2, 1e-4)


def first_at(points, level):
    for p in points:
        if p["e"] <= level:
            return p
    return None


def main():
    print("| mesh | ranks | case | iterations | final e | ms/it | cpu ms/it | collectives/it |"
          + "".join(f" to {lv:g}: k, ms, cpu ms |" for lv in LEVELS))
    print("| --- " * (8 + len(LEVELS)) + "|")
    for folder in map(Path, sys.argv[1:]):
        rows = read_study(folder)
        cases = defaultdict(list)
        for r in rows:
            cases[(int(r["ranks"]), r["case"])].append(
                {"k": int(r["k"]), "e": float(r["rel_error"]), "ms": float(r["ms"]),
                 "cpu": float(r["cpu_ms"]), "coll": int(r["collectives"])})
        for (ranks, case), points in cases.items():
            last = points[-1]
            k = max(last["k"], 1)
            cells = [folder.name, str(ranks), case, str(last["k"]), f"{last['e']:.2e}",
                     f"{last['ms'] / k:.2f}", f"{last['cpu'] / k:.2f}", f"{last['coll'] / k:.2f}"]
            for lv in LEVELS:
                p = first_at(points, lv)
                cells.append(f"{p['k']}, {p['ms']:.0f}, {p['cpu']:.0f}" if p else "not reached")
            print("| " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
