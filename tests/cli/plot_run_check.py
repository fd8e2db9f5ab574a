#!/usr/bin/python3
"""Render a small run's picture and movie with tools/plot_run.py, headless.

    plot_run_check.py PLOT_RUN OUT_DIR

OUT_DIR holds a run that wrote every frame. The picture must be a PNG of the
size asked for, and the movie an H.264 MP4 of the default size (720 pixels
tall, as wide as the view needs, rounded to even: yuv420p refuses odd sizes)
with one frame per frame group of frames.h5 (ffprobe counts the frames it
decodes). And the boundary surface the tool draws must enclose the mesh:
wound outward, its divergence-theorem volume equals the tets' total volume.
Exits 77 (the test's SKIP_RETURN_CODE) when h5py, matplotlib or ffmpeg is
missing: CI installs them (scripts/install-deps.sh), a user's machine may not.
"""
import importlib.util
import shutil
import struct
import subprocess
import sys
from pathlib import Path

try:
    import h5py
except ImportError as error:
    print(f"SKIP: {error} (install python3-h5py)")
    sys.exit(77)
if importlib.util.find_spec("matplotlib") is None:
    print("SKIP: no matplotlib (install python3-matplotlib)")
    sys.exit(77)
if shutil.which("ffmpeg") is None or shutil.which("ffprobe") is None:
    print("SKIP: no ffmpeg/ffprobe (install ffmpeg)")
    sys.exit(77)


def fail(message):
    print(f"FAIL: {message}")
    sys.exit(1)


def png_size(path):
    """(width, height) from a PNG's IHDR chunk, which follows the 8-byte signature."""
    data = path.read_bytes()[:24]
    if data[:8] != b"\x89PNG\r\n\x1a\n" or data[12:16] != b"IHDR":
        fail(f"{path} is not a PNG")
    return struct.unpack(">II", data[16:24])


def movie_stream(path):
    """(codec, width, height, decoded frame count) of the movie's video stream."""
    out = subprocess.run(["ffprobe", "-v", "error", "-count_frames", "-select_streams", "v:0",
                          "-show_entries", "stream=codec_name,width,height,nb_read_frames",
                          "-of", "csv=p=0", str(path)], capture_output=True, text=True, check=True)
    codec, width, height, frames = out.stdout.strip().split(",")
    return codec, int(width), int(height), int(frames)


def check_surface(tool, out):
    """The enclosed volume of plot_run.boundary_faces against the tets' volume."""
    sys.path.insert(0, str(tool.parent))
    import numpy as np
    from plot_run import boundary_faces
    with h5py.File(out / "frames.h5", "r") as f:
        tets, x = f["mesh/tets"][()], f["mesh/rest_positions"][()]
    faces = boundary_faces(tets, x)
    a, b, c = x[faces[:, 0]], x[faces[:, 1]], x[faces[:, 2]]
    enclosed = np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6
    p = x[tets]
    total = np.abs(np.einsum("ij,ij->i", p[:, 1] - p[:, 0], np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 0]))).sum() / 6
    if not np.isclose(enclosed, total, rtol=1e-12):
        fail(f"boundary surface encloses {enclosed}, the tets hold {total}")


def main():
    tool, out = Path(sys.argv[1]), Path(sys.argv[2])
    check_surface(tool, out)
    png, mp4 = out / "check.png", out / "check.mp4"
    for stale in (png, mp4):
        stale.unlink(missing_ok=True)
    subprocess.run([sys.executable, str(tool), str(out), "--output", str(png), "--movie", str(mp4),
                    "--size", "800x500", "--views", "3"], check=True)
    with h5py.File(out / "frames.h5", "r") as f:
        frames = len(f["frames"])
    if png_size(png) != (800, 500):
        fail(f"{png} is {png_size(png)}, asked for 800x500")
    codec, width, height, decoded = movie_stream(mp4)
    if (codec, height, decoded) != ("h264", 720, frames) or width % 2:
        fail(f"{mp4}: {codec} {width}x{height} with {decoded} frames, want h264, an even width x 720, {frames} frames")
    print(f"OK: {png} 800x500, {mp4} h264 {width}x{height} with {frames} frames")


if __name__ == "__main__":
    main()
