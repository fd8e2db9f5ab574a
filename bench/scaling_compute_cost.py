#!/usr/bin/python3
"""CPU cost of one Chebyshev iteration per tet on one core, at the part sizes
of the scaling model (bench/scaling_model.py reads the CSV this writes).

  bench/scaling_compute_cost.py --resolutions 15.4 4.8125 2.42 1.5275 --runs 3

Each resolution of the double helix (jobs/helix.toml; 15.4 is the 10.36M-tet
helix, the others its parts at 32, 256 and 1024 ranks) runs on one rank and
one thread, the paper's fixed Chebyshev parameters, ITERATIONS a step, no
output, twice: for F1 and for F2 frames. Two figures per pair:

- wall: descent's own "ns per tet-iteration" of the F2 run (step wall time /
  (tets x iterations)), the figure of bench/results/cpu_helix_*.md;
- cpu: (CPU time of the F2 run - CPU time of the F1 run) / (tets x
  ITERATIONS x (F2 - F1)), with the process's user + system time from
  getrusage. The difference removes the set-up (mesh generation, local mesh)
  and counts only the time the process was on a core, so time slices that
  other processes took on a shared machine are not in it (their cache and
  memory-bandwidth contention still is).

The machine's load before and after each run is recorded beside it: on a
shared machine the wall figure is inflated and the cpu one is the one to use.
Writes OUT.csv (one row per run pair) and OUT.md (medians, machine, commands).
"""
import argparse
import csv
import math
import os
import platform
import re
import resource
import statistics
import subprocess
import sys
import time
from datetime import datetime, timezone
from pathlib import Path

from bench_record import cpu_model

ROOT = Path(__file__).resolve().parent.parent
FIXED_PARAMETERS = ['solver.chebyshev_parameters="fixed"', "solver.rho=0.96", "solver.chebyshev_delay=10",
                    "solver.alpha_max=1", "solver.accuracy=0"]


def load_average():
    return " ".join(f"{x:.2f}" for x in os.getloadavg())


def helix_scene(resolution, folder):
    """jobs/helix.toml at `resolution`: its preset line replaced, as the
    README's 10M-tet example does with sed (a preset and a resolution
    exclude each other, so --set cannot do it)."""
    text = (ROOT / "jobs/helix.toml").read_text()
    text, count = re.subn(r'^preset = "82k".*$', f"resolution = {resolution}", text, flags=re.M)
    if count != 1:
        sys.exit("jobs/helix.toml has no line 'preset = \"82k\"' to replace")
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"helix_r{resolution}.toml"
    path.write_text(text)
    return path


