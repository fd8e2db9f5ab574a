#!/usr/bin/env python3
"""A run renumbered for locality writes what the run in input order writes.

    reorder_output.py OUT_NONE OUT_RCM

The two directories hold frames.h5 of one scene run with partition.reorder
= "none" and = "rcm" (src/partition/local_order.hpp). Output is in input
vertex order either way: the rest mesh and its tets must be equal bit for
bit, and every frame's positions and velocities equal to round-off (1e-12
of the mesh's extent, and of the largest speed), since only the order of
sums differs. Exits 77 (the test's SKIP_RETURN_CODE) without h5py.
"""
import sys

try:
    import h5py
    import numpy as np
except ImportError as error:
    print(f"SKIP: {error} (install python3-h5py)")
    sys.exit(77)


def fail(message):
    print(f"FAIL: {message}")
    sys.exit(1)


none_dir, rcm_dir = sys.argv[1:3]
with h5py.File(f"{none_dir}/frames.h5", "r") as none, h5py.File(f"{rcm_dir}/frames.h5", "r") as rcm:
    for name in ("mesh/rest_positions", "mesh/tets"):
        if not np.array_equal(none[name][()], rcm[name][()]):
            fail(f"{name} differs: output is not in input order")
    rest = none["mesh/rest_positions"][()]
    extent = np.linalg.norm(rest.max(axis=0) - rest.min(axis=0))
    frames = sorted(none["frames"].keys())
    if frames != sorted(rcm["frames"].keys()) or len(frames) < 2:
        fail(f"frames differ or too few: {frames} / {sorted(rcm['frames'].keys())}")
    for frame in frames:
        for field, scale in (("positions", extent), ("velocity", None)):
            a, b = none[f"frames/{frame}/{field}"][()], rcm[f"frames/{frame}/{field}"][()]
            bound = 1e-12 * (scale if scale else max(np.abs(a).max(), 1e-300))
            worst = np.abs(a - b).max()
            if worst > bound:
                fail(f"frame {frame}: {field} differ by {worst:.3g} (bound {bound:.3g})")
    moved = np.abs(none[f"frames/{frames[-1]}/positions"][()] - rest).max()
    if moved < 1e-6 * extent:
        fail(f"the body did not move ({moved:.3g}): nothing compared")
print(f"OK: {len(frames)} frames equal to round-off, rest mesh and tets bit for bit")
