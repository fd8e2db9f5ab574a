#!/usr/bin/python3
"""Boundary tets per part of a partition file (`descent partition -o PIECES.h5`).

  bench/partition_boundary_tets.py PIECES.h5 OUT.csv

A part's boundary tets are those with at least one shared vertex (a vertex
that tets of another part use too): the tets the iteration computes before
it posts the halo exchange, while the interior tets overlap it
(src/partition/local_mesh.cpp orders them so; src/solver/
iteration_engine_impl.hpp). `descent partition --stats` does not report
them, and the overlap model of bench/scaling_model.py needs them, so they
are counted here from the file's tets. As a check on the counting, each
part's tets and shared vertices are compared with what the partitioner
itself wrote (/partition/part_stats); a mismatch is an error.

Writes OUT.csv: part,tets,shared_vertices,boundary_tets.
Needs Debian's python3-h5py (and numpy).
"""
import argparse
import csv
import sys

import h5py
import numpy as np


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("pieces", help="partition file written by descent partition -o")
    parser.add_argument("out", help="CSV to write")
    args = parser.parse_args()

    with h5py.File(args.pieces, "r") as f:
        offsets = f["partition/tet_offsets"][...].ravel()
        corners = f["partition/tets"][...].reshape(-1)  # 4 global vertex ids per tet, parts in order
        part_stats = f["partition/part_stats"][...]
        num_vertices = f["mesh/positions"].shape[0]
    num_parts = len(offsets) - 1
    tets_per_part = np.diff(offsets)
    corner_part = np.repeat(np.arange(num_parts, dtype=np.int32), 4 * tets_per_part)

    # A vertex is shared when the lowest and highest part using it differ.
    lowest = np.full(num_vertices, num_parts, dtype=np.int32)
    highest = np.full(num_vertices, -1, dtype=np.int32)
    np.minimum.at(lowest, corners, corner_part)
    np.maximum.at(highest, corners, corner_part)
    shared = lowest != highest
    del lowest, highest, corner_part

    rows = []
    for p in range(num_parts):
        ids = corners[4 * offsets[p]:4 * offsets[p + 1]].reshape(-1, 4)
        on_shared = shared[ids]
        boundary = int(np.count_nonzero(on_shared.any(axis=1)))
        shared_vertices = int(np.unique(ids[on_shared]).size)
        if int(tets_per_part[p]) != int(part_stats[p, 0]) or shared_vertices != int(part_stats[p, 1]):
            sys.exit(f"{args.pieces}: part {p}: counted {tets_per_part[p]} tets and {shared_vertices} "
                     f"shared vertices, the partitioner wrote {part_stats[p, 0]} and {part_stats[p, 1]}")
        rows.append({"part": p, "tets": int(tets_per_part[p]), "shared_vertices": shared_vertices,
                     "boundary_tets": boundary})

    with open(args.out, "w", newline="") as out:
        writer = csv.DictWriter(out, fieldnames=["part", "tets", "shared_vertices", "boundary_tets"])
        writer.writeheader()
        writer.writerows(rows)
    most = max(rows, key=lambda r: r["boundary_tets"] / r["tets"])
    print(f"{args.out}: {num_parts} parts; largest boundary share: part {most['part']}, "
          f"{most['boundary_tets']} of {most['tets']} tets")


if __name__ == "__main__":
    main()
