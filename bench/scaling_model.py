#!/usr/bin/python3
"""Modelled strong and weak scaling of the Chebyshev iteration, 1 to 1024 ranks.

  bench/scaling_model.py                       # defaults: the inputs committed beside it
  bench/scaling_model.py --latency-us 5 --out /tmp/slow_network

Only 2 cores were ever available to this project, so scaling beyond 2 ranks
cannot be measured here; this model predicts it from what can be:

- REAL partitions of the 10.36M-tet double helix into P = 2 .. 1024 parts
  (bench/scaling_partitions.sh): per part its tets, neighbours, shared
  (vertex, neighbour) pairs and shared vertices as the partitioner reported
  them, and its boundary tets counted from the partition file;
- the CPU cost of one iteration per tet on one core, MEASURED on this machine
  at four part sizes (bench/scaling_compute_cost.py; by default the median
  of all its samples, see CpuCost);
- STATED assumptions for everything not measurable here: the network, the
  GPU's cost per tet-iteration, the host-device copies. Each is an option
  below with its default, and every output names the values used.

What one iteration does (src/solver/iteration_engine_impl.hpp, assemble()
and iteration(); src/comm/halo.cpp), per rank:

  element pass over the boundary tets (those touching a shared vertex)
  [GPU: copy the shared vertices' partials to the host]
  pack the partials for each neighbour, post one MPI_Isend and one MPI_Irecv
    per neighbour: w values per shared (vertex, neighbour) pair
  element pass over the interior tets (overlaps the exchange)
  wait; sum each shared vertex's partials in rank order (unpack)
  [GPU: copy the totals back]
  vertex update (fused: direction, Chebyshev, constraints)

w is 3 (the gradient) or 6 (gradient and Hessian diagonal) in the
iterations that refresh the diagonal, every hessian_interval (M = 32): on
average 3 + 3/M values. A value is a double on the CPU and a float on the
GPU. Every check_interval (8) iterations the energy is checked with the one
MPI_Allreduce of the loop.

The model, per part p of P (times per iteration, averaged over M and the
check interval; c = cost per tet-iteration, s = bytes per value):

  w        = 3 + 3/M
  T_b      = c * boundary_tets_p             T_i = c * (tets_p - boundary_tets_p)
  T_pack   = pairs_p * w * pack_ns                          (fill the send buffers)
  T_sum    = (pairs_p + shared_p) * w * pack_ns             (rank-order sums of the terms)
  T_net    = neighbours_p * latency + pairs_p * w * s / B,  B = node_bandwidth / min(P, ranks_per_node)
  T_copy   = 2 * (copy_latency + shared_p * w * s / pcie)   (GPU only: to the host and back)
  T_ar     = ceil(log2 P) * allreduce_latency / check_interval
  CPU, overlap:  T_p = T_b + T_pack + max(T_i, T_net) + T_sum + T_ar
      (the host packs and posts, computes the interior, then waits and sums)
  GPU, overlap:  T_p = T_b + max(T_i, T_copy + T_pack + T_net + T_sum) + T_ar
      (the interior runs on its own stream while the host exchanges)
  no overlap:    T_p = T_b + T_i + T_copy + T_pack + T_net + T_sum + T_ar
  T(P) = max over parts of T_p (neighbours wait for each other every
  iteration, so the slowest part sets the pace)

The CPU overlap assumes the network moves the messages while the interior
is computed (eager-size messages, or an MPI with asynchronous progress);
where it does not, the no-overlap time is the one to read.

The measured cost per tet-iteration c already contains the vertex update
and the energy evaluations of the checks (it is the CPU time of whole steps
divided by tets x iterations), so those scale with the tets.

With the multilevel preconditioner (docs/multilevel.md; the cases
"multilevel" below) an iteration also applies one V-cycle and each step
rebuilds it once (the refresh), amortised over the step's iterations:

  compute  = c * tets * (k_it + k_ref / its)   k_it: an iteration with its
             V-cycle, k_ref: a refresh, both in Jacobi iterations' cost per
             tet, MEASURED here (--ml-iteration-factor, --ml-refresh-factor);
             its: iterations per step (--ml-iterations-per-step, the main job's)
  finest   the gradient's exchange (w = 3) and 2 d more (the smoother's
           products, d = degree) on the same pairs
  level l  (1 <= l < L - 1: the smoothed coarse levels) 2 d + 1 exchanges of
           6 values per pair, neighbours as the finest's, pairs scaled from the
           finest's by (nodes_l / vertices)^(2/3) (a halo is a surface) times
           --ml-halo-widening (smoothed P reaches one aggregate further)
  coarsest one MPI_Allgatherv per V-cycle: ceil(log2 P) latencies plus
           (coarsest nodes + 4 P) * 6 * s bytes at the node's bandwidth share
           (each rank's partial right-hand side; a rank holds a few coarsest
           nodes at least)
  refresh  per step (amortised): 21 + 1 small allgathers (the smoother bounds,
           the coarsest sizes) and the coarsest operator's MPI_Allgatherv,
           (its lower half + 4 P blocks of 36) * 16 bytes (row, column, value)
The hierarchy's sizes come from --ml-levels (nodes per level as the 1M
helix's run reported them, scaled with the mesh; one more level per factor
--ml-level-ratio of unknowns beyond it).

Strong scaling: the 10.36M-tet helix on P ranks, efficiency T(1) / (P T(P)).
Weak scaling: N tets per rank (one CPU case, one GPU case). Each part of the
P-part partition is scaled to N / (10.36M / P) times its tets (its imbalance
kept), its shared vertices, pairs and boundary tets by that ratio to the
power 2/3 (a halo is a surface), its neighbours as measured. Efficiency
T(1) / T(P).

Writes OUT/scaling_model.csv, OUT/scaling_model.md, OUT/scaling_model.png
and OUT/partitions.md (a summary of every partition CSV in --partitions).
Needs Debian's python3 and python3-matplotlib.
"""
import argparse
import csv
import math
import re
import statistics
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
RESULTS = ROOT / "bench/results/scaling_model"
# The paper's Table 1 (shared/papers/000_0651955c5455f15b.txt): the 316K-tet
# double helix, 96 iterations a frame, 122 ms a frame on a GTX TITAN X.
PAPER_GPU_NS = 122e-3 / (316e3 * 96) * 1e9


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def read_partition(folder, method, parts):
    """The parts of one partition: the partitioner's counts joined with the
    boundary tets counted from its file."""
    stats = read_csv(folder / f"{method}-{parts}.csv")
    boundary = {int(r["part"]): int(r["boundary_tets"]) for r in read_csv(folder / f"boundary-{method}-{parts}.csv")}
    if len(stats) != parts or len(boundary) != parts:
        sys.exit(f"{folder}: {method}-{parts}: {len(stats)} parts of stats, {len(boundary)} of boundary tets")
    return [{"tets": int(r["tets"]), "shared": int(r["shared_vertices"]), "neighbours": int(r["neighbours"]),
             "pairs": int(r["shared_pairs"]), "boundary": boundary[int(r["part"])]} for r in stats]


