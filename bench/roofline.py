#!/usr/bin/env python3
"""The roofline of a CPU tet-iteration: what the machine allows per model and
where today's loops stand against it, in double and float.

Three measured inputs and one counted one:
  * the machine (bench/roofline/machine_rates.cpp, built with the build's own
    flags, run with the same ranks and threads as the runs judged): a STREAM
    triad over arrays as large as the run's working set, the peak of
    independent multiply-add chains the compiler vectorises, and one core's
    time per sqrt, cbrt, exp and division;
  * the operations per tet of each model's element math, counted from
    src/kernels by instantiating it on a counting real type
    (bench/roofline/op_count.cpp);
  * the bytes per tet-iteration, counted here from the loops' data layout
    (src/kernels/loops.hpp; see BYTES below);
  * the solver's own ns per tet-iteration (step time only) of `descent run`
    on the generated helix: Jacobi, fixed Chebyshev parameters, 96
    iterations per step, no accuracy target, every model.

How operations are counted: additions, subtractions and multiplications are
flops and run at the measured peak; divisions, square and cube roots and
exponentials are not counted as flops but timed: each costs the measured
time per value in lanes (kernels/cpu/lanes.hpp; cube roots and
exponentials are kernels/cube_root.hpp's and kernels/exponential.hpp's), as
the element pass takes them. Comparisons, selects and
abs/copysign/frexp/ldexp (bit operations) cost nothing in the bound. The compute bound is thus the time the operations
take at the machine's best, the memory bound the bytes at the triad's
bandwidth for a working set of the run's size; the larger applies.

  python3 bench/roofline.py                     # 82K helix, every model, 3 runs each
  python3 bench/roofline.py --runs 5 --models neo_hookean --preset 1m
  python3 bench/roofline.py --compare out/bench/before/descent   # an earlier build, run by run

--compare runs an earlier build's binary with the same keys, alternating
with this build's run by run, so that before and after are measured in one
sitting; the table gains its median and the speed-up. --samples-from REPORT
takes the runs' samples (and the earlier build's) from an earlier report of
this script instead of running the cases again, and measures the machine
and computes the bounds anew.
"""
import argparse
import re
import statistics
import sys
from pathlib import Path

from bench_record import machine_lines, mpi_env, run_command, sample_list, write_report

ROOT = Path(__file__).resolve().parent.parent
WORK = ROOT / "out" / "bench" / "roofline"

MODELS = ["stvk", "neo_hookean", "mooney_rivlin", "fung", "corotated", "arap", "neo_hookean+conversion"]
MODEL_KEYS = {"mooney_rivlin": ["material.c2=1e4"], "fung": ["material.c2=1e4", "material.c3=2.0"]}
SOLVER_KEYS = ['solver.preconditioner="jacobi"', 'solver.chebyshev_parameters="fixed"', "solver.rho=0.96",
               "solver.chebyshev_delay=10", "solver.alpha_max=1", "solver.accuracy=0", "solver.iterations=96"]
HESSIAN_INTERVAL = 32  # solver.hessian_interval: the diagonal refreshed every M iterations
CHECK_INTERVAL = 8  # solver.check_interval: the energy evaluated every 8 iterations
INDEX_BYTES = 4  # index_t

# BYTES: the compulsory traffic of one iteration of the CPU engine on one
# rank with one thread (the element results added to the vertex partials in
# tet order), in bytes, as a function of the real's size s, the tets T and
# vertices V: every array the iteration reads or writes, once (a cache that
# keeps each tet's corners and each vertex's partials between their uses;
# stores counted once, as the triad counts them).
#   element pass: 4 ids + TetRest (Dm^-1 and V: 10 reals) per tet, the
#     positions q (3 reals per vertex); with conversion the interpolant read
#     and written (2 reals)
#   assembly: the partials zeroed, read and written (3 reals per vertex,
#     three times)
#   vertex update per vertex: partials, y, q_t, force, q, q_prev, diagonal
#     (3 reals each), mass (1 real), held flags (1 byte), q_next written (3)
#   every M iterations: the diagonal's partials zeroed, read and written
#     (3 reals per vertex, three times), the floor read and diagonal
#     written (6 per vertex)
#   every check: ids, rest data and q once more, per vertex mass, y, q_t,
#     force (10 reals) and with conversion the interpolant
def bytes_per_iteration(s, tets, vertices, conversion):
    element = tets * (4 * INDEX_BYTES + 10 * s + (2 * s if conversion else 0)) + vertices * 3 * s
    assembly = vertices * 3 * s * 3
    update = vertices * (3 * s * 7 + s + 1 + 3 * s)
    refresh = (vertices * 3 * s * 3 + vertices * 9 * s) / HESSIAN_INTERVAL
    check = (tets * (4 * INDEX_BYTES + 10 * s + (s if conversion else 0)) + vertices * (3 * s + 10 * s)) / CHECK_INTERVAL
    return element + assembly + update + refresh + check


