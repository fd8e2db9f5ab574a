#!/usr/bin/env python3
"""The built-in job's ms per frame, this build against an earlier one, in one sitting.

Runs `descent run` with no scene (jobs/helix.toml: the 82K helix, each step to
1e-2 with the automatic preconditioner) for --frames frames with each binary,
alternately run by run, and records the medians, every sample and the
machine in bench/results/main_job_compare.md.

  python3 bench/main_job_compare.py --earlier out/bench/before/descent --earlier-name 2ef1328

--set KEY=VALUE (repeatable) passes scene keys to both builds (another mesh,
method or accuracy); the report names them.
"""
import argparse
import re
import statistics
import sys
from pathlib import Path

from bench_record import machine_lines, mpi_env, run_command, sample_list, write_report

ROOT = Path(__file__).resolve().parent.parent
WORK = ROOT / "out" / "bench" / "main_job_compare"


def ms_per_frame(binary, ranks, frames, keys):
    cmd = ["mpiexec", "-n", str(ranks), "--oversubscribe", "--bind-to", "none", str(binary), "run", "--overwrite",
           "--out", str(WORK), "--set", f"time.frames={frames}", "--set", f"output.every={frames + 1}"]
    for key in keys:
        cmd += ["--set", key]
    text, shown = run_command(cmd, ROOT, mpi_env())
    found = re.search(r"([0-9.]+) ms/frame", text)
    if not found:
        sys.exit(f"no ms/frame in the output of {shown}")
    return float(found.group(1)), shown


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--binary", default=ROOT / "build/src/app/descent", type=Path)
    parser.add_argument("--earlier", required=True, type=Path, help="an earlier build's descent")
    parser.add_argument("--earlier-name", required=True, help="what the earlier build is (a commit)")
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--frames", type=int, default=20)
    parser.add_argument("--configs", nargs="+", type=int, default=[1, 2], help="rank counts (1 thread each)")
    parser.add_argument("--set", dest="keys", action="append", default=[], metavar="KEY=VALUE",
                        help="a scene key for both builds (repeatable)")
    parser.add_argument("--output", default=ROOT / "bench/results/main_job_compare.md")
    args = parser.parse_args()
    WORK.mkdir(parents=True, exist_ok=True)
    rows, command = [], ""
    for ranks in args.configs:
        now, earlier = [], []
        for run in range(args.runs):
            earlier.append(ms_per_frame(args.earlier, ranks, args.frames, args.keys)[0])
            ms, command = ms_per_frame(args.binary, ranks, args.frames, args.keys)
            now.append(ms)
            print(f"{ranks} rank(s) run {run + 1}/{args.runs}: {ms:.1f} ms/frame (earlier {earlier[-1]:.1f})",
                  flush=True)
        rows.append((ranks, earlier, now))
    lines = [
        "# The built-in job's ms per frame: this build against an earlier one",
        "",
        *machine_lines(),
        f"- command (last run; ranks and binary varied): `{command}`",
        f"- earlier build: {args.earlier_name} (`{str(args.earlier).replace(f'{ROOT}/', '')}`), run alternately "
        "with this build's",
        f"- figure: the run's own ms/frame over {args.frames} frames of jobs/helix.toml (82K helix, accuracy 1e-2"
        + (f"; with {', '.join(f'`{k}`' for k in args.keys)}" if args.keys else "")
        + f"), median of {args.runs} runs; 1 OpenMP thread per rank",
        "",
        "| ranks | earlier ms/frame | this build ms/frame | speed-up | samples earlier | samples this build |",
        "| --- | --- | --- | --- | --- | --- |",
    ]
    for ranks, earlier, now in rows:
        lines.append(f"| {ranks} | {statistics.median(earlier):.1f} | {statistics.median(now):.1f} | "
                     f"{statistics.median(earlier) / statistics.median(now):.2f}x | "
                     f"{sample_list(earlier)} | {sample_list(now)} |")
    write_report(lines, str(args.output))
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
