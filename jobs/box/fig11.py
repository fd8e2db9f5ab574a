#!/usr/bin/env python3
"""Paper 1, Fig. 11: force-stretch curves of a box under uniaxial load.

For each model, quasi-static solves of jobs/box/uniaxial.toml at loads from
the one that compresses it to --stretch-min to the one that stretches it to
--stretch-max (taken from the analytic curve of tools/uniaxial_reference.py),
then the measured stretch of the top face against the analytic force at that
stretch. Writes DIR/fig11_<model>.csv (model,force,area,stretch), prints the
worst relative force error per model, and with --check TOL exits 1 when a
well-defined point is off by more than TOL.

  python3 jobs/box/fig11.py --out out/fig11                  # all models
  python3 jobs/box/fig11.py --models stvk neo_hookean --check 0.005
Plot: /usr/bin/python3 tools/plot_force_stretch.py out/fig11/fig11_*.csv --young 1e5 --poisson 0.3 --c2 5e3 --c3 2
"""
import argparse
import csv
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
import uniaxial_reference as ref  # noqa: E402

MODELS = ["stvk", "neo_hookean", "mooney_rivlin", "fung", "corotated", "arap"]
SCENE = ROOT / "jobs/box/uniaxial.toml"
AREA = 1.0    # undeformed top face of the unit box, m^2
HEIGHT = 1.0  # along the load axis, m


def run(binary, model, material, force, frames, iterations, cells, out_dir, ranks):
    """One ramped run; returns [(force, stretch)] per frame."""
    extra = []
    if model in ("mooney_rivlin", "fung"):
        extra += ["--set", f"material.c2={material.c2!r}"]
    if model == "fung":
        extra += ["--set", f"material.c3={material.c3!r}"]
    cmd = [str(binary), "run", str(SCENE), "--quiet", "--overwrite", "--out", str(out_dir), *extra,
           "--set", f'material.model="{model}"', "--set", f"material.young={material.young!r}",
           "--set", f"material.poisson={material.poisson!r}", "--set", f"load.0.force=[0.0, {force!r}, 0.0]",
           "--set", f"load.0.ramp={float(frames)}", "--set", f"time.frames={frames}",
           "--set", f"solver.iterations={iterations}", "--set", f"mesh.box.cells=[{cells}, {cells}, {cells}]"]
    if ranks > 1:
        cmd = ["mpiexec", "-n", str(ranks), "--oversubscribe"] + cmd
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    subprocess.run(cmd, check=True, env=env)
    with open(out_dir / "stats.csv") as f:
        return [(float(r["load0_force_y"]), 1.0 + float(r["load0_disp_y"]) / HEIGHT)
                for r in csv.DictReader(f)]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--binary", type=Path, default=ROOT / "build/src/app/descent")
    parser.add_argument("--models", nargs="+", default=MODELS, choices=MODELS)
    parser.add_argument("--young", type=float, default=1e5)
    parser.add_argument("--poisson", type=float, default=0.3)
    parser.add_argument("--c2", type=float, default=5e3)
    parser.add_argument("--c3", type=float, default=2.0)
    parser.add_argument("--stretch-min", type=float, default=0.7)
    parser.add_argument("--stretch-max", type=float, default=2.0)
    parser.add_argument("--branches", nargs="+", default=["tension", "compression"],
                        choices=["tension", "compression"])
    parser.add_argument("--frames", type=int, default=16, help="load steps per branch")
    parser.add_argument("--iterations", type=int, default=4000)
    parser.add_argument("--cells", type=int, default=3)
    parser.add_argument("--ranks", type=int, default=1)
    parser.add_argument("--out", type=Path, default=ROOT / "out/fig11")
    parser.add_argument("--check", type=float, help="fail above this relative force error")
    args = parser.parse_args()

    material = ref.Material(args.young, args.poisson, args.c2, args.c3)
    args.out.mkdir(parents=True, exist_ok=True)
    worst_overall = 0.0
    print(f"{'model':15s} {'points':>6s} {'worst |dF|/F':>13s}  not well-defined  inverted")
    failed_branch = False
    for model in args.models:
        points = []
        targets = {"tension": args.stretch_max, "compression": args.stretch_min}
        for target in (targets[b] for b in args.branches):
            end = ref.uniaxial_point(model, target, material)
            if not end.well_defined:
                print(f"  {model}: stretch {target} is not well-defined; that branch is skipped",
                      file=sys.stderr)
                continue
            force = end.nominal_stress * AREA
            points += run(args.binary, model, material, force, args.frames, args.iterations, args.cells,
                          args.out / f"{model}_{target}", args.ranks)
        rows, worst, undefined, inverted = [], 0.0, 0, 0
        for force, stretch in points:
            rows.append({"model": model, "force": force, "area": AREA, "stretch": stretch})
            if stretch <= 0:
                # The box went through itself: under a dead push with no floor an
                # invertible model has an inverted equilibrium, off the uniaxial branch.
                inverted += 1
                continue
            analytic = ref.uniaxial_point(model, stretch, material)
            if not analytic.well_defined:
                undefined += 1
                continue
            worst = max(worst, abs(force - AREA * analytic.nominal_stress) / abs(force))
        with open(args.out / f"fig11_{model}.csv", "w", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=["model", "force", "area", "stretch"])
            writer.writeheader()
            writer.writerows(rows)
        print(f"{model:15s} {len(rows):6d} {worst:13.2e}  {undefined:16d}  {inverted}")
        worst_overall = max(worst_overall, worst)
        failed_branch = failed_branch or inverted > 0
    if args.check is not None and worst_overall > args.check:
        sys.exit(f"fig11: worst relative force error {worst_overall:.3e} exceeds {args.check}")
    if args.check is not None and failed_branch:
        sys.exit("fig11: the box left the uniaxial branch (inverted) at some load")


if __name__ == "__main__":
    main()
