#!/usr/bin/env python3
"""Breaks copies of an HDF5 file that descent wrote, each one way, as a user
or a failing disk might: break_h5.py SOURCE DIR CASE... writes DIR/CASE.h5
for each CASE (one Python start for all: each costs most of a second). The
cases are the partition file's (docs/partition.md) and the frame file's;
tests/cli/binary_inputs.sh runs descent on each and checks its one error."""
import shutil
import sys

import h5py
import numpy as np


def replace(group, name, data):
    del group[name]
    group.create_dataset(name, data=data)


def break_file(path, case):
    with h5py.File(path, "r+") as f:
        if case.startswith("frames_"):
            first = sorted(f["frames"].keys())[0]
            if case == "frames_no_velocity":
                del f["frames"][first]["velocity"]
            elif case == "frames_time_nan":
                f["frames"][first].attrs["time"] = np.nan
            return
        part = f["partition"]
        offsets = part["tet_offsets"][...]
        if case == "offsets_past_end":
            offsets[-1] += 7
            part["tet_offsets"][...] = offsets
        elif case == "offsets_decreasing":
            offsets[-1] = offsets[-2] - 1
            part["tet_offsets"][...] = offsets
        elif case == "no_offsets":
            del part["tet_offsets"]
        elif case == "tet_twice":
            ids = part["tet_ids"][...]
            ids[offsets[-2]] = ids[0] if len(offsets) > 2 else ids[1]
            part["tet_ids"][...] = ids
        elif case == "vertex_out_of_range":
            tets = part["tets"][...]
            tets[0, 2] = f["mesh"]["positions"].shape[0] + 10
            part["tets"][...] = tets
        elif case == "num_parts":
            part.attrs["num_parts"] = np.int64(part.attrs["num_parts"] + 1)
        elif case == "float_ids":
            replace(part, "tet_ids", part["tet_ids"][...].astype(np.float64))
        elif case == "nan_position":
            positions = f["mesh"]["positions"][...]
            positions[0, 1] = np.nan
            f["mesh"]["positions"][...] = positions
        elif case == "surface_bits":
            surface = part["surface_faces"][...]
            surface[0] = 200
            part["surface_faces"][...] = surface
        elif case == "method":
            part.attrs["method"] = "scotch"
        elif case == "stats":
            stats = part["part_stats"][...]
            stats[0, 0] += 1
            part["part_stats"][...] = stats
        elif case == "short_tets":
            replace(part, "tets", part["tets"][:-1, :])
        else:
            sys.exit(f"break_h5.py: unknown case {case}")


def main():
    source, directory = sys.argv[1], sys.argv[2]
    for case in sys.argv[3:]:
        path = f"{directory}/{case}.h5"
        shutil.copyfile(source, path)
        break_file(path, case)


if __name__ == "__main__":
    main()
