#!/usr/bin/env python3
"""The markdown table of an extremes sweep: DIR/results.jsonl (one JSON
object per run, from tests/extremes/extremes_driver.cpp) -> DIR/table.md.

    python3 tools/extremes_table.py bench/results/extremes

Summary matrices first (case x model, each cell over the float/double x
1/3-rank runs), then one row per run. Standard library only.
"""
import json
import sys
from collections import defaultdict
from pathlib import Path

MODELS = ["stvk", "neo_hookean", "mooney_rivlin", "fung", "corotated", "arap"]


def fmt(x, digits=2):
    if x is None:
        return "-"
    if isinstance(x, bool):
        return "yes" if x else "NO"
    if isinstance(x, int):
        return str(x)
    if x != 0 and (abs(x) < 1e-2 or abs(x) >= 1e4):
        return f"{x:.{digits}e}"
    return f"{x:.{digits + 1}g}"


def variant(r):
    return f"{r['precision'][0]}{r['ranks']}"  # f1, d3, ...


def summary_cell(runs, key):
    """One cell of a matrix over a case x model's runs (any precision, ranks)."""
    if not runs:
        return ""
    if key == "finite":
        failed = [r for r in runs if not r["finite"]]
        if not failed:
            return f"{len(runs)}/{len(runs)}"
        first = failed[0]
        where = f" @{first['failed_frame']}" if first["failed_frame"] else ""
        return f"**{len(runs) - len(failed)}/{len(runs)}**{where}"
    if key == "distance":
        parts = []
        for r in sorted(runs, key=lambda r: (r["precision"] != "double", r["ranks"])):
            if r["ranks"] == 1:
                parts.append(fmt(r["distance"], 1))
        return " / ".join(parts)
    if key == "stalled":
        worst = max(r["stalled_steps"] for r in runs)
        steps = max(r["steps"] for r in runs)
        rollbacks = max(r["rollbacks"] for r in runs)
        return f"{worst}/{steps} ({rollbacks})"
    if key == "inversion":
        sigma = min((r["min_sigma"] for r in runs if r["min_sigma"] is not None), default=None)
        inverted = max(r["max_inverted"] for r in runs)
        return f"{fmt(sigma, 1)} ({inverted})"
    if key == "energy":
        checked = [r for r in runs if r["energy_checked"]]
        if not checked:
            return "n/a"
        rises = sum(r["energy_rises"] for r in checked)
        return "ok" if rises == 0 else f"**{rises} rises**"
    raise KeyError(key)


def matrix(rows, cases, key, title, note):
    by = defaultdict(list)
    for r in rows:
        by[(r["case"], r["model"])].append(r)
    out = [f"### {title}", "", note, "", "| case | " + " | ".join(MODELS) + " |",
           "|---|" + "---|" * len(MODELS)]
    for case in cases:
        out.append(f"| {case} | " + " | ".join(summary_cell(by[(case, m)], key) for m in MODELS)
                   + " |")
    return out + [""]


