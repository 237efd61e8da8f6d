"""growth.gif (growth.mp4 when ffmpeg is on PATH): the von Mises stress and
the fractures, one frame per step, from a result folder's step files.

The colour scale is logarithmic and fixed over the run, so that frames
compare: from the smallest 1st percentile of the positive nodal values of
any step (at least 1e-4 of the top) to the largest 99.5th percentile (the
tip singularity alone would otherwise set the top). The view is the
fractures' box at the end of the run, widened by half its size (the whole
domain when there are no fractures).
"""
from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np

#: frames per second
FPS = 4


def animation_format() -> str:
    """"mp4" when ffmpeg is on PATH, else "gif"."""
    return "mp4" if shutil.which("ffmpeg") else "gif"


def colour_range(von_mises: list) -> tuple[float, float]:
    """(vmin, vmax) of the run's logarithmic colour scale (Pa). Non-finite
    values (a crack-tip node, where the stress is singular, may hold NaN)
    are left out."""
    positive = [v[np.isfinite(v) & (v > 0)] for v in von_mises]
    positive = [v for v in positive if len(v)]
    if not positive:
        return 1.0, 10.0
    top = max(float(np.percentile(v, 99.5)) for v in positive)
    low = min(float(np.percentile(v, 1.0)) for v in positive)
    return max(low, 1e-4 * top), top


def view_box(frames) -> tuple[np.ndarray, np.ndarray]:
    """(lower-left, upper-right) corners of the view over all frames."""
    x = np.vstack([f.x for f, _ in frames])
    lo_mesh, hi_mesh = x.min(axis=0), x.max(axis=0)
    lines = frames[-1][1].lines
    if not len(lines):
        return lo_mesh, hi_mesh
    pts = lines.reshape(-1, 2)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    pad = 0.5 * max(hi - lo) + 1e-12
    return np.maximum(lo - pad, lo_mesh), np.minimum(hi + pad, hi_mesh)


def animate_growth(folder: Path, result, fmt: str | None = None) -> Path:
    """Write growth.gif or growth.mp4 (`fmt`, default animation_format())
    into `folder` for `result` (an io.outdir.StoredResult with at least
    one step) and return its path."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib import animation
    from matplotlib.collections import LineCollection, TriMesh
    from matplotlib.colors import LogNorm
    from matplotlib.tri import Triangulation

    fmt = fmt or animation_format()
    path = Path(folder) / f"growth.{fmt}"
    steps = result.steps
    frames = [(result.fields_of(k), result.faces_of(k)) for k in range(len(steps))]
    vmin, vmax = colour_range([f.von_mises for f, _ in frames])
    norm = LogNorm(vmin=vmin, vmax=vmax)
    lo, hi = view_box(frames)

    fig, ax = plt.subplots(figsize=(7.2, 6.0))
    fig.colorbar(plt.cm.ScalarMappable(norm=norm, cmap="magma"), ax=ax, label="von Mises stress (Pa)")
    ax.set_aspect("equal")
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    if fmt == "mp4":
        writer = animation.FFMpegWriter(fps=FPS, codec="libx264", extra_args=["-pix_fmt", "yuv420p"])
    else:
        writer = animation.PillowWriter(fps=FPS)
    drawn = []
    with writer.saving(fig, str(path), dpi=100):
        for (fields, faces), step in zip(frames, steps):
            for artist in drawn:
                artist.remove()
            v = np.clip(np.where(np.isfinite(fields.von_mises), fields.von_mises, vmax), vmin, vmax)
            # a TriMesh added without autoscaling (the view is fixed) is ax.tripcolor(shading="gouraud")
            # without its costly data limits
            field = TriMesh(Triangulation(fields.x[:, 0], fields.x[:, 1], fields.triangles),
                            norm=norm, cmap="magma", rasterized=True)
            field.set_array(v)
            drawn = [ax.add_collection(field, autolim=False),
                     ax.add_collection(LineCollection(faces.lines, colors="white", linewidths=1.2), autolim=False),
                     ax.add_collection(LineCollection(faces.lines[faces.closed], colors="tab:cyan",
                                                      linewidths=2.5), autolim=False)]
            ax.set_title(f"{result.summary['title']}\nstep {step['step']}: load factor {step['load_factor']:.5g}"
                         + (f", {int(faces.closed.sum())} closed face edges" if faces.closed.any() else ""),
                         fontsize=10)
            writer.grab_frame()
    plt.close(fig)
    return path
