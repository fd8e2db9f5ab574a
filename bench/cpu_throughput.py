#!/usr/bin/env python3
"""ns per tet-iteration of `descent run` on the double helix, on CPU.

Runs each configuration (ranks x threads) several times and records the
median of the solver's own figure (step time only: output is not timed),
with the machine, the commands and every sample, in a Markdown table.

  python3 bench/cpu_throughput.py                      # 82k helix, 96 iterations
  python3 bench/cpu_throughput.py --preset 316k --runs 5 --configs 1x1 2x1
"""
import argparse
import os
import platform
import re
import statistics
import subprocess
import sys
from datetime import datetime, timezone
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def cpu_model():
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def run_once(binary, ranks, threads, preset, iterations, frames, out_dir):
    env = dict(os.environ, OMP_NUM_THREADS=str(threads), OMP_PROC_BIND="false",
               OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    cmd = ["mpiexec", "-n", str(ranks), "--oversubscribe", "--bind-to", "none", str(binary), "run", "--overwrite",
           "--set", f'mesh.helix.preset="{preset}"', "--set", f"solver.iterations={iterations}",
           "--set", f"time.frames={frames}", "--set", f"output.every={frames + 1}",
           "--out", str(out_dir)]
    text = subprocess.run(cmd, env=env, check=True, capture_output=True, text=True).stdout
    match = re.search(r"([0-9.]+) ns per tet-iteration", text)
    if not match:
        sys.exit(f"no ns per tet-iteration line in the output of {' '.join(cmd)}:\n{text}")
    # Recorded relative to the repository, so results name no machine's paths.
    return float(match.group(1)), " ".join(cmd).replace(f"{ROOT}/", "")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--binary", default=ROOT / "build/src/app/descent", type=Path)
    parser.add_argument("--preset", default="82k")
    parser.add_argument("--iterations", type=int, default=96)
    parser.add_argument("--frames", type=int, default=10)
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--configs", nargs="+", default=["1x1", "1x2", "2x1"],
                        help="RANKSxTHREADS")
    parser.add_argument("--output", type=Path,
                        default=ROOT / "bench/results/cpu_throughput.md",
                        help="Markdown file for the table")
    args = parser.parse_args()

    out_dir = ROOT / "out/bench"
    rows = []
    command = ""
    for config in args.configs:
        ranks, threads = (int(x) for x in config.split("x"))
        samples = []
        for run in range(args.runs):
            value, command = run_once(args.binary, ranks, threads, args.preset, args.iterations,
                                      args.frames, out_dir)
            samples.append(value)
            print(f"{config}: run {run + 1}/{args.runs}: {value:.1f} ns per tet-iteration", flush=True)
        rows.append((ranks, threads, statistics.median(samples), samples))

    base = rows[0][2]
    lines = [
        f"# CPU throughput: double helix {args.preset}, {args.iterations} iterations per step",
        "",
        f"- date: {datetime.now(timezone.utc).strftime('%Y-%m-%d %H:%M UTC')}",
        f"- machine: {cpu_model()}, {os.cpu_count()} logical cores, {platform.system()} {platform.release()}",
        f"- GPU: none used (CPU backend)",
        f"- command (per configuration, ranks and OMP_NUM_THREADS varied): `{command}`",
        f"- figure: step wall time / (tets x iterations), {args.frames} frames per run, median of {args.runs} runs",
        "",
        "| ranks | threads/rank | cores | ns per tet-iteration (median) | ns x cores | efficiency vs first row | samples |",
        "| --- | --- | --- | --- | --- | --- | --- |",
    ]
    for ranks, threads, median, samples in rows:
        cores = ranks * threads
        efficiency = base * rows[0][0] * rows[0][1] / (median * cores)
        lines.append(f"| {ranks} | {threads} | {cores} | {median:.1f} | {median * cores:.1f} | "
                     f"{100 * efficiency:.0f}% | {', '.join(f'{s:.1f}' for s in samples)} |")
    args.output.parent.mkdir(parents=True, exist_ok=True)
    args.output.write_text("\n".join(lines) + "\n")
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
