#!/usr/bin/python3
"""Pictures and movies of a `descent run` output folder.

Draws the body's boundary surface (the tet faces that belong to one tet
only), lit from the camera's upper left and coloured by a field
(|displacement| by default), at a few frames with the per-frame stats
beneath, in one PNG; with --movie also an MP4 of every written frame.

  tools/plot_run.py out/helix              # out/helix/run.png
  tools/plot_run.py out/helix --movie      # ... and out/helix/run.mp4
  tools/plot_run.py out/helix_floor --scene jobs/contact/helix_floor.toml
                                           # ... with the scene's floor

Rendering is matplotlib's Agg, headless: each frame projects the surface
orthographically, keeps the faces that face the camera, sorts them back to
front (painter's algorithm) and draws them as one 2D polygon collection,
one colour per face. Every frame shares one view and one colour scale, so the frames
compare. --scene draws the scene's fixed plane obstacles (a floor, walls)
behind the body; moving planes, spheres and boxes are not drawn.
Needs Debian's python3-h5py and python3-matplotlib, and ffmpeg for --movie.
"""
import argparse
import csv
import shutil
import sys
import tomllib
from pathlib import Path

try:
    import h5py
    import numpy as np
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.animation import FFMpegWriter
    from matplotlib.collections import PolyCollection
except ImportError as e:
    sys.exit(f"plot_run.py needs python3-h5py and python3-matplotlib (apt-get install them): {e}")

DPI = 100  # sizes are given in pixels; this only converts them to inches
CMAP = "viridis"


def boundary_faces(tets, rest):
    """The faces that belong to exactly one tet, wound so their normal points out
    of it at rest. A face is keyed by its sorted vertex ids packed into two int64
    words (exact below about 3e9 vertices), which np.unique sorts about twice as
    fast as rows of three (3.3 s against 6.9 s for the 1M-tet helix)."""
    faces = np.concatenate([tets[:, [1, 2, 3]], tets[:, [0, 3, 2]], tets[:, [0, 1, 3]], tets[:, [0, 2, 1]]])
    opposite = np.concatenate([tets[:, 0], tets[:, 1], tets[:, 2], tets[:, 3]])
    s = np.sort(faces, axis=1)
    keys = np.empty(len(s), dtype=[("hi", np.int64), ("lo", np.int64)])
    keys["hi"] = s[:, 0]
    keys["lo"] = s[:, 1] * (int(s.max()) + 1) + s[:, 2]
    _, first, counts = np.unique(keys, return_index=True, return_counts=True)
    once = first[counts == 1]
    faces, opposite = faces[once], opposite[once]
    a, b, c = rest[faces[:, 0]], rest[faces[:, 1]], rest[faces[:, 2]]
    inward = np.einsum("ij,ij->i", np.cross(b - a, c - a), rest[opposite] - a) > 0
    faces[inward] = faces[inward][:, [0, 2, 1]]
    return faces


def camera(azimuth, elevation):
    """Unit vectors (right, up, toward the camera) of an orthographic camera
    circling the vertical +y axis (the scenes' up: gravity is along -y)."""
    az, el = np.radians(azimuth), np.radians(elevation)
    toward = np.array([np.cos(el) * np.sin(az), np.sin(el), np.cos(el) * np.cos(az)])
    right = np.cross([0.0, 1.0, 0.0], toward)
    right /= np.linalg.norm(right)
    return right, np.cross(toward, right), toward


def project(points, view):
    """Screen coordinates of 3D points: (x right, y up)."""
    right, up, _ = view
    return np.stack([points @ right, points @ up], axis=-1)


def visible_faces(x, faces, view):
    """The faces facing the camera, back to front, and the normals to shade
    them with. Culling uses each face's own normal; shading uses the mean of
    its corners' normals (each the area-weighted sum of the faces around the
    vertex), which smooths the stair steps of a voxelized mesh, where flat
    shading draws every riser as a dark streak."""
    a, b, c = x[faces[:, 0]], x[faces[:, 1]], x[faces[:, 2]]
    area_normals = np.cross(b - a, c - a)
    toward = view[2]
    front = area_normals @ toward > 0
    depth = (a + b + c)[front] @ toward
    order = np.flatnonzero(front)[np.argsort(depth)]  # farthest first: nearer faces paint over it
    vertex_normals = np.stack([np.bincount(faces.ravel(), np.repeat(area_normals[:, k], 3), len(x))
                               for k in range(3)], axis=1)
    smooth = vertex_normals[faces[order]].sum(axis=1)
    smooth /= np.maximum(np.linalg.norm(smooth, axis=1, keepdims=True), 1e-300)
    return order, smooth


