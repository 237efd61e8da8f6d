"""growth.gif (growth.mp4 when ffmpeg is on PATH): the von Mises stress and
the fractures, one frame per step, from a result folder's step files; the
faces of each step banded by their contact state, open, stick or slip, in
the colours of fractures.png (io.pictures.FACE_BANDS), with a legend entry
for each state that some frame shows; the edges that hold fluid (the face
file's pressure > 0) with a blue rim in the shades of fractures.png, on a
pressure scale fixed over the run (a colour bar, and the step's highest
pressure in the title).

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

from . import fonts
from .atomic import replacing
from .faces import STATE_NAMES
from .pictures import FACE_BANDS, PRESSURE_BAR, pressure_colours

#: frames per second
FPS = 4
#: width (points) of the face-state bands; opaque and outlined in black, as
#: the slip colour is close to magma's upper colours and a GIF's palette
#: blurs translucent ones
BAND_WIDTH = 5.0
#: width (points) of the pressure rim under a band's black outline (BAND_WIDTH
#: + 2), itself outlined in white: magma's dark colours would swallow navy
RIM_WIDTH = BAND_WIDTH + 6.0


def animation_format() -> str:
    """"mp4" when ffmpeg is on PATH, else "gif"."""
    return "mp4" if shutil.which("ffmpeg") else "gif"


def colour_range(von_mises: list) -> tuple[float, float]:
    """(vmin, vmax) of the run's logarithmic colour scale (Pa). Non-finite
    values are left out: the step files of this version hold none, those of
    earlier ones NaN at the crack-tip nodes, which `wingcrack plot` still
    draws."""
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


def animate_growth(folder: Path, result, fmt: str | None = None, drawn: list | None = None) -> Path:
    """Write growth.gif or growth.mp4 (`fmt`, default animation_format())
    into `folder` for `result` (an io.outdir.StoredResult with at least
    one step) and return its path. drawn: a list that gets, per frame, what
    plot_fractures returns: {"faces open" / "faces stick" / "faces slip":
    (k, 3, 2) the face edges banded in that state, read back from the
    figure (only states present), "pressurised": {"lines": (k, 3, 2) the
    edges drawn with a pressure rim, "pressure": (k,) their pressures (Pa)}
    (only in a frame with fluid), "legend": the legend's labels}."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib import animation, patheffects
    from matplotlib.collections import LineCollection, TriMesh
    from matplotlib.lines import Line2D
    from matplotlib.colors import LogNorm
    from matplotlib.tri import Triangulation

    fmt = fmt or animation_format()
    path = Path(folder) / f"growth.{fmt}"
    steps = result.steps
    frames = [(result.fields_of(k), result.faces_of(k)) for k in range(len(steps))]
    vmin, vmax = colour_range([f.von_mises for f, _ in frames])
    norm = LogNorm(vmin=vmin, vmax=vmax)
    lo, hi = view_box(frames)
    p_top = max((float(f.pressure.max()) for _, f in frames if len(f.pressure)), default=0.0)
    p_cmap, p_norm = pressure_colours(p_top)

    fig, ax = plt.subplots(figsize=(7.2, 6.0 if p_top <= 0 else 6.8))
    fig.colorbar(plt.cm.ScalarMappable(norm=norm, cmap="magma"), ax=ax, label="von Mises stress (Pa)")
    if p_top > 0:   # below the axes, clear of the stress scale's labels
        fig.colorbar(plt.cm.ScalarMappable(norm=plt.Normalize(0.0, p_top / 1e6), cmap=p_cmap), ax=ax,
                     label=PRESSURE_BAR, orientation="horizontal", fraction=0.04, pad=0.1)
    ax.set_aspect("equal")
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    if fmt == "mp4":
        writer = animation.FFMpegWriter(fps=FPS, codec="libx264", extra_args=["-pix_fmt", "yuv420p"])
    else:
        writer = animation.PillowWriter(fps=FPS)
    # one legend for the whole run, fixed like the colour scale: the states some frame shows
    outline = [patheffects.Stroke(linewidth=BAND_WIDTH + 2.0, foreground="black"), patheffects.Normal()]
    shown = [state for state in FACE_BANDS if any(np.any(f.state == state) for _, f in frames)]
    handles = [Line2D([], [], color="white", lw=0.8, label="fracture")]
    handles += [Line2D([], [], color=FACE_BANDS[s][0], lw=BAND_WIDTH, solid_capstyle="butt", path_effects=outline,
                       label=FACE_BANDS[s][1]) for s in shown]
    rim_outline = [patheffects.Stroke(linewidth=RIM_WIDTH + 2.0, foreground="white"), patheffects.Normal()]
    if p_top > 0:
        handles.append(Line2D([], [], color=p_cmap(p_norm(p_top)), lw=RIM_WIDTH, solid_capstyle="butt",
                              path_effects=rim_outline, label="pressurised (colour: p)"))
    legend = ax.legend(handles=handles, loc="upper right", fontsize=8, facecolor="0.25", labelcolor="white",
                       framealpha=0.8)
    labels = [t.get_text() for t in legend.get_texts()]
    artists = []
    try:
        # the temporary file keeps the suffix: the writer's format goes by it
        with replacing(path, path.suffix) as tmp, writer.saving(fig, str(tmp), dpi=100):
            for (fields, faces), step in zip(frames, steps):
                for artist in artists:
                    artist.remove()
                v = np.clip(np.where(np.isfinite(fields.von_mises), fields.von_mises, vmax), vmin, vmax)
                # a TriMesh added without autoscaling (the view is fixed) is ax.tripcolor(shading="gouraud")
                # without its costly data limits
                field = TriMesh(Triangulation(fields.x[:, 0], fields.x[:, 1], fields.triangles),
                                norm=norm, cmap="magma", rasterized=True)
                field.set_array(v)
                artists = [ax.add_collection(field, autolim=False)]
                wet = faces.pressure > 0
                rim = None
                if wet.any():
                    # under the state bands and their black outline: a blue ring outside them
                    rim = ax.add_collection(LineCollection(faces.lines[wet], cmap=p_cmap, norm=p_norm,
                                                           linewidths=RIM_WIDTH, capstyle="butt",
                                                           path_effects=rim_outline), autolim=False)
                    rim.set_array(faces.pressure[wet])
                    artists.append(rim)
                bands = {}
                for state, (colour, label) in FACE_BANDS.items():
                    edges = faces.lines[faces.state == state]
                    if len(edges):
                        # under the fracture line, wide enough to show past it on either side
                        bands[label] = ax.add_collection(LineCollection(edges, colors=colour, linewidths=BAND_WIDTH,
                                                                        capstyle="butt", path_effects=outline),
                                                         autolim=False)
                artists += bands.values()
                artists.append(ax.add_collection(LineCollection(faces.lines, colors="white", linewidths=0.8),
                                                 autolim=False))
                counts = ", ".join(f"{int(np.sum(faces.state == s))} {STATE_NAMES[s]}" for s in FACE_BANDS
                                   if np.any(faces.state == s))
                # with fluid the face counts go to a line of their own: the stress scale would cut a long one
                injection = f"; p max {faces.pressure.max() / 1e6:.4g} MPa\n" if wet.any() else "; "
                # a pumped run: the time and the pump's pressure (the load factor is that pressure in Pa)
                load = f"load factor {step['load_factor']:.5g}" if "time" not in step else \
                    f"t = {step['time']:.5g} s"
                fonts.set_title(ax, f"{result.summary['title']}\nstep {step['step']}: {load}"
                             + (injection + f"face edges {counts}" if counts else injection.rstrip("; \n")),
                             fontsize=10)
                if drawn is not None:
                    frame = {label: np.asarray(b.get_segments(), float).reshape(-1, 3, 2) for label, b in bands.items()}
                    if rim is not None:
                        frame["pressurised"] = {"lines": np.asarray(rim.get_segments(), float).reshape(-1, 3, 2),
                                                "pressure": np.asarray(rim.get_array(), float)}
                    frame["legend"] = labels
                    drawn.append(frame)
                writer.grab_frame()
    finally:   # a file not written leaves no figure open (a long-lived drawing process draws the next)
        plt.close(fig)
    return path
