#!/usr/bin/env python3
"""Paper 1, Fig. 10: a box with its bottom face fixed and its top face
stretched, compressed and twisted, for every model (jobs/box/deform.toml).

Runs 3 deformations x 6 models into OUT/<model>_<mode>/ (frames.h5/.xdmf,
stats.csv), prints one line per run (ms per frame, rollbacks, finite or not),
and, when h5py and matplotlib are importable (Debian's /usr/bin/python3 with
python3-h5py and python3-matplotlib), draws the last frame of every run into
OUT/fig10.png.

  python3 jobs/box/fig10.py --out out/fig10
  /usr/bin/python3 jobs/box/fig10.py --out out/fig10 --models neo_hookean arap
"""
import argparse
import csv
import math
import os
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SCENE = ROOT / "jobs/box/deform.toml"
MODELS = ["stvk", "neo_hookean", "mooney_rivlin", "fung", "corotated", "arap"]
MODES = {
    "stretch": ["--set", "fixed.1.motion.velocity=[0.0, 1.0, 0.0]"],       # to 2x
    "compress": ["--set", "fixed.1.motion.velocity=[0.0, -0.5, 0.0]"],     # to 0.5x
    "twist": ["--set", 'fixed.1.motion.kind="rotate"',
              "--set", f"fixed.1.motion.angular_velocity={math.pi}"],      # by pi
}
PARAMETERS = {"mooney_rivlin": ["--set", "material.c2=5e3"],
              "fung": ["--set", "material.c2=5e3", "--set", "material.c3=2.0"]}


def run(binary, model, mode, out_dir):
    cmd = [str(binary), "run", str(SCENE), "--quiet", "--overwrite", "--out", str(out_dir),
           "--set", f'material.model="{model}"', *PARAMETERS.get(model, []), *MODES[mode]]
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    subprocess.run(cmd, check=True, env=env)
    with open(out_dir / "stats.csv") as f:
        rows = list(csv.DictReader(f))
    ms = sum(float(r["wall_ms"]) for r in rows) / len(rows)
    rollbacks = sum(int(r["rollbacks"]) for r in rows)
    finite = all(math.isfinite(float(r["energy"])) for r in rows)
    return ms, rollbacks, finite


def boundary_triangles(tets):
    """Faces used by one tet only: the surface to draw."""
    count = {}
    for t in tets:
        for face in ((t[1], t[2], t[3]), (t[0], t[3], t[2]), (t[0], t[1], t[3]), (t[0], t[2], t[1])):
            key = tuple(sorted(int(v) for v in face))
            count[key] = (count.get(key, (0, face))[0] + 1, face)
    return [face for n, face in count.values() if n == 1]


def draw(out, runs):
    try:
        import h5py
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        from mpl_toolkits.mplot3d.art3d import Poly3DCollection
    except ImportError as e:
        print(f"fig10: no picture ({e}); use Debian's /usr/bin/python3 with python3-h5py, python3-matplotlib")
        return
    models = sorted({m for m, _ in runs}, key=MODELS.index)
    fig = plt.figure(figsize=(2.4 * len(models), 2.8 * len(MODES)))
    for col, model in enumerate(models):
        for row, mode in enumerate(MODES):
            ax = fig.add_subplot(len(MODES), len(models), row * len(models) + col + 1,
                                 projection="3d")
            with h5py.File(out / f"{model}_{mode}" / "frames.h5", "r") as f:
                last = sorted(f["frames"].keys())[-1]
                x = f["frames"][last]["positions"][()]
                faces = boundary_triangles(f["mesh"]["tets"][()])
            # Drawn with y up: plot axes (x, z, y).
            polys = [[(x[v, 0], x[v, 2], x[v, 1]) for v in face] for face in faces]
            ax.add_collection3d(Poly3DCollection(polys, facecolor="#8fb3d9", edgecolor="#1f3b5c",
                                                 linewidths=0.3))
            ax.set_xlim(-0.5, 1.5)
            ax.set_ylim(-0.5, 1.5)
            ax.set_zlim(0, 2)
            ax.set_box_aspect((1, 1, 1))
            ax.view_init(elev=15, azim=-60)
            ax.set_axis_off()
            ax.set_title(f"{model}\n{mode}", fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "fig10.png", dpi=90)
    print(f"wrote {out / 'fig10.png'}")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--binary", type=Path, default=ROOT / "build/src/app/descent")
    parser.add_argument("--models", nargs="+", default=MODELS, choices=MODELS)
    parser.add_argument("--out", type=Path, default=ROOT / "out/fig10")
    args = parser.parse_args()
    runs = []
    print(f"{'model':15s} {'mode':9s} {'ms/frame':>9s} {'rollbacks':>9s}  finite")
    for model in args.models:
        for mode in MODES:
            ms, rollbacks, finite = run(args.binary, model, mode, args.out / f"{model}_{mode}")
            runs.append((model, mode))
            print(f"{model:15s} {mode:9s} {ms:9.1f} {rollbacks:9d}  {finite}", flush=True)
    draw(args.out, runs)


if __name__ == "__main__":
    main()