def shade(rgba, normals, view):
    """Lambert shading with some ambient light, from the camera's upper left."""
    right, up, toward = view
    light = toward + 0.6 * up - 0.4 * right
    light /= np.linalg.norm(light)
    intensity = 0.35 + 0.65 * np.clip(normals @ light, 0.0, None)
    out = rgba.copy()
    out[:, :3] *= intensity[:, None]
    return out


def draw_body(ax, x, values, faces, view, norm):
    """The surface at positions x, each face coloured by its vertices' mean value."""
    shown, normals = visible_faces(x, faces, view)
    tri = faces[shown]
    colours = shade(plt.get_cmap(CMAP)(norm(values[tri].mean(axis=1))), normals, view)
    polygons = project(x, view)[tri]
    ax.add_collection(PolyCollection(polygons, facecolors=colours, edgecolors="none",
                                     antialiased=False, zorder=2))


def read_planes(scene):
    """The scene's plane obstacles that do not move, as (point, unit normal)."""
    with open(scene, "rb") as f:
        obstacles = tomllib.load(f).get("obstacle", [])
    planes = []
    for o in obstacles:
        if o.get("kind") == "plane" and "motion" not in o:
            n = np.array(o["normal"], dtype=float)
            planes.append((np.array(o["point"], dtype=float), n / np.linalg.norm(n)))
    return planes


def clip(polygon, point, n):
    """The part of a convex polygon (rows of 3D corners) on the free side of
    the plane through `point` with normal n (Sutherland-Hodgman, one plane)."""
    kept = []
    for a, b in zip(polygon, np.roll(polygon, -1, axis=0)):
        da, db = (a - point) @ n, (b - point) @ n
        if da >= 0:
            kept.append(a)
        if (da >= 0) != (db >= 0):
            kept.append(a + da / (da - db) * (b - a))
    return np.array(kept).reshape(-1, 3)


def draw_planes(ax, planes, centre, size, view):
    """Each plane the camera sees from its free side, as a grey square of side
    `size` about the body's centre cut to the free side of the other planes
    (a wall ends at the floor), lit like the body (a floor and a wall differ
    in tone). These are the far faces of the free space, a convex region: they
    do not overlap on screen, and lie behind everything inside it, so drawing
    them first is always right."""
    for i, (point, n) in enumerate(planes):
        if n @ view[2] <= 0:
            continue
        on_plane = centre - ((centre - point) @ n) * n
        t1 = np.cross(n, [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 0.0, 1.0])
        t1 /= np.linalg.norm(t1)
        t2 = np.cross(n, t1)
        square = np.array([on_plane + size / 2 * (s1 * t1 + s2 * t2)
                           for s1, s2 in [(-1, -1), (1, -1), (1, 1), (-1, 1)]])
        for j, (other_point, other_n) in enumerate(planes):
            if j != i:
                square = clip(square, other_point, other_n)
        if len(square) < 3:
            continue
        grey = shade(np.array([[0.9, 0.9, 0.9, 1.0]]), n[None, :], view)
        ax.add_collection(PolyCollection([project(square, view)], facecolors=grey,
                                         edgecolors="none", zorder=1))