def partition_counts(folder, method):
    found = sorted(int(m.group(1)) for p in folder.glob(f"{method}-*.csv")
                   if (m := re.fullmatch(rf"{method}-(\d+)\.csv", p.name)))
    if not found:
        sys.exit(f"{folder}: no {method}-P.csv (make them with bench/scaling_partitions.sh)")
    return found


class CpuCost:
    """ns per tet-iteration on one core for a rank of `tets` tets, from the
    measured samples: "pooled", the median of every sample at every size
    (the default: on this shared machine the medians per size differ by no
    more than the samples of one size do, so no size dependence is
    resolved); "by-size", the median per size interpolated linearly in
    log(tets), held beyond the ends; or one constant (--cpu-ns)."""

    def __init__(self, table_path, mode, constant):
        self.mode = "constant" if constant is not None else mode
        self.constant = constant
        if constant is None:
            rows = read_csv(table_path)
            self.samples = [float(r["cpu_ns"]) for r in rows]
            sizes = sorted({int(r["tets"]) for r in rows})
            self.points = [(t, statistics.median(float(r["cpu_ns"]) for r in rows if int(r["tets"]) == t))
                           for t in sizes]
            if mode == "pooled":
                self.constant = statistics.median(self.samples)

    def __call__(self, tets):
        if self.mode != "by-size":
            return self.constant
        points = self.points
        if tets <= points[0][0]:
            return points[0][1]
        if tets >= points[-1][0]:
            return points[-1][1]
        for (t0, c0), (t1, c1) in zip(points, points[1:]):
            if t0 <= tets <= t1:
                x = (math.log(tets) - math.log(t0)) / (math.log(t1) - math.log(t0))
                return c0 + x * (c1 - c0)

    def describe(self):
        if self.mode == "constant":
            return f"{self.constant} ns (constant, --cpu-ns)"
        per_size = "; ".join(f"{t:,} tets: {c:.1f} ns" for t, c in self.points)
        if self.mode == "pooled":
            return (f"{self.constant:.1f} ns, the median of {len(self.samples)} samples measured here "
                    f"(medians per size: {per_size})")
        return f"{per_size} (medians measured here, interpolated in log tets)"


