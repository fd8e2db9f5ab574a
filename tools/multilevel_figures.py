#!/usr/bin/env python3
"""Tables and plots of jobs/study/multilevel.sh's results (issue 25).

    tools/multilevel_figures.py [RESULTS]   (default bench/results/multilevel)

Reads what each part left in RESULTS and writes beside it:
  resolution.md/.csv/.png  iterations and rank 0's wall time (median of the
                           study's repeats) to e <= 1e-1 .. 1e-5 per case and
                           helix size; growth, ratios, crossover, extrapolation
  poisson.md               iterations to e <= 1e-3 per Poisson ratio
  stiff.md                 time to e <= 1e-2 .. 1e-4 on the armadillos
  mainjob.md               ms per frame (median of 3 runs), set-up, memory
  refresh.md               ms per frame and iterations per step per refresh interval
  bound.md                 the 316K helix's multilevel Chebyshev against its bound
                           per Lanczos length and spectrum margin
  unseen.md                the shared meshes under four materials: iterations,
                           rank 0 ms and the error where each case's step stops
  stopping.md              where a step with solver.accuracy stops and the error
                           there, per binary (label), size and target
A part whose results are absent is skipped. Needs python3-matplotlib.
"""
import csv
import gzip
import math
import os
import re
import statistics
import sys

LEVELS = [1e-1, 1e-2, 1e-3, 1e-4, 1e-5]


def read_study(directory):
    """Per case: the rows of study.csv(.gz) in k order, and the tet count."""
    path = os.path.join(directory, "study.csv.gz")
    opener = gzip.open if os.path.exists(path) else open
    if not os.path.exists(path):
        path = os.path.join(directory, "study.csv")
    if not os.path.exists(path):
        return None, None
    cases = {}
    with opener(path, "rt") as f:
        for row in csv.DictReader(f):
            cases.setdefault(row["case"], []).append(row)
    tets = None
    log = os.path.join(directory, "progress.log")
    if os.path.exists(log):
        m = re.search(r"study: (\d+) tets", open(log).read())
        tets = int(m.group(1)) if m else None
    return cases, tets


def first_reaching(rows, level):
    """(k, ms, cpu_ms) of the first iterate with e <= level, or None."""
    for r in rows:
        e = float(r["rel_error"])
        if math.isfinite(e) and e <= level:
            return int(r["k"]), float(r["ms"]), float(r["cpu_ms"])
    return None


def fmt(x, digits=0):
    return "-" if x is None else (f"{x:.{digits}f}" if digits else f"{x:.0f}")