class Run:
    """A run's frames.h5: the rest mesh, its boundary surface, and per frame
    the positions and the field's magnitude."""

    def __init__(self, run_dir, field):
        self.file = h5py.File(run_dir / "frames.h5", "r")
        self.field = field
        tets = self.file["mesh/tets"][()]
        self.title = f"{run_dir.resolve().name}: {len(tets)} tets, {len(self.file['frames'])} frames"
        self.faces = boundary_faces(tets, self.file["mesh/rest_positions"][()])
        self.surface = np.unique(self.faces)
        self.names = sorted(self.file["frames"].keys())  # zero-padded: by name is by frame

    def frame(self, name):
        """(time, positions, |field| per vertex) of the frame group `name`."""
        g = self.file["frames"][name]
        return g.attrs["time"], g["positions"][()], np.linalg.norm(g[self.field][()], axis=1)

    def extent(self, names, view):
        """Screen box (xmin, xmax, ymin, ymax), the largest |field|, the 3D
        centre and size of the surface over the given frames: one view and
        one colour scale for all of them."""
        lo, hi, top, pts = np.full(2, np.inf), np.full(2, -np.inf), 0.0, []
        for name in names:
            _, x, v = self.frame(name)
            xs = x[self.surface]
            p = project(xs, view)
            lo, hi = np.minimum(lo, p.min(axis=0)), np.maximum(hi, p.max(axis=0))
            top = max(top, float(v[self.surface].max()))
            pts.append([xs.min(axis=0), xs.max(axis=0)])
        pts = np.array(pts)
        box_lo, box_hi = pts[:, 0].min(axis=0), pts[:, 1].max(axis=0)
        margin = 0.05 * max(hi - lo)
        return ((lo[0] - margin, hi[0] + margin, lo[1] - margin, hi[1] + margin), top,
                (box_lo + box_hi) / 2, float(np.max(box_hi - box_lo)))


def frame_axes(ax, box):
    """An equal-aspect axes on the common view, without ticks (the projection's
    screen coordinates mean little)."""
    ax.set_xlim(box[0], box[1])
    ax.set_ylim(box[2], box[3])
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_yticks([])


def figure(width, height):
    """A figure of exactly width x height pixels. Agg truncates inches x dpi
    to whole pixels, so 5.06 in at 100 dpi would come out 505 wide (an odd
    width ffmpeg's yuv420p refuses): half a pixel more truncates to the size asked."""
    return plt.figure(figsize=((width + 0.5) / DPI, (height + 0.5) / DPI), dpi=DPI)


def read_stats(path):
    """The numeric columns of stats.csv (`status` and the like are left out)."""
    if not path.exists():
        return {}
    with open(path) as f:
        rows = list(csv.DictReader(f))
    out = {}
    for k in rows[0] if rows else []:
        try:
            out[k] = [float(r[k]) for r in rows]
        except ValueError:
            continue
    return out


def draw_stats(fig, grid, stats):
    """One panel per stats.csv column this build wrote, in the grid's cell."""
    panels = [("wall_ms", "ms per frame"), ("iterations", "iterations per step"),
              ("alpha", "alpha at step end"), ("rollbacks", "rollbacks per step"),
              ("energy", "energy at last check [J]")]
    panels = [p for p in panels if p[0] in stats]
    cells = grid.subgridspec(1, max(1, len(panels)), wspace=0.35)
    for i, (key, label) in enumerate(panels):
        ax = fig.add_subplot(cells[0, i])
        ax.plot(stats["frame"], stats[key], lw=1)
        ax.set_xlabel("frame")
        ax.set_title(label, fontsize=10)


def field_label(field):
    return f"|{field}| [{'m' if field == 'displacement' else 'm/s'}]"


def write_picture(run, stats, views, view, planes, size, out):
    """The surface at `views` frames spread over the run, the stats beneath."""
    n = len(run.names)
    picks = [run.names[round(i * (n - 1) / max(1, views - 1))] for i in range(min(views, n))]
    box, top, centre, extent = run.extent(picks, view)
    norm = matplotlib.colors.Normalize(0.0, top or 1.0)
    fig = figure(*size)
    grid = fig.add_gridspec(2, 1, height_ratios=[2.2, 1], left=0.055, right=0.9, top=0.92, bottom=0.07,
                            hspace=0.2)
    row = grid[0].subgridspec(1, len(picks), wspace=0.05)
    for i, name in enumerate(picks):
        time, x, values = run.frame(name)
        ax = fig.add_subplot(row[0, i])
        draw_planes(ax, planes, centre, 2 * extent, view)
        draw_body(ax, x, values, run.faces, view, norm)
        frame_axes(ax, box)
        ax.set_title(f"frame {int(name)}  t = {time:.2f} s", fontsize=10)
    fig.suptitle(run.title)
    bar = fig.add_axes([0.92, 0.4, 0.012, 0.5])
    fig.colorbar(matplotlib.cm.ScalarMappable(norm, CMAP), cax=bar, label=field_label(run.field))
    if stats:
        draw_stats(fig, grid[1], stats)
    fig.savefig(out, dpi=DPI)
    plt.close(fig)
    print(f"wrote {out} ({size[0]}x{size[1]}, {len(run.faces)} surface triangles)")


