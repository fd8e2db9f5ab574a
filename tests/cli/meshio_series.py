#!/usr/bin/env python3
"""Read a run's frames.xdmf the way meshio users do and check it against frames.h5.

    meshio_series.py OUT_DIR

OUT_DIR holds frames.xdmf and frames.h5 of a run that wrote every frame
(output.every = 1). meshio.xdmf.TimeSeriesReader must give the rest mesh from
read_points_cells() and, per frame, the time and the point data
"displacement" and "velocity", equal to the datasets of frames.h5; there must
be one step per frame group, times increasing, displacement changing, and the
velocity the simulation's: (displacement_k - displacement_{k-1}) / dt, since
a step sets v = (q - q_t) / h.
Exits 77 (the test's SKIP_RETURN_CODE) when meshio or h5py is not installed.
"""
import pathlib
import sys

try:
    import h5py
    import meshio
    import numpy as np
except ImportError as error:
    print(f"SKIP: {error} (install python3-meshio and python3-h5py)")
    sys.exit(77)


def fail(message):
    print(f"FAIL: {message}")
    sys.exit(1)


def main():
    out = pathlib.Path(sys.argv[1])
    with h5py.File(out / "frames.h5", "r") as h5:
        rest = h5["/mesh/rest_positions"][()]
        tets = h5["/mesh/tets"][()]
        names = sorted(h5["/frames"])  # zero-padded: by name is by frame
        frames = [
            {
                "time": float(h5["/frames"][name].attrs["time"]),
                **{key: h5["/frames"][name][key][()] for key in ("positions", "displacement", "velocity")},
            }
            for name in names
        ]

    with meshio.xdmf.TimeSeriesReader(out / "frames.xdmf") as reader:
        points, cells = reader.read_points_cells()
        if not np.array_equal(points, rest):
            fail("read_points_cells() does not give /mesh/rest_positions")
        if len(cells) != 1 or cells[0].type != "tetra" or not np.array_equal(cells[0].data, tets):
            fail(f"read_points_cells() does not give /mesh/tets as one tetra block: {cells}")
        if reader.num_steps != len(frames):
            fail(f"{reader.num_steps} steps in frames.xdmf, {len(frames)} frame groups in frames.h5")
        steps = [reader.read_data(k) for k in range(reader.num_steps)]

    for k, ((time, point_data, _), frame) in enumerate(zip(steps, frames)):
        if time != frame["time"]:
            fail(f"step {k}: time {time}, frames.h5 says {frame['time']}")
        for key in ("displacement", "velocity"):
            if key not in point_data:
                fail(f"step {k}: no point data {key!r} (has {sorted(point_data)})")
            if not np.array_equal(point_data[key], frame[key]):
                fail(f"step {k}: {key} differs from /frames/{names[k]}/{key}")
        if not np.array_equal(frame["displacement"], frame["positions"] - rest):
            fail(f"step {k}: displacement is not positions - rest_positions")

    times = np.array([time for time, _, _ in steps])
    if not np.all(np.diff(times) > 0):
        fail(f"times do not increase: {times}")
    displacements = [point_data["displacement"] for _, point_data, _ in steps]
    velocities = [point_data["velocity"] for _, point_data, _ in steps]
    if not np.all(velocities[0] == 0):
        fail("frame 0 starts at rest, but its velocity is not zero")
    for k in range(1, len(steps)):
        if np.array_equal(displacements[k], displacements[k - 1]):
            fail(f"displacement of step {k} equals that of step {k - 1}")
        difference = (displacements[k] - displacements[k - 1]) / (times[k] - times[k - 1])
        if not np.allclose(velocities[k], difference, rtol=1e-6, atol=1e-9):
            error = np.max(np.abs(velocities[k] - difference))
            fail(f"step {k}: velocity is not the displacement's difference quotient (off by {error:g})")

    largest = np.max(np.linalg.norm(displacements[-1], axis=1))
    mean_vy = np.mean(velocities[-1][:, 1])
    print(
        f"meshio read {len(steps)} steps of {len(points)} vertices and {len(tets)} tets, "
        f"t = {times[0]:g} .. {times[-1]:g}; largest displacement {largest:.6g}, "
        f"mean y velocity {mean_vy:.6g} at the end; all equal to frames.h5"
    )


if __name__ == "__main__":
    main()
