"""growth.gif (growth.mp4 when ffmpeg is on PATH): the von Mises stress and
the fractures, one frame per step, from a result folder's step files; the
faces of each step banded by their contact state, open, stick or slip, in
the colours of fractures.png (io.pictures.FACE_BANDS), with a legend entry
for each state that some frame shows; the edges that hold fluid (the face
file's pressure > 0) with a blue rim in the shades of fractures.png, on a
pressure scale fixed over the run (a colour bar, and the step's highest
pressure in the title).

Every frame shares one Look, so that frames compare. The colour scale is
logarithmic, from the smallest 1st percentile of the positive nodal values
of any step (at least 1e-4 of the top) to the largest 99.5th percentile
(the tip singularity alone would otherwise set the top). The view is known
from the first step: the box of the fractures and of the reach of every
tip (a square of half-side the steps asked times the longest advance of a
step, summary.json's "propagation": no tip can go farther), widened by half
its size, within the domain. A result without "propagation" (a `sif`, a
folder of an earlier version) is viewed at its last fractures' box, widened
the same way. So a frame drawn as its step finishes (io.growing_animation,
in the drawing process) is the frame of the finished run unless the colour
scale, the pressure scale or the legend's states changed after it: those
frames are drawn again at the end. (The colour scale settles where the
load peaks and is held, as in the Brazilian disc; where the cracks
concentrate more stress at every step it rises to the last one, and every
frame is drawn at the end.)
"""
from __future__ import annotations

from pathlib import Path

from . import growing_animation, movie
from .animation_look import Look, StepLook, frame_title, reach_of, step_files_key
from .frames import FrameDrawer
from .movie import animation_format


def animate_growth(folder: Path, result, fmt: str | None = None, drawn: list | None = None) -> Path:
    """Write growth.gif or growth.mp4 (`fmt`, default animation_format())
    into `folder` for `result` (an io.outdir.StoredResult with at least
    one step) and return its path. The frames the drawing process drew as
    the run went (io.growing_animation) are taken where their files and
    Look are the finished run's; the others drawn now. drawn: a list that
    gets, per frame (every frame drawn now), {"faces open" / "faces stick" /
    "faces slip": (k, 3, 2) the face edges banded in that state, read back
    from the figure (only states present), "pressurised": {"lines": (k, 3, 2)
    the edges drawn with a pressure rim, "pressure": (k,) their pressures
    (Pa)} (only in a frame with fluid), "legend": the legend's labels}."""
    fmt = fmt or animation_format()
    path = Path(folder) / f"growth.{fmt}"
    grown = None if drawn is not None else growing_animation.taken(result.folder, fmt)
    seen = [grown.step(k, step_files_key(result, k)) if grown is not None else None for k in range(len(result.steps))]
    data = {}   # k -> (fields, faces) of the steps to draw here
    for k, s in enumerate(seen):
        if s is None:
            data[k] = (result.fields_of(k), result.faces_of(k))
        elif s.data is not None:
            data[k] = s.data
    steps = [StepLook.of(*data[k]) if s is None else s.step for k, s in enumerate(seen)]
    look = Look.of(steps, reach_of(result.summary))
    drawer = grown.drawer_for(look) if grown is not None else None
    frames = []
    try:
        for k, (record, step, s) in enumerate(zip(result.steps, steps, seen)):
            title = frame_title(result.summary["title"], record, step)
            if s is not None and s.frame is not None and s.look == look and s.title == title:
                frames.append(s.frame)
                continue
            if drawer is None:
                drawer = FrameDrawer(look, fmt)
            fields, faces = data.pop(k) if k in data else (result.fields_of(k), result.faces_of(k))
            frames.append(drawer.draw(fields, faces, title, drawn))
        movie.write(path, fmt, frames)
    finally:   # a file not written leaves no figure open (a long-lived drawing process draws the next)
        if drawer is not None:
            drawer.close()
        if grown is not None:
            grown.close()
    return path
