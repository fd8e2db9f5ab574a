#!/usr/bin/env python3
"""What a mesh's numbering costs the iteration, and what partition.reorder wins back.

For each mesh, runs `descent run` with partition.reorder = "none" (each rank
keeps the input's order) and "rcm" (reverse Cuthill-McKee within each vertex
class; src/partition/local_order.hpp), alternately run by run, and records
the median of the solver's own ns per tet-iteration (step time only) and the
set-up's "local order" time, with the machine and the commands.

Meshes: the generated double helix (the numbering the generator gives, along
the helix), the same helix written to a file and numbered at random
(bench/shuffle_mesh.py), at 82K and 316K tets, and the meshes of
../shared/meshes when that directory exists (skipped with a message when
not). The iteration is the paper's: Jacobi, fixed Chebyshev parameters, 96
iterations per step, no accuracy target, so every run does the same work.

  python3 bench/locality.py                       # 5 runs, 1 and 2 ranks
  python3 bench/locality.py --runs 3 --configs 1 --meshes helix_82k_generated helix_82k_shuffled
  python3 bench/locality.py --main-job            # the built-in job's ms per frame instead

--main-job runs the built-in job (jobs/helix.toml: multilevel preconditioner,
accuracy 1e-2) for --frames frames and records its ms per frame, none
against rcm, in bench/results/locality_main_job.md.
"""
import argparse
import re
import statistics
import subprocess
import sys
from pathlib import Path

from bench_record import machine_lines, mpi_env, run_command, sample_list, write_report

ROOT = Path(__file__).resolve().parent.parent
SHARED = ROOT.parent / "shared" / "meshes"
WORK = ROOT / "out" / "bench" / "locality"

# The meshes of ../shared/meshes read as they are (README there); the raptor
# is VTK XML, which descent does not read.
SHARED_MESHES = {
    "armadillo_10k": "armadillo_10k.node",
    "armadillo_13k_ipc": "armadillo_13k_ipc.msh",
    "bunny_ipc": "bunny_ipc.msh",
    "dragon_16k": "dragon_16k.mesh",
}

# The iteration every case runs.
SOLVER_KEYS = ['solver.preconditioner="jacobi"', 'solver.chebyshev_parameters="fixed"', "solver.rho=0.96",
               "solver.chebyshev_delay=10", "solver.alpha_max=1", "solver.accuracy=0",
               "solver.iterations=96"]


def descent(binary, args, ranks=1):
    cmd = ["mpiexec", "-n", str(ranks), "--oversubscribe", "--bind-to", "none", str(binary)] + args
    return run_command(cmd, ROOT, mpi_env())


def helix_file(binary, preset, shuffled):
    """The helix at `preset` as a MEDIT file, in the generator's numbering or
    shuffled; made once per build directory."""
    WORK.mkdir(parents=True, exist_ok=True)
    plain = WORK / f"helix_{preset}.mesh"
    if not plain.exists():
        descent(binary, ["mesh", "--set", f'mesh.helix.preset="{preset}"', "-o", str(plain)])
    if not shuffled:
        return plain
    mixed = WORK / f"helix_{preset}_shuffled.mesh"
    if not mixed.exists():
        subprocess.run([sys.executable, str(ROOT / "bench/shuffle_mesh.py"), str(plain), str(mixed)],
                       check=True)
    return mixed


def scene_file(binary, name):
    """A scene for mesh `name` (written under out/bench/locality); None when
    its file is absent. Every case falls freely under gravity, nothing held,
    so no case depends on where a fixed region lands."""
    if name.startswith("helix_"):
        preset = name.split("_")[1]
        if name.endswith("_generated"):
            mesh = f'generator = "double_helix"\n\n[mesh.helix]\npreset = "{preset}"'
        else:
            mesh = f'file = "{helix_file(binary, preset, name.endswith("_shuffled"))}"'
    else:
        path = SHARED / SHARED_MESHES[name]
        if not path.exists():
            print(f"skipped {name}: {path} is absent (the shared meshes are not part of this repository)")
            return None
        mesh = f'file = "{path}"'
    scene = WORK / f"{name}.toml"
    scene.write_text(f"""gravity = [0.0, -9.81, 0.0]

[mesh]
{mesh}

[material]
model = "neo_hookean"
young = 1e6
poisson = 0.3
density = 1000

[time]
dt = 0.03333333333333333

[output]
dir = "{WORK / 'run'}"
""")
    return scene


def run_once(binary, ranks, scene, reorder, frames):
    args = ["run", str(scene), "--overwrite", "--set", f"time.frames={frames}",
            "--set", f"output.every={frames + 1}", "--set", f'partition.reorder="{reorder}"']
    for key in SOLVER_KEYS:
        args += ["--set", key]
    text, command = descent(binary, args, ranks)
    ns = re.search(r"([0-9.]+) ns per tet-iteration", text)
    order = re.search(r"local order \(\w+\) ([0-9.]+) s", text)
    tets = re.search(r": [0-9]+ vertices, ([0-9]+) tets", text)
    if not (ns and order and tets):
        sys.exit(f"no ns per tet-iteration, local order or tets line in the output of {command}:\n{text}")
    return float(ns.group(1)), float(order.group(1)), int(tets.group(1)), command


