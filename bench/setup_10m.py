#!/usr/bin/env python3
"""Set-up of the 10M-tet double helix on 2 ranks, partitioned inside the run, by phase and by
partition.method (issue 22: at most 5 s from start to the first iteration).

Each run is `descent run` for one frame of a few iterations; the phases come from its own log:
"mesh set-up ... on rank 0: slices, dual graph, partition, tets moved, vertices, faces matched,
local mesh, local order" and "set-up S s to the first step: mesh, solver, output" (solver
built; output opened: mesh and frame 0 written). The methods are run in turn, round after
round, so a change of the machine's load falls on all of them.

Each method runs with glibc's malloc as it comes (4 KiB pages) and with transparent huge pages
on malloc's maps (GLIBC_TUNABLES=glibc.malloc.hugetlb=1), the cases in turn in each round.

  python3 bench/setup_10m.py --out bench/results/setup_10m/README.md   # 4k and huge
  python3 bench/setup_10m.py --size 1M --runs 1 --methods rcb --pages huge   # quick look
"""
import argparse
import os
import re
import statistics
import tempfile
import subprocess
from datetime import datetime, timezone
from pathlib import Path

from bench_record import cpu_model, mpi_env, write_report
from setup_memory import RESOLUTIONS, command, scene_file

ROOT = Path(__file__).resolve().parent.parent
PHASES = ["slices", "dual graph", "partition", "tets moved", "vertices", "faces matched",
          "local mesh", "local order", "solver", "output"]
MESH_LINE = re.compile(
    r"mesh set-up ([0-9.]+) s on rank 0: slices ([0-9.]+) s, dual graph ([0-9.]+) s, partition "
    r"([0-9.]+) s, tets moved ([0-9.]+) s, vertices ([0-9.]+) s, faces matched ([0-9.]+) s, local "
    r"mesh ([0-9.]+) s, local order \([a-z]+\) ([0-9.]+) s")
QUALITY_LINE = re.compile(r"partition \(([A-Za-z-]+)\): \d+ parts, imbalance ([0-9.]+), cut faces "
                          r"(\d+)")


# The pages a run's malloc uses: glibc's defaults (4 KiB pages), or transparent huge pages
# (madvise) on the memory it maps, a 2 MiB page faulted in where 512 pages of 4 KiB were
# (docs/partition.md: which is faster depends on the machine's page faults).
PAGES = {"4k": {}, "huge": {"GLIBC_TUNABLES": "glibc.malloc.hugetlb=1"}}


def run_once(cmd, pages):
    env = mpi_env()
    env.pop("GLIBC_TUNABLES", None)
    env.update(PAGES[pages])
    text = subprocess.run(cmd, env=env, check=True, capture_output=True, text=True).stdout
    setup, _, solver, output = (float(x) for x in re.search(
        r"set-up ([0-9.]+) s to the first step: mesh ([0-9.]+) s, solver ([0-9.]+) s, output "
        r"([0-9.]+) s", text).groups())
    mesh = [float(x) for x in MESH_LINE.search(text).groups()]
    name, imbalance, cut = QUALITY_LINE.search(text).groups()
    return {"setup": setup, "phases": mesh[1:] + [solver, output], "partitioner": name,
            "imbalance": float(imbalance), "cut": int(cut)}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--binary", default=str(ROOT / "build/src/app/descent"))
    parser.add_argument("--size", default="10M", choices=list(RESOLUTIONS))
    parser.add_argument("--ranks", type=int, default=2)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--iterations", type=int, default=16)
    parser.add_argument("--methods", nargs="+", default=["auto", "rcb"],
                        help="partition.method values compared")
    parser.add_argument("--pages", nargs="+", default=["4k", "huge"], choices=list(PAGES),
                        help="4k: glibc's defaults; huge: GLIBC_TUNABLES=glibc.malloc.hugetlb=1")
    parser.add_argument("--out", default="-")
    args = parser.parse_args()

    cases = [(method, pages) for pages in args.pages for method in args.methods]
    samples = {case: [] for case in cases}
    commands = {}
    with tempfile.TemporaryDirectory() as scratch:
        scene = scene_file(scratch, RESOLUTIONS[args.size])
        for _ in range(args.runs):
            for method, pages in cases:
                cmd = command(args.binary, args.ranks, scene, args.iterations, scratch, method,
                              None)
                # Recorded without this machine's paths.
                commands[method] = " ".join(cmd).replace(f"{ROOT}/", "").replace(scratch, "SCRATCH")
                samples[(method, pages)].append(run_once(cmd, pages))
                print(method, pages, samples[(method, pages)][-1]["setup"], flush=True)

    median = statistics.median
    lines = [
        f"# Set-up of the {args.size} double helix on {args.ranks} ranks, by phase",
        "",
        f"- date: {datetime.now(timezone.utc):%Y-%m-%d %H:%M} UTC",
        f"- machine: {cpu_model()}, {os.cpu_count()} logical cores, no GPU (CPU backend); "
        f"load average at the end {os.getloadavg()[0]:.1f}",
        f"- each run: 1 frame of {args.iterations} iterations (solver.accuracy = 0), no "
        "checkpoint, Jacobi preconditioner; seconds on rank 0 from the run's own log (output: "
        "the output opened, mesh and frame 0 written)",
        f"- median of {args.runs} runs per case, the cases taken in turn in each round",
        "- pages: 4k = glibc's malloc as it comes, huge = GLIBC_TUNABLES=glibc.malloc.hugetlb=1 "
        "(transparent huge pages: " + Path("/sys/kernel/mm/transparent_hugepage/enabled")
        .read_text().strip() + ")",
        "",
        "| partition.method | pages | partitioner | set-up s | " + " | ".join(PHASES)
        + " | cut faces | imbalance |",
        "| --- | --- | --- | --- | " + " | ".join("---" for _ in PHASES) + " | --- | --- |",
    ]
    for method, pages in cases:
        s = samples[(method, pages)]
        phases = [median(x["phases"][k] for x in s) for k in range(len(PHASES))]
        lines.append(
            f"| {method} | {pages} | {s[0]['partitioner']} | {median(x['setup'] for x in s):.2f} | "
            + " | ".join(f"{p:.2f}" for p in phases)
            + f" | {s[0]['cut']} | {s[0]['imbalance']:.3f} |")
    lines += ["", "## Commands", ""]
    lines += [f"- {method}: `{cmd}` (huge: with GLIBC_TUNABLES=glibc.malloc.hugetlb=1 in the "
              "environment)"
              for method, cmd in commands.items()]
    lines += ["", "## Samples (set-up s; by phase in the table's order)", ""]
    for method, pages in cases:
        lines.append(f"- {method}, {pages}: " + "; ".join(
            f"{x['setup']:.2f} (" + " ".join(f"{p:.2f}" for p in x["phases"]) + ")"
            for x in samples[(method, pages)]))
    write_report(lines, args.out)


if __name__ == "__main__":
    main()
