#!/usr/bin/env python3
"""The paper's Table 1 on a GPU: ms per frame of `descent run --backend cuda`.

The double helix at the paper's four sizes (presets 41k, 82k, 158k, 316k) and
a ~10M-tet helix, 96 iterations per frame, h = 1/30 s, float, gather and
scatter assembly; each figure the median of --runs runs, each run's figure
the median frame time (stats.csv wall_ms) over frames 2..N (frame 1 captures
the graphs). Also, from the same runs, the share of iteration time spent in
energy checks and rollbacks, and rollbacks per frame; from
descent_kernel_bench the element kernel's bandwidth against the GPU's peak;
and ms per frame with 2 ranks sharing the GPU (the exchange's cost).

Writes bench/results/gpu_table1.md with the GPU name, driver and date.
Never run on a machine without a GPU: the script refuses (no made-up numbers).

  python3 bench/gpu_table1.py --build build-gpu                # everything
  python3 bench/gpu_table1.py --build build-gpu --sizes 316k --runs 3
"""
import argparse
import csv
import os
import re
import statistics
import subprocess
import sys
import tempfile
from datetime import datetime, timezone
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

# Paper 1, Table 1 (GTX TITAN X): ms per frame at 96 iterations.
PAPER_MS = {"41k": 27.5, "82k": 38.5, "158k": 65.4, "316k": 122.0}
SIZES = {"41k": ("preset", "41k"), "82k": ("preset", "82k"), "158k": ("preset", "158k"),
         "316k": ("preset", "316k"), "10m": ("resolution", "15.1")}
# Peak DRAM bandwidth by product name (GB/s), for the roofline fraction;
# --peak-gbs overrides.
PEAK_GBS = [("H200", 4800.0), ("H100 SXM", 3350.0), ("H100 80GB HBM3", 3350.0),
            ("H100 PCIe", 2000.0), ("H100", 3350.0), ("A100-SXM4-80GB", 2039.0),
            ("A100", 1555.0), ("L40S", 864.0), ("RTX 4090", 1008.0)]


