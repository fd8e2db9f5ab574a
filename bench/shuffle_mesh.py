#!/usr/bin/env python3
"""Number a MEDIT .mesh file's vertices and tets at random, as a file may.

    python3 bench/shuffle_mesh.py IN.mesh OUT.mesh [--seed 2026]

Reads the Vertices and Tetrahedra sections (as `descent mesh -o X.mesh`
writes them), permutes the vertex numbering and the tet order with a fixed
seed, and writes the same mesh again: every tet keeps its corners in their
order (so its orientation), only the numbers change. bench/locality.py
measures what such a numbering costs the element loops.
"""
import argparse
import sys

import numpy as np


def read_section(lines, at, name, columns):
    """The rows of section `name` starting at lines[at] (its header), as an
    array of `columns` numbers per row, and the index after it."""
    count = int(lines[at + 1])
    rows = np.loadtxt(lines[at + 2:at + 2 + count], ndmin=2)
    if rows.shape != (count, columns):
        sys.exit(f"{name}: expected {count} rows of {columns} numbers, got {rows.shape}")
    return rows, at + 2 + count


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("input")
    parser.add_argument("output")
    parser.add_argument("--seed", type=int, default=2026)
    args = parser.parse_args()

    lines = [line.strip() for line in open(args.input)]
    vertices = tets = None
    at = 0
    while at < len(lines):
        if lines[at] == "Vertices":
            vertices, at = read_section(lines, at, f"{args.input}: Vertices", 4)
        elif lines[at] == "Tetrahedra":
            tets, at = read_section(lines, at, f"{args.input}: Tetrahedra", 5)
        else:
            at += 1
    if vertices is None or tets is None:
        sys.exit(f"{args.input}: needs a Vertices and a Tetrahedra section")

    random = np.random.default_rng(args.seed)
    new_of_old = random.permutation(len(vertices))  # 0-based
    shuffled_vertices = np.empty_like(vertices)
    shuffled_vertices[new_of_old] = vertices
    corners = new_of_old[tets[:, :4].astype(np.int64) - 1] + 1
    corners = corners[random.permutation(len(corners))]

    with open(args.output, "w") as out:
        out.write(f"MeshVersionFormatted 2\nDimension 3\nVertices\n{len(vertices)}\n")
        np.savetxt(out, shuffled_vertices[:, :3], fmt="%.17g", footer="", comments="",
                   delimiter=" ", newline=" 0\n")
        out.write(f"Tetrahedra\n{len(corners)}\n")
        np.savetxt(out, corners, fmt="%d", delimiter=" ", newline=" 0\n")
        out.write("End\n")
    print(f"wrote {args.output} ({len(vertices)} vertices, {len(corners)} tets, seed {args.seed})")


if __name__ == "__main__":
    main()