def multilevel_extra(part, ranks, case, args, total_tets):
    """Seconds per iteration the multilevel preconditioner adds to part:
    (compute, exposed exchange, collectives)."""
    c = case["ns"](part["tets"]) * 1e-9
    compute = c * part["tets"] * (args.ml_iteration_factor - 1 +
                                  args.ml_refresh_factor / args.ml_iterations_per_step)
    bytes_per_value = case["bytes_per_value"]
    bandwidth = case["node_bandwidth"] * 1e9 / min(ranks, case["ranks_per_node"])
    d = args.ml_degree
    exchange = 0.0
    if part["neighbours"] > 0:
        def one(pairs, width):
            return (part["neighbours"] * args.latency_us * 1e-6 + pairs * width * bytes_per_value / bandwidth
                    + 2 * pairs * width * args.pack_ns * 1e-9)
        exchange += 2 * d * one(part["pairs"], 3)
        nodes, coarsest = multilevel_levels(total_tets, args)
        vertices = nodes[0]
        for level_nodes in nodes[1:]:
            pairs = part["pairs"] * (level_nodes / vertices) ** (2 / 3) * args.ml_halo_widening
            exchange += (2 * d + 1) * one(pairs, 6)
    else:
        nodes, coarsest = multilevel_levels(total_tets, args)
    log_p = math.ceil(math.log2(ranks)) if ranks > 1 else 0
    gather = 0.0
    if ranks > 1:
        gather = log_p * args.allreduce_latency_us * 1e-6 + (coarsest + 4 * ranks) * 6 * 8 / bandwidth
        refresh = (22 * log_p * args.allreduce_latency_us * 1e-6 +
                   (coarsest * args.ml_coarsest_row_blocks * 36 / 2 + 4 * ranks * 36) * 16 / bandwidth)
        gather += refresh / args.ml_iterations_per_step
    return compute, exchange, gather


def multilevel_levels(total_tets, args):
    """Nodes of the hierarchy's smoothed levels (vertices first) for a mesh of
    total_tets tets, and the coarsest level's nodes."""
    measured_tets, *measured = args.ml_levels
    scale = total_tets / measured_tets
    nodes = [n * scale for n in measured]
    # Coarsen further while the coarsest exceeds the coarse size.
    while nodes[-1] * 6 > args.ml_coarse_size:
        nodes.append(nodes[-1] / args.ml_level_ratio)
    return nodes[:-1], nodes[-1]


