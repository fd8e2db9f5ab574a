#!/usr/bin/env python3
"""Plots of an extremes sweep: DIR/results.jsonl -> DIR/*.png.

    /usr/bin/python3 tools/extremes_plots.py bench/results/extremes

- distance_vs_dt.png: distance from the converged state after the last step
  against the time step (hanging helix), per model, float and double.
- distance_vs_young.png: the same against Young's modulus.
- status.png: every run as a cell (case x model/precision/ranks): finite,
  finite with stalled steps, or stopped at a failed step.
Needs matplotlib (the default python3 may lack it; /usr/bin/python3 has it).
"""
import json
import sys
from pathlib import Path

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import ListedColormap
except ImportError:
    sys.exit("extremes_plots: matplotlib is missing in this python; try /usr/bin/python3")

MODELS = ["stvk", "neo_hookean", "mooney_rivlin", "fung", "corotated", "arap"]
DT = {"dt_0.001": 1e-3, "dt_0.01": 1e-2, "dt_0.033": 1 / 30, "dt_0.1": 0.1, "dt_1": 1.0}
YOUNG = {"E_1e3": 1e3, "dt_0.033": 1e5, "E_1e7": 1e7, "E_1e9": 1e9, "E_1e11": 1e11}


def sweep_plot(rows, axis_of, xlabel, path, title):
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for i, model in enumerate(MODELS):
        for precision, style in (("double", "-"), ("float", ":")):
            points = sorted((axis_of[r["case"]], r["distance"]) for r in rows
                            if r["case"] in axis_of and r["model"] == model and r["ranks"] == 1
                            and r["precision"] == precision and r["distance"]
                            and r["distance"] > 0)
            if points:
                ax.loglog(*zip(*points), style, marker="o", color=f"C{i}", markersize=4,
                          label=f"{model} ({precision})" if precision == "double" else None)
    ax.set_xlabel(xlabel)
    ax.set_ylabel("max |q - q_ref| / bbox diagonal, last step")
    ax.set_title(title)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, title="solid: double, dotted: float", title_fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def status_plot(rows, path):
    cases = list(dict.fromkeys(r["case"] for r in rows))
    columns = [(m, p, n) for m in MODELS for p in ("double", "float") for n in (1, 3)]
    grid = [[float("nan")] * len(columns) for _ in cases]
    for r in rows:
        key = (r["model"], r["precision"], r["ranks"])
        if key in columns:
            grid[cases.index(r["case"])][columns.index(key)] = (
                0 if r["finite"] and r["stalled_steps"] == 0 else 1 if r["finite"] else 2)
    fig, ax = plt.subplots(figsize=(11, 0.32 * len(cases) + 2))
    ax.imshow(grid, cmap=ListedColormap(["#4caf50", "#ffc107", "#e53935"]), vmin=0, vmax=2,
              aspect="auto")
    ax.set_yticks(range(len(cases)), cases, fontsize=8)
    ax.set_xticks(range(len(columns)), [f"{m[:6]} {p[0]}{n}" for m, p, n in columns],
                  rotation=90, fontsize=7)
    ax.set_title("green: finite; amber: finite, some steps stalled at alpha_min; "
                 "red: stopped at a step with no finite state", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main():
    folder = Path(sys.argv[1] if len(sys.argv) > 1 else "bench/results/extremes")
    rows = [json.loads(l) for l in (folder / "results.jsonl").read_text().splitlines() if l]
    rows = [r for r in rows if "error" not in r]
    sweep_plot(rows, DT, "time step h (s)", folder / "distance_vs_dt.png",
               "Hanging helix, 10 steps of 96 iterations")
    sweep_plot(rows, YOUNG, "Young's modulus (Pa), density 1000", folder / "distance_vs_young.png",
               "Hanging helix, h = 1/30 s, 10 steps of 96 iterations")
    status_plot(rows, folder / "status.png")
    print(f"extremes_plots: wrote {folder}/distance_vs_dt.png, distance_vs_young.png, status.png")


if __name__ == "__main__":
    main()