def movie_size(box, height=720, bar=180, title=60):
    """A movie frame `height` pixels tall and as wide as the view's aspect
    needs beside a colour bar `bar` pixels wide, rounded up to even (yuv420p
    needs even sizes): a tall helix gets a narrow movie, not white margins."""
    aspect = (box[1] - box[0]) / (box[3] - box[2])
    width = int(np.ceil(aspect * (height - title))) + bar
    return width + width % 2, height


def write_movie(run, view, planes, size, fps, out):
    """Every frame of the run, one movie frame each, H.264 in yuv420p (what
    players expect), through ffmpeg. With no size, movie_size's."""
    box, top, centre, extent = run.extent(run.names, view)
    width, height = size or movie_size(box)
    norm = matplotlib.colors.Normalize(0.0, top or 1.0)
    fig = figure(width, height)
    ax = fig.add_axes([10 / width, 10 / height, 1 - 180 / width, 1 - 60 / height])
    bar = fig.add_axes([1 - 150 / width, 0.2, 15 / width, 0.6])
    fig.colorbar(matplotlib.cm.ScalarMappable(norm, CMAP), cax=bar, label=field_label(run.field))
    writer = FFMpegWriter(fps=fps, codec="libx264", extra_args=["-pix_fmt", "yuv420p"])
    with writer.saving(fig, str(out), DPI):
        for name in run.names:
            time, x, values = run.frame(name)
            ax.clear()
            draw_planes(ax, planes, centre, 2 * extent, view)
            draw_body(ax, x, values, run.faces, view, norm)
            frame_axes(ax, box)
            ax.set_title(f"frame {int(name)}  t = {time:.2f} s")
            writer.grab_frame()
    plt.close(fig)
    print(f"wrote {out} ({width}x{height}, {len(run.names)} frames at {fps} fps)")


def pixels(text):
    """WIDTHxHEIGHT in pixels, both even (what yuv420p video needs)."""
    w, h = (int(v) for v in text.lower().split("x"))
    if w <= 0 or h <= 0 or w % 2 or h % 2:
        raise argparse.ArgumentTypeError(f"{text}: want WIDTHxHEIGHT, both even and positive")
    return w, h


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("run_dir", type=Path)
    parser.add_argument("--output", type=Path, help="the picture (default DIR/run.png)")
    parser.add_argument("--views", type=int, default=4, help="frames in the picture (default 4)")
    parser.add_argument("--field", choices=["displacement", "velocity"], default="displacement",
                        help="colour by this field's magnitude (default displacement)")
    parser.add_argument("--movie", nargs="?", type=Path, const=True, default=None,
                        help="also write an MP4 of every frame (default DIR/run.mp4)")
    parser.add_argument("--scene", type=Path, help="the run's scene file: draws its fixed planes")
    parser.add_argument("--azimuth", type=float, default=30.0, help="degrees about +y (default 30)")
    parser.add_argument("--elevation", type=float, default=20.0, help="degrees above the xz plane (default 20)")
    parser.add_argument("--size", type=pixels, default=(1600, 1000), help="picture size (default 1600x1000)")
    parser.add_argument("--movie-size", type=pixels,
                        help="movie size (default 720 pixels tall, as wide as the view needs)")
    parser.add_argument("--fps", type=int, default=30, help="movie frames per second (default 30)")
    args = parser.parse_args()
    if args.movie is not None and shutil.which("ffmpeg") is None:
        sys.exit("plot_run.py --movie needs ffmpeg (apt-get install ffmpeg)")

    run = Run(args.run_dir, args.field)
    view = camera(args.azimuth, args.elevation)
    planes = read_planes(args.scene) if args.scene else []
    stats = read_stats(args.run_dir / "stats.csv")
    write_picture(run, stats, args.views, view, planes, args.size, args.output or args.run_dir / "run.png")
    if args.movie is not None:
        movie = args.run_dir / "run.mp4" if args.movie is True else args.movie
        write_movie(run, view, planes, args.movie_size, args.fps, movie)


if __name__ == "__main__":
    main()
