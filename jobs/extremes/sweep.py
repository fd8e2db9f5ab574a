#!/usr/bin/env python3
"""The full extremes sweep (issue 6): every case of tests/extremes/extreme_cases.cpp
for every model, in float and double, on 1 and 3 ranks, through the
descent_extremes driver; then the markdown table and the plots.

    python3 jobs/extremes/sweep.py --build build-extremes
    python3 jobs/extremes/sweep.py --build build --cases dt_1,E_1e11 --ranks 1

Results go to bench/results/extremes/ (results.jsonl, table.md, *.png); the
cached converged references to --work (not committed). The 1-rank runs of a
case come first and make its references (Newton when the build has
solver.method = "newton", else a long Chebyshev run), so the 3-rank runs
compare with the same ones. Standard library only; the plots need
matplotlib, which tools/extremes_plots.py looks for (it says so when it is
missing; /usr/bin/python3 has it on the project's machines).
"""
import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "bench"))
import bench_record  # noqa: E402  (the machine, as every benchmark records it)


def run_case(args, case, ranks):
    command = [args.mpiexec, "-n", str(ranks), "--oversubscribe",
               str(Path(args.build) / "tests" / "extremes" / "descent_extremes"),
               "--case", case, "--models", args.models, "--precisions", args.precisions,
               "--reference-dir", str(Path(args.work) / "references"),
               "--reference", args.reference]
    env = dict(os.environ, OMP_NUM_THREADS="1")
    start = time.time()
    try:
        done = subprocess.run(command, capture_output=True, text=True, env=env,
                              timeout=args.timeout)
    except subprocess.TimeoutExpired:
        print(f"  {case} on {ranks} rank(s): timed out after {args.timeout} s", flush=True)
        return [{"case": case, "ranks": ranks, "error": f"timed out after {args.timeout} s"}]
    rows = [json.loads(line) for line in done.stdout.splitlines() if line.startswith("{")]
    print(f"  {case} on {ranks} rank(s): {len(rows)} runs in {time.time() - start:.1f} s"
          f"{'' if done.returncode == 0 else f' (exit {done.returncode})'}", flush=True)
    if done.returncode != 0:
        sys.stderr.write(done.stderr[-2000:])
        rows.append({"case": case, "ranks": ranks,
                     "error": f"exit {done.returncode}: {done.stderr.strip()[-300:]}"})
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default="build", help="build directory holding the driver")
    parser.add_argument("--out", default=str(ROOT / "bench" / "results" / "extremes"))
    parser.add_argument("--work", default=str(ROOT / "out" / "extremes"),
                        help="cache of references (not committed)")
    parser.add_argument("--cases", default="all", help="comma-separated, or all")
    parser.add_argument("--models", default="all")
    parser.add_argument("--precisions", default="float,double")
    parser.add_argument("--ranks", default="1,3")
    parser.add_argument("--reference", default="auto", choices=["auto", "newton", "chebyshev"])
    parser.add_argument("--mpiexec", default="mpiexec")
    parser.add_argument("--timeout", type=int, default=1800, help="seconds per driver launch")
    parser.add_argument("--resume", action="store_true",
                        help="keep results.jsonl and skip (case, ranks) already in it")
    args = parser.parse_args()

    driver = Path(args.build) / "tests" / "extremes" / "descent_extremes"
    if not driver.exists():
        sys.exit(f"no driver at {driver}: cmake --build {args.build} --target descent_extremes")
    cases = args.cases.split(",") if args.cases != "all" else subprocess.run(
        [str(driver), "--list"], capture_output=True, text=True, check=True).stdout.split()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    results = out / "results.jsonl"
    done = set()
    if args.resume and results.exists():
        for line in results.read_text().splitlines():
            row = json.loads(line)
            done.add((row["case"], row["ranks"]))
    elif results.exists():
        results.unlink()

    start = time.time()
    with results.open("a") as sink:
        for case in cases:
            for ranks in (int(r) for r in args.ranks.split(",")):
                if (case, ranks) in done:
                    continue
                for row in run_case(args, case, ranks):
                    sink.write(json.dumps(row) + "\n")
                sink.flush()
    print(f"sweep: {time.time() - start:.0f} s; {results}")
    meta = {"date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
            "cpu": bench_record.cpu_model(), "cores": os.cpu_count(), "reference": args.reference}
    (out / "machine.json").write_text(json.dumps(meta, indent=1) + "\n")
    subprocess.run([sys.executable, str(ROOT / "tools" / "extremes_table.py"), str(out)],
                   check=True)
    # The plots want matplotlib, which this interpreter may lack.
    for python in (sys.executable, "/usr/bin/python3"):
        if subprocess.run([python, "-c", "import matplotlib"], capture_output=True).returncode == 0:
            subprocess.run([python, str(ROOT / "tools" / "extremes_plots.py"), str(out)],
                           check=True)
            break
    else:
        print("sweep: no matplotlib in this python or /usr/bin/python3: no plots")


if __name__ == "__main__":
    main()