def main_job(args):
    """The built-in job's ms per frame, none against rcm, run alternately."""
    samples = {"none": [], "rcm": []}
    for ranks in (int(c) for c in args.configs):
        for run in range(args.runs):
            for reorder in ("none", "rcm"):
                text, command = descent(args.binary, [
                    "run", "--overwrite", "--out", str(WORK / "run"), "--set", f"time.frames={args.frames}",
                    "--set", f"output.every={args.frames + 1}", "--set", f'partition.reorder="{reorder}"'], ranks)
                ms = float(re.search(r"([0-9.]+) ms/frame", text).group(1))
                samples[reorder].append((ranks, ms))
                print(f"main job {ranks} rank(s) {reorder}: run {run + 1}/{args.runs}: {ms:.1f} ms/frame",
                      flush=True)
    lines = [
        "# Locality: the built-in job's ms per frame by local numbering (partition.reorder)",
        "",
        *machine_lines(),
        f"- command (last run; ranks and partition.reorder varied): `{command}`",
        f"- figure: the run's own ms/frame over {args.frames} frames of jobs/helix.toml (82K helix, multilevel, "
        f"accuracy 1e-2), median of {args.runs} runs, \"none\" and \"rcm\" alternately; 1 OpenMP thread per rank",
        "",
        "| ranks | none ms/frame | rcm ms/frame | none / rcm | samples none | samples rcm |",
        "| --- | --- | --- | --- | --- | --- |",
    ]
    for ranks in (int(c) for c in args.configs):
        none = [ms for r, ms in samples["none"] if r == ranks]
        rcm = [ms for r, ms in samples["rcm"] if r == ranks]
        lines.append(f"| {ranks} | {statistics.median(none):.1f} | {statistics.median(rcm):.1f} | "
                     f"{statistics.median(none) / statistics.median(rcm):.2f} | "
                     f"{sample_list(none)} | {sample_list(rcm)} |")
    out = ROOT / "bench/results/locality_main_job.md"
    write_report(lines, str(out))
    print(f"wrote {out}")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--binary", default=ROOT / "build/src/app/descent", type=Path)
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--frames", type=int, default=10)
    parser.add_argument("--configs", nargs="+", default=["1", "2"], help="rank counts (1 thread each)")
    parser.add_argument("--meshes", nargs="+",
                        default=["helix_82k_generated", "helix_82k_file", "helix_82k_shuffled",
                                 "helix_316k_generated", "helix_316k_shuffled"] + list(SHARED_MESHES))
    parser.add_argument("--output", default=ROOT / "bench/results/locality.md")
    parser.add_argument("--main-job", action="store_true", help="the built-in job's ms per frame instead")
    args = parser.parse_args()
    if args.main_job:
        main_job(args)
        return

    rows, command = [], ""
    for name in args.meshes:
        scene = scene_file(args.binary, name)
        if scene is None:
            continue
        for ranks in (int(c) for c in args.configs):
            samples = {"none": [], "rcm": []}
            order_seconds, tets = [], 0
            for run in range(args.runs):
                for reorder in ("none", "rcm"):
                    ns, seconds, tets, command = run_once(args.binary, ranks, scene, reorder, args.frames)
                    samples[reorder].append(ns)
                    if reorder == "rcm":
                        order_seconds.append(seconds)
                    print(f"{name} {ranks} rank(s) {reorder}: run {run + 1}/{args.runs}: {ns:.1f} ns",
                          flush=True)
            none, rcm = statistics.median(samples["none"]), statistics.median(samples["rcm"])
            rows.append((name, tets, ranks, none, rcm, statistics.median(order_seconds), samples))

    lines = [
        "# Locality: ns per tet-iteration by local numbering (partition.reorder)",
        "",
        *machine_lines(),
        f"- command (last run; scene, ranks and partition.reorder varied; the scenes are written by this "
        f"script: the mesh, neo-Hookean E = 1e6, nu = 0.3, rho = 1000, dt = 1/30, falling freely): `{command}`",
        f"- figure: step wall time / (tets x iterations), {args.frames} frames of 96 Jacobi-Chebyshev "
        f"iterations per run, median of {args.runs} runs; \"none\" and \"rcm\" run alternately, run by run; "
        "1 OpenMP thread per rank",
        "- reorder s: rank 0's set-up time for the renumbering (median)",
        "",
        "| mesh | tets | ranks | none ns | rcm ns | none / rcm | reorder s | samples none | samples rcm |",
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    for name, tets, ranks, none, rcm, seconds, samples in rows:
        lines.append(f"| {name} | {tets} | {ranks} | {none:.1f} | {rcm:.1f} | {none / rcm:.2f} | {seconds:.2f} | "
                     f"{sample_list(samples['none'])} | {sample_list(samples['rcm'])} |")
    write_report(lines, str(args.output))
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