def run_once(binary, scene, iterations, frames, out_dir):
    """One `descent run` on one rank (an MPI singleton: no mpiexec, so the
    CPU time is this one process's). Returns (tets, wall ns, CPU s, command)."""
    env = dict(os.environ, OMP_NUM_THREADS="1", OMP_PROC_BIND="false",
               OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    cmd = [str(binary), "run", str(scene), "--overwrite",
           "--set", f"solver.iterations={iterations}", "--set", f"time.frames={frames}",
           "--set", f"output.every={frames + 1}", "--set", "output.checkpoint_every=0",
           "--set", 'solver.preconditioner="jacobi"',  # the Jacobi iteration's cost
           "--out", str(out_dir)]
    for key in FIXED_PARAMETERS:
        cmd += ["--set", key]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    result = subprocess.run(cmd, env=env, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    text = result.stdout + result.stderr
    if result.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed ({result.returncode}):\n{text}")
    ns = re.search(r"([0-9.]+) ns per tet-iteration", text)
    tets = re.search(r"([0-9]+) tets", text)
    if not ns or not tets:
        sys.exit(f"no tet count or ns per tet-iteration in the output of {' '.join(cmd)}:\n{text}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return int(tets.group(1)), float(ns.group(1)), cpu, " ".join(cmd)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--binary", default=ROOT / "build/src/app/descent", type=Path)
    parser.add_argument("--resolutions", nargs="+", type=float, default=[15.4, 4.8125, 2.42, 1.5275])
    parser.add_argument("--iterations", type=int, default=32,
                        help="per step; a multiple of check_interval (8) and hessian_interval (32) "
                             "keeps their share as in the paper's 96")
    parser.add_argument("--seconds", type=float, default=20,
                        help="aim of the F2 - F1 frames' CPU time; sets F1 and F2 per size")
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--out", type=Path, default=ROOT / "bench/results/scaling_model/compute_cost")
    args = parser.parse_args()

    out_dir = Path(os.environ.get("TMPDIR", "/tmp")) / "descent_compute_cost"
    rows, commands = [], {}
    for resolution in args.resolutions:
        # Frames from a guess of 100 ns per tet-iteration and the tet count's
        # cube law (15.4: 10,358,076 tets); the measurement does not use it.
        guess_tets = 10_358_076 * (resolution / 15.4) ** 3
        frame_seconds = guess_tets * args.iterations * 100e-9
        extra = max(1 if frame_seconds > 10 else 2, math.ceil(args.seconds / frame_seconds))
        f1 = 1 if frame_seconds > 5 else max(2, extra // 10)
        f2 = f1 + extra
        scene = helix_scene(resolution, out_dir)
        for run in range(args.runs):
            load_before = load_average()
            started = time.time()
            tets, _, cpu1, _ = run_once(args.binary, scene, args.iterations, f1, out_dir / "run")
            tets2, wall_ns, cpu2, command = run_once(args.binary, scene, args.iterations, f2, out_dir / "run")
            assert tets == tets2
            commands[resolution] = command.replace(f"time.frames={f2}", "time.frames=F").replace(
                f"output.every={f2 + 1}", "output.every=F2+1").replace(
                str(scene), "SCENE").replace(str(out_dir / "run"), "OUT")
            cpu_ns = 1e9 * (cpu2 - cpu1) / (tets * args.iterations * (f2 - f1))
            row = {"resolution": resolution, "tets": tets, "run": run + 1, "frames_f1": f1, "frames_f2": f2,
                   "iterations": args.iterations, "cpu_ns": round(cpu_ns, 2), "wall_ns": wall_ns,
                   "cpu_s_f1": round(cpu1, 2), "cpu_s_f2": round(cpu2, 2),
                   "wall_s_pair": round(time.time() - started, 1),
                   "load_before": load_before, "load_after": load_average()}
            rows.append(row)
            print(", ".join(f"{k} {v}" for k, v in row.items()), flush=True)

    args.out.parent.mkdir(parents=True, exist_ok=True)
    with open(f"{args.out}.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    lines = [
        "# CPU cost per tet-iteration, one rank x one thread, at the scaling model's part sizes",
        "",
        f"- date: {datetime.now(timezone.utc).strftime('%Y-%m-%d %H:%M UTC')}",
        f"- machine: {cpu_model()}, {os.cpu_count()} logical cores, {platform.system()} {platform.release()}; "
        "no GPU; shared with other work (load averages per run in the CSV)",
        f"- binary: {args.binary}",
        f"- command (F = F1, then F2): `{next(iter(commands.values()))}`, SCENE = jobs/helix.toml "
        "with its line `preset = \"82k\"` replaced by `resolution = R`",
        "- cpu ns: (CPU s at F2 - CPU s at F1) / (tets x iterations x (F2 - F1)); "
        "wall ns: descent's own figure of the F2 run",
        "",
        "| resolution | tets | F1, F2 | cpu ns (median) | wall ns (median) | cpu ns samples | wall ns samples |",
        "| --- | --- | --- | --- | --- | --- | --- |",
    ]
    for resolution in args.resolutions:
        mine = [r for r in rows if r["resolution"] == resolution]
        lines.append(
            f"| {resolution} | {mine[0]['tets']:,} | {mine[0]['frames_f1']}, {mine[0]['frames_f2']} | "
            f"{statistics.median(r['cpu_ns'] for r in mine):.1f} | "
            f"{statistics.median(r['wall_ns'] for r in mine):.1f} | "
            f"{', '.join(str(r['cpu_ns']) for r in mine)} | {', '.join(str(r['wall_ns']) for r in mine)} |")
    Path(f"{args.out}.md").write_text("\n".join(lines) + "\n")
    print(f"wrote {args.out}.csv and {args.out}.md")


if __name__ == "__main__":
    main()