def resolution(base, out):
    root = os.path.join(base, "resolution")
    if not os.path.isdir(root):
        return
    sizes = []
    for name in os.listdir(root):
        cases, tets = read_study(os.path.join(root, name))
        if cases:
            sizes.append((tets or 0, name, cases))
    sizes.sort()
    if not sizes:
        return
    case_names = sorted({c for _, _, cases in sizes for c in cases})
    table = {}  # (size name, case, level) -> (k, ms, cpu)
    rows = []
    for tets, name, cases in sizes:
        for case in case_names:
            for level in LEVELS:
                hit = first_reaching(cases.get(case, []), level)
                table[(name, case, level)] = hit
                rows.append([name, tets, case, level] + (list(hit) if hit else ["", "", ""]))
    with open(os.path.join(out, "resolution.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["size", "tets", "case", "level", "iterations", "ms", "cpu_ms"])
        w.writerows(rows)

    lines = ["# Iterations and rank 0's time to e <= level against resolution", "",
             "Per helix size (2 ranks, one step after 5 frames) and case: iterations / "
             "rank 0's wall ms (median of the study's repeats) to reach each level; "
             "`-`: not within the case's iteration cap.", ""]
    for tets, name, _ in sizes:
        lines += [f"## helix {name} ({tets} tets)", "",
                  "| case | " + " | ".join(f"e <= {l:g}" for l in LEVELS) + " |",
                  "|---|" + "---|" * len(LEVELS)]
        for case in case_names:
            cells = []
            for level in LEVELS:
                hit = table[(name, case, level)]
                cells.append("-" if hit is None else f"{hit[0]} / {hit[1]:.0f} ms")
            lines.append(f"| {case} | " + " | ".join(cells) + " |")
        lines.append("")

    # Growth, ratios, crossover and extrapolation of multilevel against Jacobi.
    ml, jac = "chebyshev_multilevel", "chebyshev_jacobi"
    first, last = sizes[0], sizes[-1]
    lines += ["## Multilevel against Jacobi (Chebyshev)", ""]
    for level in LEVELS:
        a, b = table.get((first[1], ml, level)), table.get((last[1], ml, level))
        c, d = table.get((first[1], jac, level)), table.get((last[1], jac, level))
        if a and b:
            text = f"- e <= {level:g}: multilevel iterations {a[0]} at {first[1]} -> {b[0]} at " \
                   f"{last[1]} ({b[0] / a[0]:.2f}x)"
            if c and d:
                text += f"; Jacobi {c[0]} -> {d[0]} ({d[0] / c[0]:.2f}x)"
            if d:
                text += f"; at {last[1]} Jacobi's time / multilevel's = {d[1] / b[1]:.2f}"
            lines.append(text)
    lines.append("")
    for level in LEVELS:
        cross = None
        for tets, name, _ in sizes:
            a, b = table.get((name, ml, level)), table.get((name, jac, level))
            if a and b and a[1] < b[1]:
                cross = (name, tets)
                break
        lines.append(f"- e <= {level:g}: multilevel is faster than Jacobi from "
                     + (f"{cross[0]} ({cross[1]} tets) on" if cross else "no measured size"))
    # Power laws of time in N over the two largest sizes, extrapolated to 10M.
    if len(sizes) >= 2:
        (n0, s0, _), (n1, s1, _) = sizes[-2], sizes[-1]
        lines.append("")
        for level in LEVELS:
            pts = {}
            for case in (ml, jac):
                a, b = table.get((s0, case, level)), table.get((s1, case, level))
                if a and b and n0 > 0 and n1 > n0:
                    p = math.log(b[1] / a[1]) / math.log(n1 / n0)
                    pts[case] = (p, b[1] * (1e7 / n1) ** p)
            if len(pts) == 2:
                lines.append(f"- e <= {level:g}: time grows as N^{pts[ml][0]:.2f} (multilevel) and "
                             f"N^{pts[jac][0]:.2f} (Jacobi) from {s0} to {s1}; extrapolated to 10M "
                             f"tets Jacobi / multilevel = {pts[jac][1] / pts[ml][1]:.1f}")
    # The semi-iteration against its bound: e_k <= 1 / T_k(1/rho)^2 for
    # eigenvalues in the case's [a, b] (from the study's log).
    lines += ["", "## Chebyshev with multilevel against its bound", "",
              "Per size: [a, b] the case estimated, and the largest e_k / (1 / T_k(1/rho)^2) "
              "over its iterations with e_k >= 1e-6 (below, the truth's Newton tolerance and the energy's nonlinearity set the floor; at most 1: the bound holds).", ""]
    for tets, name, cases in sizes:
        bounds = case_bounds(os.path.join(root, name))
        if ml not in bounds or ml not in cases:
            continue
        a, b = bounds[ml]
        worst, at = worst_against_bound(cases[ml], a, b)
        lines.append(f"- {name}: [{a:.4f}, {b:.4f}], kappa {b / a:.1f}: worst e_k / bound "
                     f"{worst:.3g} (k = {at})")
    with open(os.path.join(out, "resolution.md"), "w") as f:
        f.write("\n".join(lines) + "\n")

    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("multilevel_figures.py: no matplotlib: resolution.png not drawn", file=sys.stderr)
        return
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for case in case_names:
        xs, its, ms = [], [], []
        for tets, name, _ in sizes:
            hit = table.get((name, case, 1e-3))
            if hit:
                xs.append(tets)
                its.append(hit[0])
                ms.append(hit[1])
        if xs:
            axes[0].loglog(xs, its, "o-", label=case)
            axes[1].loglog(xs, ms, "o-", label=case)
    axes[0].set_xlabel("tets")
    axes[0].set_ylabel("iterations to e <= 1e-3")
    axes[1].set_xlabel("tets")
    axes[1].set_ylabel("rank 0 wall ms to e <= 1e-3")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
    axes[1].legend(fontsize=7)
    fig.suptitle("Double helix, 2 ranks: one step to e <= 1e-3")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "resolution.png"), dpi=110)


def level_table(base, part, title, levels):
    root = os.path.join(base, part)
    if not os.path.isdir(root):
        return
    lines = [f"# {title}", "", "| run | case | " + " | ".join(f"e <= {l:g}" for l in levels) + " |",
             "|---|---|" + "---|" * len(levels)]
    for name in sorted(os.listdir(root)):
        cases, _ = read_study(os.path.join(root, name))
        if not cases:
            continue
        for case in sorted(cases):
            cells = []
            for level in levels:
                hit = first_reaching(cases[case], level)
                cells.append("-" if hit is None else f"{hit[0]} / {hit[1]:.0f} ms")
            lines.append(f"| {name} | {case} | " + " | ".join(cells) + " |")
    with open(os.path.join(base, f"{part}.md"), "w") as f:
        f.write("\n".join(lines) + "\n")