def ops_per_iteration(counts, model, tets, vertices):
    """Operations per tet-iteration from the per-tet and per-dof counts."""
    base, conversion = model.split("+")[0], model.endswith("+conversion")
    per_tet = counts[(base, "converted_gradient" if conversion else "gradient")]
    if conversion:
        diag = {k: counts[(base, "converted_gradient_diagonal")][k] - per_tet[k] for k in per_tet}
    else:
        diag = counts[(base, "diagonal")]
    energy = counts[(base, "converted_energy" if conversion else "energy")]
    total = {k: per_tet[k] + diag[k] / HESSIAN_INTERVAL + energy[k] / CHECK_INTERVAL for k in per_tet}
    total["add"] += 12 + 12 / HESSIAN_INTERVAL  # the assembly's sums
    dofs_per_tet = 3 * vertices / tets
    for kernel, every in (("update", 1), ("diagonal", HESSIAN_INTERVAL), ("energy", CHECK_INTERVAL)):
        for k, v in counts[("vertex", kernel)].items():
            total[k] += dofs_per_tet * v / every
    return total


def run(cmd, env=None):
    return run_command(cmd, ROOT, env)[0]


def build(build_dir):
    run(["cmake", "--build", str(build_dir), "--target", "roofline_op_count", "roofline_machine_rates", "descent"])


def cpu_arch(build_dir):
    """The build's DESCENT_CPU_ARCH (unset before that option existed)."""
    cache = (build_dir / "CMakeCache.txt").read_text()
    found = re.search(r"^DESCENT_CPU_ARCH:STRING=(.*)$", cache, re.M)
    return found.group(1) if found else "unset"


def op_counts(build_dir):
    counts = {}
    for line in run([str(build_dir / "bench/roofline/roofline_op_count")]).splitlines():
        if line.startswith("#"):
            continue
        model, kernel, *values = line.split()
        counts[(model, kernel)] = dict(zip(["add", "mul", "div", "sqrt", "cbrt", "exp", "compare", "other"],
                                           map(float, values)))
    return counts


def machine_rates(build_dir, ranks, mib_per_rank):
    text = run(["mpiexec", "-n", str(ranks), "--oversubscribe", "--bind-to", "none",
                str(build_dir / "bench/roofline/roofline_machine_rates"), f"{mib_per_rank:.1f}"], env=mpi_env())
    rates = {}
    for line in text.splitlines():
        key, value = line.split()
        rates[key] = value if key == "isa" else float(value)
    return rates


def measure(binary, model, precision, ranks, preset, frames):
    base = model.split("+")[0]
    args = ["mpiexec", "-n", str(ranks), "--oversubscribe", "--bind-to", "none", str(binary), "run", "--overwrite",
            "--out", str(WORK / "run"), "--precision", precision, "--set", f'mesh.helix.preset="{preset}"',
            "--set", f'material.model="{base}"', "--set", f"time.frames={frames}",
            "--set", f"output.every={frames + 1}"]
    if model.endswith("+conversion"):
        args += ["--set", "material.conversion.enabled=true"]
    for key in SOLVER_KEYS + MODEL_KEYS.get(base, []):
        args += ["--set", key]
    text = run(args, env=mpi_env())
    ns = re.search(r"([0-9.]+) ns per tet-iteration", text)
    size = re.search(r": ([0-9]+) vertices, ([0-9]+) tets", text)
    if not (ns and size):
        sys.exit(f"no ns per tet-iteration or mesh size in the output of {' '.join(args)}:\n{text}")
    return float(ns.group(1)), int(size.group(1)), int(size.group(2)), " ".join(args).replace(f"{ROOT}/", "")