def part_time(part, ranks, case, args, total_tets=0):
    """Modelled seconds per iteration of one part: (with overlap, without,
    and the terms)."""
    width = 3 + 3 / args.hessian_interval
    if case.get("multilevel"):
        width = 3.0  # no diagonal is refreshed
    c = case["ns"](part["tets"]) * 1e-9
    t_boundary = c * part["boundary"]
    t_interior = c * (part["tets"] - part["boundary"])
    bytes_per_value = case["bytes_per_value"]
    t_pack = part["pairs"] * width * args.pack_ns * 1e-9
    t_sum = (part["pairs"] + part["shared"]) * width * args.pack_ns * 1e-9
    bandwidth = case["node_bandwidth"] * 1e9 / min(ranks, case["ranks_per_node"])
    t_net = part["neighbours"] * args.latency_us * 1e-6 + part["pairs"] * width * bytes_per_value / bandwidth
    if part["neighbours"] == 0:
        t_pack = t_sum = t_net = 0.0
    if case["device_copies"]:
        # The exchange runs on the host beside the interior's stream.
        t_copy = 0.0
        if part["neighbours"] > 0:
            t_copy = 2 * (args.copy_latency_us * 1e-6 +
                          part["shared"] * width * bytes_per_value / (args.pcie_gbs * 1e9))
        hidden, exposed = t_copy + t_pack + t_net + t_sum, 0.0
    else:
        # The host packs and posts, computes the interior, then waits and sums.
        hidden, exposed = t_net, t_pack + t_sum
    t_allreduce = math.ceil(math.log2(ranks)) * args.allreduce_latency_us * 1e-6 / args.check_interval
    ml_compute = ml_exchange = 0.0
    if case.get("multilevel"):
        # The V-cycle's exchanges wait on its own products: nothing hides them.
        ml_compute, ml_exchange, ml_gather = multilevel_extra(part, ranks, case, args, total_tets)
        t_allreduce += ml_gather
    return {
        "overlap": t_boundary + exposed + max(t_interior, hidden) + t_allreduce + ml_compute + ml_exchange,
        "no_overlap": t_boundary + t_interior + exposed + hidden + t_allreduce + ml_compute + ml_exchange,
        "compute": t_boundary + t_interior + ml_compute, "halo": exposed + hidden + ml_exchange, "net": t_net,
        "allreduce": t_allreduce, "bytes_sent": part["pairs"] * width * bytes_per_value,
    }


def scaled_parts(parts, tets_per_rank):
    """The parts of a partition of the 10.36M helix, grown or shrunk to
    `tets_per_rank` on average: tets by the ratio, halo by its 2/3 power."""
    mean = sum(p["tets"] for p in parts) / len(parts)
    ratio = tets_per_rank / mean
    surface = ratio ** (2 / 3)
    return [{"tets": p["tets"] * ratio, "shared": p["shared"] * surface, "pairs": p["pairs"] * surface,
             "neighbours": p["neighbours"], "boundary": min(p["boundary"] * surface, p["tets"] * ratio)}
            for p in parts]


def model_case(case, partitions, args):
    """Rows of one case (strong or weak) for P = 1 and every partition."""
    total_tets = sum(p["tets"] for p in partitions[min(partitions)])
    rows = []
    for ranks in [1] + sorted(partitions):
        if ranks == 1:
            tets = total_tets if case["mode"] == "strong" else case["tets_per_rank"]
            parts = [{"tets": tets, "shared": 0, "pairs": 0, "neighbours": 0, "boundary": 0}]
        elif case["mode"] == "strong":
            parts = partitions[ranks]
        else:
            parts = scaled_parts(partitions[ranks], case["tets_per_rank"])
        mesh_tets = total_tets if case["mode"] == "strong" else case["tets_per_rank"] * ranks
        times = [(part_time(p, ranks, case, args, mesh_tets), p) for p in parts]
        slowest, part = max(times, key=lambda tp: tp[0]["overlap"])
        worst_no_overlap = max(t["no_overlap"] for t, _ in times)
        rows.append({
            "case": case["name"], "ranks": ranks, "tets_per_rank": round(total_tets / ranks) if case["mode"] == "strong"
            else case["tets_per_rank"],
            "slowest_part_tets": round(part["tets"]), "slowest_part_boundary_tets": round(part["boundary"]),
            "slowest_part_neighbours": part["neighbours"], "slowest_part_shared_pairs": round(part["pairs"]),
            "max_neighbours": max(p["neighbours"] for p in parts),
            "bytes_sent_per_iteration": round(slowest["bytes_sent"]),
            # Whether a message is eager or rendezvous decides whether it
            # moves during the interior pass without asynchronous progress.
            "bytes_per_message": round(slowest["bytes_sent"] / part["neighbours"]) if part["neighbours"] else 0,
            "compute_us": slowest["compute"] * 1e6, "halo_us": slowest["halo"] * 1e6,
            "allreduce_us": slowest["allreduce"] * 1e6,
            "iteration_us_overlap": slowest["overlap"] * 1e6, "iteration_us_no_overlap": worst_no_overlap * 1e6,
        })
    base = rows[0]
    for r in rows:
        for kind in ("overlap", "no_overlap"):
            ratio = base[f"iteration_us_{kind}"] / r[f"iteration_us_{kind}"]
            r[f"efficiency_{kind}"] = ratio / r["ranks"] if case["mode"] == "strong" else ratio
    return rows