def run_logs(base, part, title):
    root = os.path.join(base, part)
    if not os.path.isdir(root):
        return
    groups = {}
    for name in sorted(os.listdir(root)):
        if not name.endswith(".log"):
            continue
        text = open(os.path.join(root, name)).read()
        m = re.search(r"(\d+) frames in ([\d.]+) s, ([\d.]+) ms/frame", text)
        if not m:
            continue
        # The main job's runs repeat (NAME_RUN); the refresh part's names differ.
        label = re.sub(r"_\d+$", "", name[:-4]) if part == "mainjob" else name[:-4]
        setup = re.search(r"set-up ([\d.]+) s to the first step", text)
        peak = re.search(r"descent: peak RSS per rank: ([\d ]+) MiB", text)
        pre = re.search(r"preconditioner: (.*)", text)
        stats = os.path.join(root, name[:-4], "stats.csv")
        iterations = None
        if os.path.exists(stats):
            with open(stats) as f:
                its = [int(r["iterations"]) for r in csv.DictReader(f)]
            iterations = statistics.mean(its) if its else None
        groups.setdefault(label, []).append(
            (float(m.group(3)), float(setup.group(1)) if setup else None,
             max(int(x) for x in peak.group(1).split()) if peak else None,
             iterations, pre.group(1) if pre else ""))
    lines = [f"# {title}", "", "| run | ms per frame (median; runs) | set-up s | peak MiB "
             "(largest rank) | iterations per step | preconditioner |", "|---|---|---|---|---|---|"]
    for label, runs in groups.items():
        ms = [r[0] for r in runs]
        lines.append(f"| {label} | {statistics.median(ms):.1f} ({', '.join(f'{x:.1f}' for x in ms)}) "
                     f"| {fmt(runs[0][1], 2)} | {fmt(runs[0][2])} | {fmt(runs[0][3], 1)} | "
                     f"{runs[0][4]} |")
    with open(os.path.join(base, f"{part}.md"), "w") as f:
        f.write("\n".join(lines) + "\n")


def case_bounds(directory):
    """Per case: the [a, b] its log reports."""
    log = os.path.join(directory, "progress.log")
    if not os.path.exists(log):
        return {}
    found = re.findall(r"\] (\S+) .*lambda \[([\d.eE+-]+), ([\d.eE+-]+)\]", open(log).read())
    return {name: (float(a), float(b)) for name, a, b in found}


def worst_against_bound(rows, a, b, floor=1e-6):
    """The largest e_k / (1 / T_k(1/rho)^2) over e_k >= floor, and its k."""
    phi = 2 * math.atanh(math.sqrt(a / b))
    worst, at = 0.0, 0
    for r in rows:
        k, e = int(r["k"]), float(r["rel_error"])
        if k == 0 or not math.isfinite(e) or e < floor:
            continue
        if e * math.cosh(k * phi) ** 2 > worst:
            worst, at = e * math.cosh(k * phi) ** 2, k
    return worst, at


def bound(base):
    root = os.path.join(base, "bound", "helix_316k")
    cases, _ = read_study(root)
    if not cases:
        return
    bounds = case_bounds(root)
    ks = [8, 16, 24, 32, 40]
    lines = ["# The 316K helix: multilevel Chebyshev against its bound", "",
             "One step from the same state (jobs/study/multilevel.sh bound). [a, b]: the bounds "
             "the case ran with (Lanczos at the refresh state; b = (1 + margin) x its top Ritz "
             "value); e_k: the relative error after k iterations; worst: the largest e_k / "
             "(1 / T_k(1/rho)^2) over e_k >= 1e-6 (at most 1: the bound holds).", "",
             "| case | [a, b] | " + " | ".join(f"e_{k}" for k in ks) + " | worst (k) |",
             "|---|---|" + "---|" * len(ks) + "---|"]
    for case, rows in cases.items():
        if case not in bounds:
            continue
        a, b = bounds[case]
        at_k = {int(r["k"]): float(r["rel_error"]) for r in rows}
        worst, at = worst_against_bound(rows, a, b)
        lines.append(f"| {case} | [{a:.4f}, {b:.4f}] | "
                     + " | ".join(f"{at_k[k]:.2e}" if k in at_k else "-" for k in ks)
                     + f" | {worst:.3g} ({at}) |")
    with open(os.path.join(base, "bound.md"), "w") as f:
        f.write("\n".join(lines) + "\n")