def report_samples(path):
    """{(ranks, model, precision): (samples, earlier samples)}, the mesh size and the command of a report."""
    text = path.read_text()
    size = re.search(r"^Mesh: ([0-9]+) tets, ([0-9]+) vertices", text, re.M)
    command = re.search(r"^- command \(last run[^`]*`([^`]*)`", text, re.M)
    if not (size and command):
        sys.exit(f"{path}: no mesh size or command line: not a report of this script")
    found = {}
    for line in text.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) < 16 or not cells[0].isdigit() or cells[1] not in MODELS:
            continue
        parse = lambda cell: [float(x) for x in cell.split(",")] if cell else []
        found[(int(cells[0]), cells[1], cells[2])] = (parse(cells[15]), parse(cells[18]) if len(cells) > 18 else [])
    return found, int(size.group(1)), int(size.group(2)), command.group(1)


def bound(counts, rates, model, precision, tets, vertices, ranks):
    """(compute ns, memory ns, bytes, flops, the calls' ns) per tet-iteration over all ranks."""
    s = 8 if precision == "double" else 4
    ops = ops_per_iteration(counts, model, tets, vertices)
    flops = ops["add"] + ops["mul"]
    # The calls run on every core at once: one core's time divided by the ranks.
    calls = sum(ops[op] * rates[f"ns_{op}_{precision}"] for op in ("div", "sqrt", "cbrt", "exp")) / ranks
    compute = flops / rates[f"peak_GFlops_{precision}"] + calls
    nbytes = bytes_per_iteration(s, tets, vertices, model.endswith("+conversion")) / tets
    memory = nbytes / rates[f"triad_GBps_{precision}"]
    return compute, memory, nbytes, flops, calls, ops


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default=ROOT / "build", type=Path)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--frames", type=int, default=5)
    parser.add_argument("--preset", default="82k")
    parser.add_argument("--models", nargs="+", default=MODELS, choices=MODELS)
    parser.add_argument("--precisions", nargs="+", default=["double", "float"], choices=["double", "float"])
    parser.add_argument("--ranks", nargs="+", type=int, default=[1, 2], help="rank counts (1 thread each)")
    parser.add_argument("--output", default=None, help="default bench/results/roofline_<preset>.md")
    parser.add_argument("--compare", type=Path, help="an earlier build's descent, run alternately")
    parser.add_argument("--samples-from", type=Path, help="an earlier report whose samples to use")
    args = parser.parse_args()
    WORK.mkdir(parents=True, exist_ok=True)
    build(args.build)
    counts = op_counts(args.build)
    binary = args.build / "src/app/descent"

    rows, commands, rate_rows = [], [], {}
    recorded = report_samples(args.samples_from) if args.samples_from else None
    for ranks in args.ranks:
        for model in args.models:
            for precision in args.precisions:
                samples, before = [], []
                if recorded:
                    if (ranks, model, precision) not in recorded[0]:
                        sys.exit(f"{args.samples_from} has no row for {ranks} rank(s), {model}, {precision}")
                    samples, before = recorded[0][(ranks, model, precision)]
                    tets, vertices, command = recorded[1], recorded[2], recorded[3]
                for r in range(0 if recorded else args.runs):
                    if args.compare:
                        before.append(measure(args.compare, model, precision, ranks, args.preset, args.frames)[0])
                    ns, vertices, tets, command = measure(binary, model, precision, ranks, args.preset, args.frames)
                    samples.append(ns)
                    print(f"{model} {precision} {ranks} rank(s) run {r + 1}/{args.runs}: {ns:.1f} ns"
                          + (f" (earlier build {before[-1]:.1f} ns)" if before else ""), flush=True)
                commands.append(command)
                key = (ranks, precision)
                if key not in rate_rows:
                    # The triad over each rank's working set: its share of the arrays one iteration touches.
                    working_set = bytes_per_iteration(8 if precision == "double" else 4, tets, vertices, False)
                    rate_rows[key] = machine_rates(args.build, ranks, working_set / ranks / 2**20)
                rates = rate_rows[key]
                compute, memory, nbytes, flops, calls, ops = bound(counts, rates, model, precision, tets,
                                                                   vertices, ranks)
                measured = statistics.median(samples)
                limit = max(compute, memory)
                rows.append((ranks, model, precision, nbytes, flops, ops, calls, compute, memory, limit, measured,
                             samples, tets, vertices, before))

    compared = any(row[14] for row in rows)
    earlier_line = []
    if args.compare:
        earlier_line = [f"- earlier build (--compare): `{str(args.compare).replace(f'{ROOT}/', '')}`, the same keys, "
                        "run alternately with this build's"]
    elif compared:
        earlier_line = re.findall(r"^- earlier build.*$", args.samples_from.read_text(), re.M)
    preset = args.preset
    out = args.output or ROOT / f"bench/results/roofline_{preset}.md"
    any_rates = next(iter(rate_rows.values()))
    lines = [
        f"# Roofline of the CPU tet-iteration, {preset} helix",
        "",
        *machine_lines(),
        f"- build: CMAKE_BUILD_TYPE=Release, DESCENT_CPU_ARCH={cpu_arch(args.build)!r}: vector extensions "
        f"`{any_rates['isa']}` (the rates and the bound are this build's)",
        f"- command (last run; model, precision and ranks varied): `{commands[-1]}`",
        *earlier_line,
        f"- measured: the run's own ns per tet-iteration (step time / (tets x iterations)), median of "
        f"{len(rows[0][11])} runs; 1 OpenMP thread per rank"
        + (f" (the samples of `{str(args.samples_from).replace(f'{ROOT}/', '')}`, measured "
           f"{re.search(r'- date: (.*)', args.samples_from.read_text()).group(1)}; the machine rates anew)"
           if args.samples_from else f", {args.frames} frames a run"),
        "- machine rates (`bench/roofline/machine_rates.cpp`, same ranks, threads and flags; triad over each "
        "rank's working set):",
        "",
        "| ranks | precision | triad GB/s | peak GFlop/s | ns sqrt | ns cbrt | ns exp | ns div | triad MiB per rank |",
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    for (ranks, precision), r in sorted(rate_rows.items()):
        lines.append(f"| {ranks} | {precision} | {r[f'triad_GBps_{precision}']:.1f} | "
                     f"{r[f'peak_GFlops_{precision}']:.1f} | {r[f'ns_sqrt_{precision}']:.2f} | "
                     f"{r[f'ns_cbrt_{precision}']:.2f} | {r[f'ns_exp_{precision}']:.2f} | "
                     f"{r[f'ns_div_{precision}']:.2f} | {r['triad_MiB_per_rank']:.1f} |")
    lines += [
        "",
        "Per tet-iteration (all ranks together; the bound is the larger of compute and memory):",
        "",
        "| ranks | model | precision | bytes | flops | div | sqrt | cbrt | exp | calls ns | compute ns | memory ns "
        "| bound | measured ns | % of bound | samples |" + (" earlier build ns | speed-up | earlier samples |"
                                                             if compared else ""),
        "| --- " * (16 + (3 if compared else 0)) + "|",
    ]
    for (ranks, model, precision, nbytes, flops, ops, calls, compute, memory, limit, measured, samples, tets,
         vertices, before) in rows:
        which = "compute" if compute >= memory else "memory"
        line = (f"| {ranks} | {model} | {precision} | {nbytes:.0f} | {flops:.0f} | {ops['div']:.1f} | "
                f"{ops['sqrt']:.1f} | {ops['cbrt']:.2f} | {ops['exp']:.2f} | {calls:.2f} | {compute:.2f} | "
                f"{memory:.2f} | {which} {limit:.2f} | {measured:.1f} | {100 * limit / measured:.0f}% | "
                f"{sample_list(samples)} |")
        if before:
            line += (f" {statistics.median(before):.1f} | {statistics.median(before) / measured:.2f}x | "
                     f"{sample_list(before)} |")
        lines.append(line)
    lines += ["", f"Mesh: {rows[0][12]} tets, {rows[0][13]} vertices ({3 * rows[0][13] / rows[0][12]:.3f} dofs per tet).",
              "Operations per tet and per dof (bench/roofline/op_count.cpp, 64 tets rotated at random and stretched "
              "up to 20% per axis):", "",
              "| model | kernel | add | mul | div | sqrt | cbrt | exp | compare | other |",
              "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for (model, kernel), c in counts.items():
        lines.append(f"| {model} | {kernel} | " + " | ".join(f"{c[k]:g}" for k in
                                                          ("add", "mul", "div", "sqrt", "cbrt", "exp", "compare",
                                                           "other")) + " |")
    write_report(lines, str(out))
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