def write_partition_summary(folder, out):
    lines = ["# Partitions of the 10.36M-tet helix: per P, the figures that set its slowest part", "",
             "From the CSVs in `partitions/` (`descent partition --stats`, boundary tets from "
             "`bench/partition_boundary_tets.py`). Imbalance: most tets in a part / mean. Pairs: "
             "shared (vertex, neighbour) pairs, the values one exchange sends per vertex component.", "",
             "| partitioner | P | mean tets | imbalance | neighbours max (mean) | pairs max | pairs total | "
             "boundary tets max share |", "| --- | --- | --- | --- | --- | --- | --- | --- |"]
    for method in ("ptscotch", "metis"):
        for parts in sorted(int(m.group(1)) for p in folder.glob(f"{method}-*.csv")
                            if (m := re.fullmatch(rf"{method}-(\d+)\.csv", p.name))):
            ps = read_partition(folder, method, parts)
            mean = sum(p["tets"] for p in ps) / parts
            lines.append(
                f"| {method} | {parts} | {mean:,.0f} | {max(p['tets'] for p in ps) / mean:.3f} | "
                f"{max(p['neighbours'] for p in ps)} ({statistics.mean(p['neighbours'] for p in ps):.1f}) | "
                f"{max(p['pairs'] for p in ps):,} | {sum(p['pairs'] for p in ps):,} | "
                f"{max(p['boundary'] / p['tets'] for p in ps):.1%} |")
    (out / "partitions.md").write_text("\n".join(lines) + "\n")


