#!/usr/bin/env python3
"""What the default accuracy (issue 24: a scene without solver keys runs each
Chebyshev step to 1e-2) costs: ms per frame, iterations and the estimated
error per step, median of R runs of F frames, on

  - the main job (`descent run`, no scene: jobs/helix.toml built in), which
    sets its own target and cap and so runs as before;
  - the same helix with its [solver] table removed, before (96 iterations a
    step, what such a scene ran: `--set solver.iterations=96`) and after (no
    solver keys: the default target).

    /usr/bin/python3 bench/default_accuracy.py --descent build/src/app/descent \
        --out bench/results/default_accuracy.md
"""
import argparse
import csv
import re
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "bench"))
import bench_record  # noqa: E402


def without_solver_table(scene_text):
    """The scene with its [solver] table (up to the next table) removed."""
    return re.sub(r"^\[solver\]\n(?:(?!\[).*\n)*", "", scene_text, flags=re.M)


def one_run(args, scene, extra, out_dir):
    command = [args.mpiexec, "-n", str(args.ranks), "--oversubscribe", args.descent, "run"]
    command += ([scene] if scene else []) + ["--set", f"time.frames={args.frames}"] + extra
    command += ["--out", str(out_dir), "--overwrite", "--quiet"]
    subprocess.run(command, check=True, env=bench_record.mpi_env())
    with open(out_dir / "stats.csv") as f:
        rows = list(csv.DictReader(f))
    return command, rows


def measure(args, label, scene, extra, work):
    samples = []
    for r in range(args.runs):
        command, rows = one_run(args, scene, extra, work / f"run{r}")
        samples.append(rows)
    command = [("OUT" if c == str(work / f"run{args.runs - 1}") else c) for c in command]
    command = [("SCENE_WITHOUT_SOLVER.toml" if c == scene else c) for c in command]
    ms = statistics.median(statistics.mean(float(x["wall_ms"]) for x in rows) for rows in samples)
    its = [int(x["iterations"]) for x in samples[0]]
    errors = [x["error_estimate"] for x in samples[0]]
    return {"label": label, "command": " ".join(command), "ms": ms, "iterations": its,
            "errors": errors, "samples": [[float(x["wall_ms"]) for x in rows] for rows in samples]}


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--descent", default="build/src/app/descent")
    parser.add_argument("--mpiexec", default="mpiexec")
    parser.add_argument("--ranks", type=int, default=2)
    parser.add_argument("--frames", type=int, default=5)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--out", default="-")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        untuned = work / "helix_no_solver.toml"
        untuned.write_text(without_solver_table((ROOT / "jobs" / "helix.toml").read_text()))
        results = [measure(args, "main job (as before: it sets its target)", None, [], work),
                   measure(args, "no [solver], 96 a step (before)", str(untuned),
                           ["--set", "solver.iterations=96"], work),
                   measure(args, "no [solver], default target (after)", str(untuned), [], work)]
    lines = ["# Default accuracy: cost on the main job and on the helix without [solver]", "",
             f"Machine: {bench_record.cpu_model()}, {subprocess.check_output(['nproc']).decode().strip()}"
             " logical cores; shared with other builds while measured (timings are noisy).",
             f"{args.ranks} MPI ranks x 1 thread, {args.frames} frames a run, median over "
             f"{args.runs} runs of the mean ms per frame (stats.csv wall_ms).",
             f"Command: `/usr/bin/python3 bench/default_accuracy.py --descent {args.descent}`",
             "SCENE_WITHOUT_SOLVER.toml is jobs/helix.toml without its [solver] table; before"
             " the change such a scene ran 96 iterations a step, as `--set"
             " solver.iterations=96` runs it now.",
             "", "| case | ms / frame | iterations per step (run 1) | estimated error per step |",
             "| --- | --- | --- | --- |"]
    for r in results:
        lines.append(f"| {r['label']} | {r['ms']:.0f} | {' '.join(map(str, r['iterations']))} | "
                     f"{' '.join(r['errors'])} |")
    lines += ["", "Commands and every run's ms per frame:", ""]
    for r in results:
        lines.append(f"- {r['label']}: `{r['command']}`: "
                     + "; ".join(" ".join(f"{x:.0f}" for x in s) for s in r["samples"]))
    bench_record.write_report(lines, args.out)


if __name__ == "__main__":
    main()