def main():
    folder = Path(sys.argv[1] if len(sys.argv) > 1 else "bench/results/extremes")
    lines = [json.loads(l) for l in (folder / "results.jsonl").read_text().splitlines() if l]
    errors = [r for r in lines if "error" in r]
    rows = [r for r in lines if "error" not in r]
    cases = list(dict.fromkeys(r["case"] for r in rows))
    what = {r["case"]: (r["group"], r["what"], r["conversion"]) for r in rows}
    machine = {}
    if (folder / "machine.json").exists():
        machine = json.loads((folder / "machine.json").read_text())

    total = len(rows)
    finite = sum(r["finite"] for r in rows)
    rises = sum(r["energy_rises"] for r in rows if r["energy_checked"])
    checked = sum(1 for r in rows if r["energy_checked"])
    stalled_runs = sum(1 for r in rows if r["stalled_steps"] > 0)
    refs = sorted({r["distance_kind"] for r in rows if r["distance_kind"] != "none"})
    md = ["# Extremes sweep", "",
          f"Made by `jobs/extremes/sweep.py` ({machine.get('date', '?')}, "
          f"{machine.get('cpu', '?')}, {machine.get('cores', '?')} cores, "
          "OMP_NUM_THREADS=1). Cases: tests/extremes/extreme_cases.cpp; what each "
          "means and how to read this: docs/extremes.md.", "",
          "## Headline", "",
          f"- {total} runs ({len(cases)} cases x {len(MODELS)} models x float/double x 1/3 ranks"
          f"{'; ' + str(len(errors)) + ' driver launches failed' if errors else ''}).",
          f"- Finite to the end: {finite}/{total}. Every other run stopped at a step that reached "
          "no finite state, with the culprit named (below).",
          f"- State finite at the end (positions and velocities, stopped runs included): "
          f"{sum(1 for r in rows if r.get('state_finite'))}/{total}.",
          f"- Energy across each step (eps(q_t+1) <= eps(initial guess) + round-off tolerance, "
          f"evaluated apart from the solver): {checked - sum(1 for r in rows if r['energy_checked'] and r['energy_rises'])}"
          f"/{checked} runs without a rise ({rises} rising steps in all); runs with model "
          "conversion are not checked (the energy changes within a step).",
          f"- Runs with at least one step ended at alpha_min (stalled): {stalled_runs}/{total}.",
          f"- Distance references: {', '.join(refs)}.", ""]
    md += ["## Cases", "", "| case | group | what | conversion |", "|---|---|---|---|"]
    md += [f"| {c} | {what[c][0]} | {what[c][1]} | {'on' if what[c][2] else 'off'} |"
           for c in cases]
    md += [""]
    md += matrix(rows, cases, "finite", "Finite (runs finite / runs; @frame of the first failure)",
                 "Over float/double x 1/3 ranks. A failure is a step that reached no state of "
                 "finite energy: the run stopped there, the body kept its last good state.")
    md += matrix(rows, cases, "energy", "Energy never rises across a step",
                 "ok: no step of any run ended above its initial guess's energy by more than "
                 "the round-off tolerance; n/a: model conversion on.")
    md += matrix(rows, cases, "distance", "Distance from the converged state",
                 "max |q - q_ref| / bbox diagonal at the last step, double / float on 1 rank "
                 "(recovery cases: max |sigma - 1| over the tets, 0 = rest shape recovered; "
                 "- : no finite run or no reference).")
    md += matrix(rows, cases, "stalled", "Steps ended at alpha_min",
                 "stalled steps / steps (most rollbacks in a run), worst over the four runs.")
    md += matrix(rows, cases, "inversion", "Inversion",
                 "smallest signed singular value of any tet over all frames (most tets with "
                 "det F <= 0 at once), over the four runs.")
    md += ["## Every run", "",
           "v: f/d = float/double, 1/3 = ranks. rises: steps whose energy rose (n/a: "
           "conversion). dist: as above.", "",
           "| case | model | v | finite | failed | steps | rollbacks | non-finite | stalled | "
           "alpha | rises | min det F | min sigma | inverted | dist | s |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    order = {m: i for i, m in enumerate(MODELS)}
    for r in sorted(rows, key=lambda r: (cases.index(r["case"]), order.get(r["model"], 9),
                                         r["precision"] != "double", r["ranks"])):
        md.append(
            f"| {r['case']} | {r['model']} | {variant(r)} | {fmt(r['finite'])} | "
            f"{(str(r['failed_frame']) + ': ' + r['failure']) if r['failed_frame'] else ''} | "
            f"{r['steps']} | {r['rollbacks']} | {r['nonfinite_rollbacks']} | "
            f"{r['stalled_steps']} | {fmt(r['final_alpha'], 1)} | "
            f"{r['energy_rises'] if r['energy_checked'] else 'n/a'} | {fmt(r['min_det'], 1)} | "
            f"{fmt(r['min_sigma'], 1)} | {r['max_inverted']} | {fmt(r['distance'], 1)} | "
            f"{fmt(r['wall_s'], 1)} |")
    if errors:
        md += ["", "## Driver launches that failed", ""]
        md += [f"- {e['case']} on {e['ranks']} rank(s): {e['error']}" for e in errors]
    (folder / "table.md").write_text("\n".join(md) + "\n")
    print(f"extremes_table: wrote {folder / 'table.md'}")


if __name__ == "__main__":
    main()