def write_tables(rows, cases, assumptions, out):
    columns = list(rows[0])
    with open(out / "scaling_model.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=columns)
        writer.writeheader()
        for r in rows:
            writer.writerow({k: (f"{v:.7g}" if isinstance(v, float) else v) for k, v in r.items()})
    lines = ["# Modelled scaling of the Chebyshev iteration (a model, not a measurement)", "",
             "Inputs and assumptions:", ""]
    lines += [f"- {k}: {v}" for k, v in assumptions.items()]
    for case in cases:
        lines += ["", f"## {case['title']}", "",
                  "| ranks | tets per rank | slowest part: tets, boundary, neighbours, pairs | sent per iteration "
                  "(per message) | "
                  "compute us | halo us | allreduce us | us per iteration (overlap) | efficiency (overlap) | "
                  "us per iteration (no overlap) | efficiency (no overlap) |",
                  "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
        for r in (r for r in rows if r["case"] == case["name"]):
            lines.append(
                f"| {r['ranks']} | {r['tets_per_rank']:,} | {r['slowest_part_tets']:,}, "
                f"{r['slowest_part_boundary_tets']:,}, {r['slowest_part_neighbours']}, "
                f"{r['slowest_part_shared_pairs']:,} | {r['bytes_sent_per_iteration'] / 1e3:.1f} kB "
                f"({r['bytes_per_message'] / 1e3:.1f} kB) | "
                f"{r['compute_us']:,.0f} | {r['halo_us']:,.1f} | {r['allreduce_us']:.2f} | "
                f"{r['iteration_us_overlap']:,.0f} | {r['efficiency_overlap']:.1%} | "
                f"{r['iteration_us_no_overlap']:,.0f} | {r['efficiency_no_overlap']:.1%} |")
    (out / "scaling_model.md").write_text("\n".join(lines) + "\n")
    return lines


def plot(rows, cases, out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (strong_axes, weak_axes, efficiency_axes) = plt.subplots(1, 3, figsize=(16, 4.8))
    colours = {"strong_cpu": "C0", "weak_cpu": "C1", "weak_gpu": "C2", "strong_cpu_multilevel": "C3",
               "weak_cpu_multilevel": "C4"}
    for case in cases:
        mine = [r for r in rows if r["case"] == case["name"]]
        ranks = [r["ranks"] for r in mine]
        colour = colours[case["name"]]
        axes = strong_axes if case["mode"] == "strong" else weak_axes
        axes.loglog(ranks, [r["iteration_us_overlap"] / 1e3 for r in mine], "o-", color=colour,
                    label=f"{case['label']}: with overlap")
        axes.loglog(ranks, [r["iteration_us_no_overlap"] / 1e3 for r in mine], "--", color=colour,
                    label=f"{case['label']}: no overlap")
        # From 2 ranks: one rank exchanges nothing (no point on a log axis).
        axes.loglog(ranks[1:], [(r["halo_us"] + r["allreduce_us"]) / 1e3 for r in mine[1:]], ":", color=colour,
                    label=f"{case['label']}: halo + allreduce")
        if case["mode"] == "strong":
            axes.loglog(ranks, [mine[0]["iteration_us_overlap"] / 1e3 / p for p in ranks], "-", color="grey",
                        linewidth=0.8, label="ideal")
        efficiency_axes.semilogx(ranks, [r["efficiency_overlap"] for r in mine], "o-", color=colour,
                                 label=f"{case['label']}: with overlap")
        efficiency_axes.semilogx(ranks, [r["efficiency_no_overlap"] for r in mine], "--", color=colour,
                                 label=f"{case['label']}: no overlap")
    strong_axes.set(xlabel="ranks", ylabel="ms per iteration (slowest rank)",
                    title="strong: 10.36M-tet helix, CPU cores")
    weak_axes.set(xlabel="ranks", ylabel="ms per iteration (slowest rank)", title="weak: fixed tets per rank")
    efficiency_axes.axhline(1, color="grey", linewidth=0.8)
    efficiency_axes.set(xlabel="ranks", ylabel="parallel efficiency", title="efficiency (model)",
                        ylim=(min(0.5, 0.1 * math.floor(10 * min(r["efficiency_no_overlap"] for r in rows))),
                              1.02 * max(1, max(r["efficiency_overlap"] for r in rows))))
    ticks = sorted({r["ranks"] for r in rows})
    for axes in (strong_axes, weak_axes, efficiency_axes):
        axes.set_xticks(ticks, [str(p) for p in ticks])
        axes.minorticks_off()
        axes.legend(fontsize=7)
    fig.suptitle("Modelled from real PT-Scotch partitions, CPU cost measured on one core here; "
                 "network and GPU figures are assumptions (README.md)", fontsize=9)
    fig.tight_layout()
    fig.savefig(out / "scaling_model.png", dpi=110)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--partitions", type=Path, default=RESULTS / "partitions")
    parser.add_argument("--method", default="ptscotch", help="partitioner whose CSVs the model uses")
    parser.add_argument("--compute-cost", type=Path, default=RESULTS / "compute_cost.csv",
                        help="bench/scaling_compute_cost.py's CSV (measured CPU ns per tet-iteration)")
    parser.add_argument("--cpu-cost", choices=["pooled", "by-size"], default="pooled",
                        help="from the CSV: the median of all samples, or the medians per size interpolated")
    parser.add_argument("--cpu-ns", type=float, help="a constant CPU ns per tet-iteration instead of the CSV")
    parser.add_argument("--gpu-ns", type=float, default=round(PAPER_GPU_NS, 2),
                        help="ASSUMED GPU ns per tet-iteration (default: the paper's Table 1, 316K helix "
                             "on a GTX TITAN X; not measured here)")
    parser.add_argument("--latency-us", type=float, default=2.0, help="ASSUMED point-to-point latency per message")
    parser.add_argument("--allreduce-latency-us", type=float, default=2.0,
                        help="ASSUMED cost per log2(P) stage of the energy allreduce")
    parser.add_argument("--cpu-node-bandwidth", type=float, default=25.0,
                        help="ASSUMED GB/s a CPU node injects (200 Gb/s), shared by its ranks")
    parser.add_argument("--cpu-ranks-per-node", type=int, default=64, help="ASSUMED ranks (cores) per CPU node")
    parser.add_argument("--gpu-node-bandwidth", type=float, default=100.0,
                        help="ASSUMED GB/s a GPU node injects (4 x 200 Gb/s), shared by its ranks")
    parser.add_argument("--gpu-ranks-per-node", type=int, default=4, help="ASSUMED GPUs (ranks) per node")
    parser.add_argument("--pcie-gbs", type=float, default=25.0, help="ASSUMED host-device copy GB/s")
    parser.add_argument("--copy-latency-us", type=float, default=10.0,
                        help="ASSUMED per host-device copy, with the host's wait for the stream")
    parser.add_argument("--pack-ns", type=float, default=1.0,
                        help="ASSUMED host ns per value packed or summed in the exchange")
    parser.add_argument("--hessian-interval", type=int, default=32, help="M: iterations between diagonal refreshes")
    parser.add_argument("--check-interval", type=int, default=8, help="iterations between energy allreduces")
    parser.add_argument("--weak-cpu-tets", type=int, default=323_690,
                        help="tets per CPU rank (default: the 10.36M helix's mean part at P = 32)")
    parser.add_argument("--weak-gpu-tets", type=int, default=5_000_000, help="tets per GPU")
    # Measured on the 1M helix, 2 ranks (bench/results/multilevel/memory/):
    # a Jacobi iteration 54.0 ms, a multilevel one 146 ms, a refresh 1171 ms.
    parser.add_argument("--ml-iteration-factor", type=float, default=2.70,
                        help="MEASURED: an iteration with its V-cycle in Jacobi iterations' cost per tet")
    parser.add_argument("--ml-refresh-factor", type=float, default=21.7,
                        help="MEASURED: one refresh in Jacobi iterations' cost per tet")
    parser.add_argument("--ml-iterations-per-step", type=float, default=16,
                        help="MEASURED: iterations per step with multilevel (the main job at 1e-2)")
    parser.add_argument("--ml-degree", type=int, default=2, help="solver.multilevel_smoother_degree")
    parser.add_argument("--ml-levels", type=float, nargs="+", default=[1_031_208, 200_480, 5_304, 834, 154],
                        help="MEASURED: tets of a run, then nodes per level (vertices first, coarsest last)")
    parser.add_argument("--ml-level-ratio", type=float, default=6.0,
                        help="ASSUMED: nodes of a level over the next one's, beyond the measured levels")
    parser.add_argument("--ml-coarse-size", type=float, default=2000, help="solver.multilevel_coarse_size")
    parser.add_argument("--ml-coarsest-row-blocks", type=float, default=154,
                        help="ASSUMED: 6x6 blocks per row of the coarsest operator (default: dense, the "
                             "1M helix's coarsest nodes, an upper bound)")
    parser.add_argument("--ml-halo-widening", type=float, default=2.0,
                        help="ASSUMED: a coarse level's shared nodes over the surface scaling's")
    parser.add_argument("--out", type=Path, default=RESULTS)
    args = parser.parse_args()

    counts = partition_counts(args.partitions, args.method)
    partitions = {p: read_partition(args.partitions, args.method, p) for p in counts}
    cpu_ns = CpuCost(args.compute_cost, args.cpu_cost, args.cpu_ns)
    gpu_ns = lambda tets: args.gpu_ns
    cpu = {"bytes_per_value": 8, "node_bandwidth": args.cpu_node_bandwidth,
           "ranks_per_node": args.cpu_ranks_per_node, "device_copies": False, "ns": cpu_ns}
    gpu = {"bytes_per_value": 4, "node_bandwidth": args.gpu_node_bandwidth,
           "ranks_per_node": args.gpu_ranks_per_node, "device_copies": True, "ns": gpu_ns}
    total = sum(p["tets"] for p in partitions[counts[0]])
    cases = [
        dict(cpu, name="strong_cpu", mode="strong", label="strong CPU",
             title=f"Strong scaling, CPU: the {total:,}-tet helix on P cores (double)"),
        dict(cpu, name="weak_cpu", mode="weak", tets_per_rank=args.weak_cpu_tets, label="weak CPU",
             title=f"Weak scaling, CPU: {args.weak_cpu_tets:,} tets per core (double)"),
        dict(gpu, name="weak_gpu", mode="weak", tets_per_rank=args.weak_gpu_tets, label="weak GPU (assumed cost)",
             title=f"Weak scaling, GPU: {args.weak_gpu_tets:,} tets per GPU (float; GPU cost ASSUMED, "
                   "not measured)"),
        dict(cpu, name="strong_cpu_multilevel", mode="strong", label="strong CPU, multilevel", multilevel=True,
             title=f"Strong scaling, CPU, multilevel preconditioner: the {total:,}-tet helix on P cores"),
        dict(cpu, name="weak_cpu_multilevel", mode="weak", tets_per_rank=args.weak_cpu_tets,
             label="weak CPU, multilevel", multilevel=True,
             title=f"Weak scaling, CPU, multilevel preconditioner: {args.weak_cpu_tets:,} tets per core"),
    ]
    rows = [r for case in cases for r in model_case(case, partitions, args)]
    assumptions = {
        "partitions": f"{args.method}, P = {', '.join(map(str, counts))} ({args.partitions.relative_to(ROOT) if args.partitions.is_relative_to(ROOT) else args.partitions})",
        "CPU ns per tet-iteration (measured, one core)": cpu_ns.describe(),
        "GPU ns per tet-iteration (ASSUMED)": f"{args.gpu_ns} ns (paper Table 1: 316K helix, 122 ms a 96-iteration "
                                              "frame, GTX TITAN X)" if args.gpu_ns == round(PAPER_GPU_NS, 2)
        else f"{args.gpu_ns} ns (--gpu-ns)",
        "values per shared pair and iteration": f"3 + 3/M = {3 + 3 / args.hessian_interval:.4g} (M = "
                                                f"{args.hessian_interval}); 8 bytes CPU, 4 bytes GPU",
        "latency per message (ASSUMED)": f"{args.latency_us} us",
        "allreduce (ASSUMED)": f"ceil(log2 P) x {args.allreduce_latency_us} us every {args.check_interval} iterations",
        "CPU network (ASSUMED)": f"{args.cpu_node_bandwidth} GB/s per node shared by min(P, {args.cpu_ranks_per_node}) ranks",
        "GPU network (ASSUMED)": f"{args.gpu_node_bandwidth} GB/s per node shared by min(P, {args.gpu_ranks_per_node}) ranks",
        "host-device copies (ASSUMED, GPU)": f"2 per iteration, {args.copy_latency_us} us + bytes / {args.pcie_gbs} GB/s",
        "pack and rank-order sums (ASSUMED)": f"{args.pack_ns} ns per value",
        "weak scaling": "parts of the P-part partition scaled to the tets per rank; shared vertices, pairs and "
                        "boundary tets by (tets per rank / mean tets per part)^(2/3); neighbours as measured",
        "multilevel (measured here)": f"an iteration {args.ml_iteration_factor} and a refresh "
                                      f"{args.ml_refresh_factor} Jacobi iterations' cost, "
                                      f"{args.ml_iterations_per_step} iterations a step; levels "
                                      f"{args.ml_levels[1:]} nodes at {args.ml_levels[0]:,.0f} tets, "
                                      f"coarsest rows of {args.ml_coarsest_row_blocks} blocks",
        "multilevel (ASSUMED)": f"{args.ml_level_ratio}x fewer nodes per further level; coarse halos "
                                f"{args.ml_halo_widening}x the surface scaling; neighbours as the finest's",
    }
    args.out.mkdir(parents=True, exist_ok=True)
    write_partition_summary(args.partitions, args.out)
    lines = write_tables(rows, cases, assumptions, args.out)
    plot(rows, cases, args.out)
    print("\n".join(lines))
    print(f"wrote {args.out}/scaling_model.csv, scaling_model.md, scaling_model.png, partitions.md")


if __name__ == "__main__":
    main()
