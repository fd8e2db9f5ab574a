r"""Open a run's frames.xdmf in ParaView, step through time, check what it
reads, and save a picture coloured by displacement magnitude.

    xvfb-run -a pvpython tools/paraview_check.py OUT_DIR/frames.xdmf \
        [--png picture.png] [--time T]

(pvpython needs an X display to render: xvfb-run gives it one on a machine
without.) At every time step ParaView's Xdmf3 reader must give the full tet
mesh (the topology the first grid holds, included by the others), node
arrays "displacement" and "velocity" (3 components), and per-step points
whose points - displacement is the same rest shape at every step. The
picture shows the step at --time (default: the last), coloured by |u| with
one colour range over the whole run. Exits 1 with a message when a check
fails. docs/paraview_displacement.png is the last step of

    mpiexec -n 2 descent run jobs/helix.toml --set time.frames=20 --out /tmp/pvrun
    xvfb-run -a pvpython tools/paraview_check.py /tmp/pvrun/frames.xdmf \
        --png docs/paraview_displacement.png
"""
import argparse
import sys

import numpy as np
from paraview import servermanager
from paraview.simple import (
    ColorBy,
    GetActiveViewOrCreate,
    GetColorTransferFunction,
    GetScalarBar,
    OpenDataFile,
    Render,
    SaveScreenshot,
    Show,
)
from paraview.vtk.numpy_interface import dataset_adapter as dsa


def fail(message):
    print(f"FAIL: {message}")
    sys.exit(1)


def first_leaf(data):
    """The one unstructured grid of the reader's output, whether it comes
    alone or inside a multiblock."""
    if data.IsA("vtkCompositeDataSet"):
        iterator = data.NewIterator()
        iterator.InitTraversal()
        return iterator.GetCurrentDataObject()
    return data


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("xdmf")
    parser.add_argument("--png", help="save the picture here")
    parser.add_argument("--time", type=float, help="time of the picture (default: the last step)")
    args = parser.parse_args()

    reader = OpenDataFile(args.xdmf)
    if reader is None:
        fail(f"ParaView has no reader for {args.xdmf}")
    reader.UpdatePipelineInformation()
    times = list(reader.TimestepValues)
    if len(times) < 2:
        fail(f"{len(times)} time step(s): frames.xdmf should be a time series")

    rest = None
    num_cells = None
    largest = 0.0
    for time in times:
        reader.UpdatePipeline(time)
        grid = first_leaf(servermanager.Fetch(reader))
        data = dsa.WrapDataObject(grid)
        for name in ("displacement", "velocity"):
            if name not in data.PointData.keys() or data.PointData[name].shape[1:] != (3,):
                fail(f"t = {time:g}: no 3-component node array {name!r} ({data.PointData.keys()})")
        if num_cells is None:
            num_cells = grid.GetNumberOfCells()
        if grid.GetNumberOfCells() != num_cells or num_cells == 0:
            fail(f"t = {time:g}: {grid.GetNumberOfCells()} cells, {num_cells} at the first step")
        points = np.asarray(data.Points)
        displacement = np.asarray(data.PointData["displacement"])
        if rest is None:
            rest = points - displacement
        elif not np.allclose(points - displacement, rest, rtol=0, atol=1e-12):
            fail(f"t = {time:g}: points - displacement is not the rest shape of the first step")
        magnitude = np.linalg.norm(displacement, axis=1)
        speed = np.linalg.norm(np.asarray(data.PointData["velocity"]), axis=1)
        largest = max(largest, float(magnitude.max()))
        print(
            f"t = {time:.6g}: {grid.GetNumberOfPoints()} points, {num_cells} cells, "
            f"|u| max {magnitude.max():.6g}, |v| max {speed.max():.6g}"
        )
    print(f"ParaView read {len(times)} time steps with displacement and velocity at every one")

    if args.png:
        view = GetActiveViewOrCreate("RenderView")
        view.ViewSize = [900, 1200]
        view.ViewTime = args.time if args.time is not None else times[-1]
        display = Show(reader, view)
        ColorBy(display, ("POINTS", "displacement", "Magnitude"))
        colours = GetColorTransferFunction("displacement")
        colours.VectorMode = "Magnitude"
        colours.RescaleTransferFunction(0.0, largest)
        display.SetScalarBarVisibility(view, True)
        bar = GetScalarBar(colours, view)
        bar.Title = "displacement magnitude (m)"
        bar.ComponentTitle = ""
        view.CameraPosition = [0.0, 0.0, 1.0]
        view.CameraFocalPoint = [0.0, 0.0, 0.0]
        view.CameraViewUp = [0.0, 1.0, 0.0]
        view.ResetCamera()
        Render(view)
        SaveScreenshot(args.png, view, ImageResolution=[900, 1200])
        print(f"wrote {args.png} (t = {view.ViewTime:g})")


if __name__ == "__main__":
    main()