def env(ranks=1):
    # The host's per-step loops (initial guess, velocities) use OpenMP: the
    # machine's cores shared among the ranks.
    threads = max(1, (os.cpu_count() or 1) // ranks)
    return dict(os.environ, OMP_NUM_THREADS=str(threads), OMPI_ALLOW_RUN_AS_ROOT="1",
                OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")


def gpu_info():
    try:
        out = subprocess.run(["nvidia-smi", "--query-gpu=name,driver_version,memory.total",
                              "--format=csv,noheader"], capture_output=True, text=True,
                             check=True).stdout.strip().splitlines()
        name, driver, memory = [x.strip() for x in out[0].split(",")]
        return name, driver, memory
    except (OSError, subprocess.CalledProcessError, IndexError, ValueError):
        return None


def scene_text(size):
    kind, value = SIZES[size]
    base = (ROOT / "jobs/helix.toml").read_text()
    if kind == "resolution":
        base = re.sub(r'^preset = .*$', f"resolution = {value}", base, flags=re.M)
    else:
        base = re.sub(r'^preset = .*$', f'preset = "{value}"', base, flags=re.M)
    return base


def run_descent(binary, scene, out, frames, assembly, ranks, share, backend="cuda"):
    cmd = []
    if ranks > 1:
        cmd += ["mpiexec", "-n", str(ranks), "--oversubscribe", "--bind-to", "none"]
    cmd += [str(binary), "run", str(scene), "--backend", backend, "--precision", "float",
            "--assembly", assembly, "--overwrite", "--out", str(out),
            "--set", "solver.iterations=96", "--set", "solver.accuracy=0",
            "--set", 'solver.preconditioner="jacobi"',  # the paper's method
            "--set", "time.dt=0.03333333333333333",
            "--set", f"time.frames={frames}", "--set", f"output.every={frames + 1}",
            "--set", "output.checkpoint_every=0"]
    if share:
        cmd.append("--share-device")
    text = subprocess.run(cmd, env=env(ranks), check=True, capture_output=True, text=True).stdout
    with open(out / "stats.csv") as f:
        rows = list(csv.DictReader(f))
    wall = [float(r["wall_ms"]) for r in rows[1:]] or [float(rows[0]["wall_ms"])]
    rollbacks = statistics.mean(int(r["rollbacks"]) for r in rows)
    tets = re.search(r"([0-9]+) tets on", text)
    share_match = re.search(r"energy checks and rollbacks ([0-9.]+)% of step time", text)
    memory = re.search(r"([0-9]+) bytes per tet, ([0-9]+) per vertex", text)
    return {"ms": statistics.median(wall), "rollbacks": rollbacks,
            "tets": int(tets.group(1)) if tets else 0,
            "check_share": float(share_match.group(1)) if share_match else float("nan"),
            "bytes_tet": int(memory.group(1)) if memory else 0,
            "bytes_vertex": int(memory.group(2)) if memory else 0,
            "command": " ".join(cmd).replace(f"{ROOT}/", "")}


def median_of_runs(runs, key):
    return statistics.median(r[key] for r in runs)


def kernel_bench(binary, size, backend="cuda"):
    kind, value = SIZES[size]
    flag = "--preset" if kind == "preset" else "--resolution"
    text = subprocess.run([str(binary), flag, value, "--precision", "float", "--repeats", "50",
                           "--backend", backend],
                          env=env(), check=True, capture_output=True, text=True).stdout
    rows = []
    for line in text.splitlines():
        if line.startswith("kernel "):
            rows.append(dict(kv.split("=", 1) for kv in line.split()[1:]))
    return rows


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--build", type=Path, default=ROOT / "build-gpu")
    p.add_argument("--sizes", nargs="+", default=list(SIZES), choices=list(SIZES))
    p.add_argument("--assemblies", nargs="+", default=["gather", "scatter"])
    p.add_argument("--runs", type=int, default=5)
    p.add_argument("--frames", type=int, default=10)
    p.add_argument("--two-rank-sizes", nargs="*", default=["316k", "10m"])
    p.add_argument("--peak-gbs", type=float, default=0.0)
    p.add_argument("--output", type=Path, default=ROOT / "bench/results/gpu_table1.md")
    p.add_argument("--smoke", action="store_true",
                   help="check the script itself without a GPU: the CPU backend (the same "
                        "engine on the host), output marked as such; needs --output")
    a = p.parse_args()

    backend = "cpu" if a.smoke else "cuda"
    info = gpu_info()
    if a.smoke:
        if a.output == p.get_default("output"):
            sys.exit("gpu_table1: --smoke writes no GPU results: give --output elsewhere")
        info = ("NO GPU: smoke test of the script on the CPU backend, not GPU figures",
                "-", "-")
    if info is None:
        sys.exit("gpu_table1: nvidia-smi sees no GPU here; nothing measured, nothing written")
    gpu, driver, gpu_memory = info
    descent = a.build / "src/app/descent"
    bench = a.build / "src/backends/descent_kernel_bench"
    version = subprocess.run([str(descent), "--version"], env=env(), capture_output=True,
                             text=True).stdout
    if not a.smoke and "\ndevice 0:" not in version:
        sys.exit(f"gpu_table1: descent sees no usable device:\n{version}")
    peak = a.peak_gbs or next((g for n, g in PEAK_GBS if n in gpu), 0.0)

    lines = [f"# Table 1 on {gpu}", "",
             f"- GPU: {gpu} ({gpu_memory}), driver {driver}; date "
             f"{datetime.now(timezone.utc).strftime('%Y-%m-%d %H:%M UTC')}",
             "- " + version.strip().replace("\n", "; "),
             "- scene: jobs/helix.toml with its mesh.helix.preset set per row (10m: "
             f"mesh.helix.resolution = {SIZES['10m'][1]} instead)",
             f"- 96 iterations per frame, h = 1/30 s, float, {a.frames} frames per run; each "
             f"figure the median of {a.runs} runs, each run's the median of frames 2..{a.frames}",
             ""]
    table = ["| helix | tets | assembly | ms/frame | paper (TITAN X) | checks+rollbacks share "
             "| rollbacks/frame | bytes/tet | bytes/vertex |", "|" + "---|" * 9]
    commands = []
    results = {}
    with tempfile.TemporaryDirectory() as tmp:
        for size in a.sizes:
            scene = Path(tmp) / f"helix_{size}.toml"
            scene.write_text(scene_text(size))
            for assembly in a.assemblies:
                runs = [run_descent(descent, scene, Path(tmp) / f"out_{size}_{assembly}", a.frames,
                                    assembly, 1, False, backend) for _ in range(a.runs)]
                r = runs[0]
                ms = median_of_runs(runs, "ms")
                results[(size, assembly)] = ms
                paper = PAPER_MS.get(size)
                table.append(f"| {size} | {r['tets']:,} | {assembly} | {ms:.3f} | "
                             f"{paper if paper else '-'} | {median_of_runs(runs, 'check_share'):.1f}% | "
                             f"{median_of_runs(runs, 'rollbacks'):.2f} | {r['bytes_tet']} | "
                             f"{r['bytes_vertex']} |")
                commands.append(r["command"])
                print(table[-1], flush=True)
        lines += table + [""]

        two = ["## 2 ranks sharing the GPU (the exchange's cost)", "",
               "| helix | assembly | 1 rank ms/frame | 2 ranks ms/frame |", "|---|---|---|---|"]
        for size in [s for s in a.two_rank_sizes if s in a.sizes]:
            scene = Path(tmp) / f"helix_{size}.toml"
            assembly = a.assemblies[0]
            runs = [run_descent(descent, scene, Path(tmp) / f"out2_{size}", a.frames, assembly, 2,
                                True, backend) for _ in range(a.runs)]
            two.append(f"| {size} | {assembly} | {results[(size, assembly)]:.3f} | "
                       f"{median_of_runs(runs, 'ms'):.3f} |")
            commands.append(runs[0]["command"])
            print(two[-1], flush=True)
        lines += two + [""]

    kern = ["## Element kernel (descent_kernel_bench, float)", "",
            "Bytes are what one pass requests: tet ids, rest data, the 12 corner coordinates "
            "per tet and its outputs (scatter atomics counted as read + write); the fraction is "
            f"of the GPU's peak DRAM bandwidth ({peak:.0f} GB/s" +
            (", from its product name)" if not a.peak_gbs else ", given)"), "",
            "| helix | assembly | diagonal | us/pass | GB/s | of peak |", "|---|---|---|---|---|---|"]
    for size in a.sizes:
        for row in kernel_bench(bench, size, backend):
            gbs = float(row["gbs"])
            fraction = f"{100 * gbs / peak:.0f}%" if peak else "-"
            kern.append(f"| {size} | {row['assembly']} | {'yes' if row['diag'] == '1' else 'no'} | "
                        f"{float(row['us']):.1f} | {gbs:.0f} | {fraction} |")
            print(kern[-1], flush=True)
    lines += kern + ["", "## Commands", ""] + [f"    {c}" for c in commands] + [""]
    a.output.parent.mkdir(parents=True, exist_ok=True)
    a.output.write_text("\n".join(lines))
    print(f"gpu_table1: wrote {a.output}")


if __name__ == "__main__":
    main()
