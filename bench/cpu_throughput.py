#!/usr/bin/env python3
"""ns per tet-iteration of `descent run` on the double helix, on CPU.

Runs each configuration (ranks x threads) several times and records the
median of the solver's own figure (step time only: output is not timed),
with the machine, the commands and every sample, in a Markdown table.

  python3 bench/cpu_throughput.py                      # 82k helix, 96 iterations
  python3 bench/cpu_throughput.py --preset 316k --runs 5 --configs 1x1 2x1
  python3 bench/cpu_throughput.py --configs 1x1 --compare /path/to/old/descent

--parameters fixed (default) runs the paper's fixed Chebyshev parameters
(rho 0.96, 10 plain iterations, alpha_max 1), auto the automatic ones (their
spectrum estimates are in the step time); solver.accuracy is 0 either way.
--compare runs an earlier build with its own defaults (before the automatic
parameters: the same fixed method) interleaved with this one, run by run,
so the ratio is measured on one machine in one sitting.
"""
import argparse
import os
import re
import statistics
import subprocess
import sys
from pathlib import Path

from bench_record import machine_lines

ROOT = Path(__file__).resolve().parent.parent


PARAMETER_KEYS = {
    "fixed": ['solver.chebyshev_parameters="fixed"', "solver.rho=0.96", "solver.chebyshev_delay=10",
              "solver.alpha_max=1", "solver.accuracy=0"],
    "auto": ['solver.chebyshev_parameters="auto"', "solver.accuracy=0"],
    "legacy": [],  # an earlier build: its defaults
}


def run_once(binary, ranks, threads, preset, iterations, frames, out_dir, parameters, precision):
    env = dict(os.environ, OMP_NUM_THREADS=str(threads), OMP_PROC_BIND="false",
               OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    cmd = ["mpiexec", "-n", str(ranks), "--oversubscribe", "--bind-to", "none", str(binary), "run", "--overwrite",
           "--set", f'mesh.helix.preset="{preset}"', "--set", f"solver.iterations={iterations}",
           "--set", f"time.frames={frames}", "--set", f"output.every={frames + 1}",
           # The Jacobi iteration's throughput (the multilevel preconditioner's:
           # bench/results/multilevel).
           "--set", 'solver.preconditioner="jacobi"',
           "--precision", precision, "--out", str(out_dir)]
    for key in PARAMETER_KEYS[parameters]:
        cmd += ["--set", key]
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
    parser.add_argument("--parameters", choices=["fixed", "auto"], default="fixed")
    parser.add_argument("--compare", type=Path, help="an earlier build, run interleaved")
    parser.add_argument("--compare-keys", choices=["own", "same"], default="own",
                        help="own: the earlier build's defaults (one from before the automatic "
                             "parameters); same: this build's keys")
    parser.add_argument("--precision", choices=["double", "float"], default="double")
    args = parser.parse_args()

    out_dir = ROOT / "out/bench"
    builds = [("this build", args.binary, args.parameters)]
    if args.compare:
        builds.append(("--compare", args.compare,
                       "legacy" if args.compare_keys == "own" else args.parameters))
    rows = []
    commands = {}
    for config in args.configs:
        ranks, threads = (int(x) for x in config.split("x"))
        samples = {name: [] for name, _, _ in builds}
        for run in range(args.runs):
            for name, binary, parameters in builds:
                value, commands[name] = run_once(binary, ranks, threads, args.preset,
                                                 args.iterations, args.frames, out_dir, parameters,
                                                 args.precision)
                samples[name].append(value)
                print(f"{config} {name}: run {run + 1}/{args.runs}: {value:.1f} ns per tet-iteration",
                      flush=True)
        for name, _, _ in builds:
            rows.append((name, ranks, threads, statistics.median(samples[name]), samples[name]))
    command = commands["this build"]

    base = rows[0][3]
    lines = [
        f"# CPU throughput: double helix {args.preset}, {args.iterations} iterations per step, "
        f"{args.parameters} Chebyshev parameters, {args.precision}",
        "",
        *machine_lines(),
        f"- command (per configuration, ranks and OMP_NUM_THREADS varied): `{command}`",
        f"- figure: step wall time / (tets x iterations), {args.frames} frames per run, median of {args.runs} runs",
    ]
    if args.compare:
        # The earlier build's path is this machine's: shown as EARLIER.
        shown = commands["--compare"].replace(str(args.compare), "EARLIER")
        lines.append(f"- --compare: `{shown}` (an earlier build, "
                     f"{'its own defaults' if args.compare_keys == 'own' else 'the same keys'}), "
                     "run alternately with this build, run by run")
    lines += [
        "",
        "| build | ranks | threads/rank | cores | ns per tet-iteration (median) | ns x cores | vs first row | samples |",
        "| --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    for name, ranks, threads, median, samples in rows:
        cores = ranks * threads
        efficiency = base * rows[0][1] * rows[0][2] / (median * cores)
        lines.append(f"| {name} | {ranks} | {threads} | {cores} | {median:.1f} | {median * cores:.1f} | "
                     f"{100 * efficiency:.0f}% | {', '.join(f'{s:.1f}' for s in samples)} |")
    args.output.parent.mkdir(parents=True, exist_ok=True)
    args.output.write_text("\n".join(lines) + "\n")
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
