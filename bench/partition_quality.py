#!/usr/bin/env python3
"""Partition quality of PT-Scotch and RCB against METIS, the reference.

For each mesh and part count, `descent partition` runs with
partition.method = "metis" (gathered on rank 0), "ptscotch" (in parallel)
and "rcb" (recursive coordinate bisection, in parallel, no dual graph, no
tries), on the same ranks, and its own report gives the faces between parts
(edge cut of the dual graph), the imbalance (most tets in a part / mean) and
the time. Meshes: the double helix at about 4M tets and the real meshes of
../shared/meshes (skipped when absent). Targets: PT-Scotch's cut within 10%
of METIS's (issue 12); RCB's too (issue 22), or say why not.

  python3 bench/partition_quality.py --out bench/results/partition_quality/README.md
"""
import argparse
import os
import re
import subprocess
import tempfile
from datetime import datetime, timezone
from pathlib import Path

from bench_record import cpu_model, mpi_env, write_report

ROOT = Path(__file__).resolve().parent.parent
SHARED = ROOT.parent / "shared" / "meshes"
FILES = ["armadillo_10k.node", "armadillo_13k_ipc.msh", "bunny_ipc.msh", "dragon_16k.mesh"]
REPORT = re.compile(r"partition \((METIS|PT-Scotch|RCB)\) on \d+ rank\(s\) in ([0-9.]+) s: (\d+) parts, "
                    r"imbalance ([0-9.]+), cut faces (\d+)")


def scenes(scratch):
    """(name, scene file) of every mesh to partition."""
    helix = (ROOT / "jobs/helix.toml").read_text()
    helix = re.sub(r'^preset = "82k".*$', "resolution = 11.35", helix, flags=re.M)
    path = Path(scratch) / "helix_4m.toml"
    path.write_text(helix)
    found = [("helix 4M (resolution 11.35)", path)]
    for name in FILES:
        mesh = SHARED / name
        if not mesh.exists():
            print(f"skipped {name}: {mesh} is absent")
            continue
        path = Path(scratch) / (name + ".toml")
        path.write_text(f'[mesh]\nfile = "{mesh}"\n')
        found.append((name, path))
    return found


def partition(binary, ranks, scene, parts, method, tries):
    env = mpi_env()
    cmd = ["mpiexec", "-n", str(ranks), "--oversubscribe", str(binary), "partition", str(scene),
           "-n", str(parts), "--set", f'partition.method="{method}"',
           "--set", f"partition.tries={tries}"]
    text = subprocess.run(cmd, env=env, check=True, capture_output=True, text=True).stdout
    _, seconds, _, imbalance, cut = REPORT.search(text).groups()
    return float(seconds), float(imbalance), int(cut), " ".join(cmd)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--binary", default=str(ROOT / "build/src/app/descent"))
    parser.add_argument("--ranks", type=int, default=2, help="ranks that run the partitioner")
    parser.add_argument("--parts", nargs="+", type=int, default=[2, 4, 8, 16, 64])
    parser.add_argument("--tries", nargs="+", type=int, default=[1, 3],
                        help="partition.tries compared (the same for both partitioners)")
    parser.add_argument("--out", default="-")
    args = parser.parse_args()

    lines = [
        "# Partition quality: PT-Scotch and RCB against METIS",
        "",
        f"- date: {datetime.now(timezone.utc):%Y-%m-%d %H:%M} UTC",
        f"- machine: {cpu_model()}, {os.cpu_count()} logical cores, no GPU",
        f"- each partition computed on {args.ranks} ranks by `descent partition` (METIS: the "
        "dual graph gathered on rank 0, METIS_PartGraphKway, seed 1, partition.tries as "
        "METIS_OPTION_NCUTS; PT-Scotch: SCOTCH_dgraphPart, strategy SCOTCH_STRATSPEED, 3% imbalance, one "
        "thread, deterministic, the best of partition.tries seeds; RCB: recursive coordinate "
        "bisection of tet centroids, exact part sizes, one partition whatever partition.tries); "
        "cut = faces whose two tets "
        "lie in different parts; times are the partition step alone (all tries) on a shared "
        f"machine (load average {os.getloadavg()[0]:.1f} at the start), for orientation only",
        "",
        "| mesh | parts | tries | METIS cut | PT-Scotch cut | ratio | RCB cut | RCB ratio | "
        "METIS imbalance | PT-Scotch imbalance | RCB imbalance | METIS s | PT-Scotch s | RCB s |",
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    commands = []
    worst = {tries: 0.0 for tries in args.tries}
    worst_rcb = {tries: 0.0 for tries in args.tries}
    with tempfile.TemporaryDirectory() as scratch:
        for name, scene in scenes(scratch):
            for parts in args.parts:
                # RCB has no tries: one partition, compared with each row's METIS.
                rcb = partition(args.binary, args.ranks, scene, parts, "rcb", 1)
                commands.append(rcb[3])
                for tries in args.tries:
                    metis = partition(args.binary, args.ranks, scene, parts, "metis", tries)
                    scotch = partition(args.binary, args.ranks, scene, parts, "ptscotch", tries)
                    ratio = scotch[2] / metis[2]
                    ratio_rcb = rcb[2] / metis[2]
                    worst[tries] = max(worst[tries], ratio)
                    worst_rcb[tries] = max(worst_rcb[tries], ratio_rcb)
                    lines.append(f"| {name} | {parts} | {tries} | {metis[2]} | {scotch[2]} | "
                                 f"{ratio:.3f} | {rcb[2]} | {ratio_rcb:.3f} | {metis[1]:.3f} | "
                                 f"{scotch[1]:.3f} | {rcb[1]:.3f} | {metis[0]:.2f} | "
                                 f"{scotch[0]:.2f} | {rcb[0]:.2f} |")
                    commands += [metis[3], scotch[3]]
                    print(lines[-1], flush=True)
    lines.append("")
    for tries, ratio in worst.items():
        lines.append(f"- partition.tries = {tries}: largest ratio of cuts PT-Scotch / METIS "
                     f"{ratio:.3f}, RCB / METIS {worst_rcb[tries]:.3f} (target <= 1.10: "
                     f"PT-Scotch {'met' if ratio <= 1.10 else 'NOT met'}, RCB "
                     f"{'met' if worst_rcb[tries] <= 1.10 else 'NOT met'})")
    lines += ["", "## Commands", ""]
    lines += [f"- `{c}`" for c in commands]
    write_report(lines, args.out)


if __name__ == "__main__":
    main()