def stop_of(rows):
    """(k, e, ms) of the last iterate a case's step reached."""
    last = max(rows, key=lambda r: int(r["k"]))
    return int(last["k"]), float(last["rel_error"]), float(last["ms"])


def unseen(base):
    root = os.path.join(base, "unseen")
    if not os.path.isdir(root):
        return
    names = ["auto_1e-2", "jacobi_1e-2", "auto_1e-4"]
    lines = ["# Meshes and materials nobody tuned for", "",
             "Each mesh of ../shared/meshes scaled to 1 m and held at its lowest 5%, one step "
             "after 5 warm-up frames (jobs/study/multilevel.sh unseen). Per case: iterations / "
             "rank 0 ms / the relative error where the step stopped (from Newton's eps*); "
             "**bold** where it exceeds the target. auto: the multilevel preconditioner.", "",
             "| mesh, model, E, nu | tets | " + " | ".join(names) + " | time jacobi / auto to 1e-2 |",
             "|---|---|" + "---|" * len(names) + "---|"]
    for name in sorted(os.listdir(root)):
        cases, tets = read_study(os.path.join(root, name))
        if not cases:
            continue
        cells, stops = [], {}
        for case in names:
            if case not in cases:
                cells.append("-")
                continue
            k, e, ms = stops[case] = stop_of(cases[case])
            cell = f"{k} / {ms:.0f} / {e:.1e}"
            cells.append(f"**{cell}**" if e > float(case.split("_", 1)[1]) else cell)
        ratio = (f"{stops['jacobi_1e-2'][2] / stops['auto_1e-2'][2]:.1f}x"
                 if "jacobi_1e-2" in stops and "auto_1e-2" in stops else "-")
        lines.append(f"| {name.replace('_', ' ')} | {fmt(tets)} | " + " | ".join(cells)
                     + f" | {ratio} |")
    with open(os.path.join(base, "unseen.md"), "w") as f:
        f.write("\n".join(lines) + "\n")


def stopping(base):
    root = os.path.join(base, "stopping")
    if not os.path.isdir(root):
        return
    lines = ["# Where a step with solver.accuracy stops", "",
             "Multilevel Chebyshev, one step from the same state per size (jobs/study/multilevel.sh "
             "stopping), per binary: iterations at the stop / the relative error there (from "
             "Newton's eps*); **bold** where the error exceeds the target.", ""]
    for label in sorted(os.listdir(root)):
        sizes = []
        for name in os.listdir(os.path.join(root, label)):
            cases, tets = read_study(os.path.join(root, label, name))
            if cases:
                sizes.append((tets or 0, name, cases))
        if not sizes:
            continue
        sizes.sort()
        # Cases are named accuracy_<target> as the study job spelled it.
        targets = sorted({c.split("_", 1)[1] for _, _, cases in sizes for c in cases},
                         key=float, reverse=True)
        lines += [f"## {label}", "", "| size | " + " | ".join(f"e <= {t}" for t in targets) + " |",
                  "|---|" + "---|" * len(targets)]
        for _, name, cases in sizes:
            cells = []
            for t in targets:
                rows = cases.get(f"accuracy_{t}")
                if not rows:
                    cells.append("-")
                    continue
                k, e, _ = stop_of(rows)
                cell = f"{k} / {e:.2e}"
                cells.append(f"**{cell}**" if e > float(t) else cell)
            lines.append(f"| {name} | " + " | ".join(cells) + " |")
        lines.append("")
    with open(os.path.join(base, "stopping.md"), "w") as f:
        f.write("\n".join(lines))


def main():
    base = sys.argv[1] if len(sys.argv) > 1 else "bench/results/multilevel"
    resolution(base, base)
    level_table(base, "poisson", "Nearly incompressible: the 158K helix per Poisson ratio",
                [1e-2, 1e-3, 1e-4])
    level_table(base, "stiff", "The armadillos: iterations / rank 0 ms to each level",
                [1e-1, 1e-2, 1e-3, 1e-4])
    run_logs(base, "mainjob", "The main job (82K helix, 1e-2 a step, 2 ranks, 60 frames)")
    run_logs(base, "refresh", "The main job with multilevel, per solver.preconditioner_refresh")
    bound(base)
    unseen(base)
    stopping(base)


if __name__ == "__main__":
    main()
