"""The drawing process: the pictures of a result drawn in a long-lived
worker (a meshing.worker.Channel of its own, named "drawing"), part of the
api layer. api.sif and api.run start it at their top (rank 0 with an output
folder), so that its interpreter start-up and matplotlib's import run while
the case computes on the other core; at the end the pictures are drawn
there and the caller waits for them, so the result has its pictures when
the command returns, as when they were drawn in-process.

The worker runs api's own drawing functions (the same code as `wingcrack
plot`), so the files and the warnings of a picture that cannot be drawn
are the same. A drawing process that is not running (never started, or
died) or dies while drawing: the pictures are drawn in this process
instead. Ctrl-C or SIGTERM while waiting kills the worker (see
meshing.worker.Call) and reaches the caller as KeyboardInterrupt, as when
the drawing was in-process.

A run with plots of SPLIT_FRAMES steps or more also starts a second
drawing process: the GIF's frames are then drawn half in each (the first
drawing fractures.png and history.png as well) and assembled here, the
same file byte for byte (every frame is drawn on the run's fixed colour
scale and view, whichever others are drawn). The frames cannot be drawn
as the steps finish: that scale, the view, the legend and the figure size
come from every step of the run.
"""
from __future__ import annotations

import math

#: no time limit, as in-process: a drawing that runs long is a large result, not a hang
DRAW_TIMEOUT = math.inf

#: a GIF of at least this many frames is drawn in two processes: below it
#: the frames cost less than fractures.png and history.png, which the first
#: process draws meanwhile, and than the second process's start-up
SPLIT_FRAMES = 8
#: the share of fractures.png and history.png, in frames, given to the
#: first process (they take about as long as that many frames)
PICTURES_AS_FRAMES = 9

_channel = None
_frames_channel = None


def _drawing():
    global _channel
    if _channel is None:
        from meshing.worker import Channel

        _channel = Channel("drawing", f"{__name__}:preload")
    return _channel


def _framing():
    """The second drawing process, for the other half of a long animation's frames."""
    global _frames_channel
    if _frames_channel is None:
        from meshing.worker import Channel

        _frames_channel = Channel("drawing", f"{__name__}:preload")
    return _frames_channel


def preload() -> None:
    """The worker's start-up: matplotlib (Agg) and the drawing modules, and a
    first text drawn (the font cache and the font file read once)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from . import api  # noqa: F401
    from .io import animation, history, pictures  # noqa: F401

    fig, ax = plt.subplots(figsize=(1, 1))
    ax.set_title("wingcrack")
    fig.canvas.draw()
    plt.close(fig)


def start(frames: int = 0) -> None:
    """Start the drawing process now, without waiting (rank 0 only: the
    other ranks draw nothing); for an animation of up to `frames` frames
    that is long enough (SPLIT_FRAMES) also the second one, which draws
    half of them."""
    from .parallel import world_rank

    if world_rank() == 0:
        _drawing().start()
        if frames >= SPLIT_FRAMES:
            _framing().start()


def _running(channel: str = "_channel") -> bool:
    """Whether the drawing process (or the second one, "_frames_channel") runs."""
    channel = globals()[channel]
    return channel is not None and channel._worker is not None and channel._worker.alive()


class NotDrawn(Exception):
    """A picture that could not be drawn in the drawing process, with that
    exception's message (plot without `failed`)."""


def pictures(out, summary: dict, history: bool, animation: bool) -> tuple[dict, list]:
    """({name: path}, warnings) of api._draw_pictures(out, summary, history,
    animation), drawn in the drawing process when it runs, else here."""
    from . import api

    args = (out, summary, history, animation)
    if _running():
        try:
            if animation and _running("_frames_channel") and _split(summary):
                return _in_two(out, summary, history)
            return _drawing().call(api._draw_pictures, args, DRAW_TIMEOUT)
        except RuntimeError:   # a worker died (or its answer failed): draw here instead
            pass
    return api._draw_pictures(*args)


def _split(summary: dict) -> bool:
    from .io.animation import animation_format

    steps = summary.get("steps")
    return isinstance(steps, list) and len(steps) >= SPLIT_FRAMES and animation_format() == "gif"


def _in_two(out, summary: dict, history: bool) -> tuple[dict, list]:
    """_draw_pictures(out, summary, history, True) with the GIF's frames
    drawn in both drawing processes, the first one also drawing
    fractures.png and history.png, and assembled here (as PillowWriter
    would: the same file)."""
    n = len(summary["steps"])
    first = range(0, max(0, (n - PICTURES_AS_FRAMES) // 2))
    second = _framing().send(_frames, (out, summary, range(len(first), n)), DRAW_TIMEOUT)
    try:
        files, warnings, part = _drawing().call(_pictures_and_frames, (out, summary, history, first), DRAW_TIMEOUT)
        rest = second.result()
    finally:
        second.cancel()   # no-op once collected; on Ctrl-C or a dead first worker it stops the second one
    if part[0] == "unread":   # no picture at all: the one warning _draw_pictures gave
        return files, warnings
    if rest[0] == "unread":   # the folder changed under us: all again, here
        raise RuntimeError("the result could not be read by the second drawing process")
    failed = next((p for p in (part, rest) if p[0] != "ok"), None)
    if failed is None:
        from .io.animation import assemble_gif

        try:
            files["animation"] = assemble_gif(out / "growth.gif", part[1] or rest[1], part[2] + rest[2])
        except Exception as err:  # noqa: BLE001 - a warning, as for every picture
            from . import api

            warnings.append(api._not_drawn("the growth animation", err, out))
    else:
        warnings.append(failed[1])
    return files, warnings


def _frames(out, summary: dict, frames: range) -> tuple:
    """In a worker: ("ok", size, [RGBA bytes]) of these frames of the
    result's animation; ("failed", the warning) when they cannot be drawn;
    ("unread", None) when the result cannot be read (_draw_pictures says that)."""
    from . import api
    from .io.animation import animate_growth
    from .io.outdir import read_result

    if not frames:
        return "ok", None, []
    try:
        result = read_result(out, summary=summary)
    except Exception:  # noqa: BLE001 - said once, by _draw_pictures
        return "unread", None
    try:
        size, drawn = animate_growth(out, result, "gif", only=frames)
    except Exception as err:  # noqa: BLE001 - as plot() words it
        return "failed", api._not_drawn("the growth animation", err, out)
    return "ok", size, drawn


def _pictures_and_frames(out, summary: dict, history: bool, frames: range) -> tuple:
    """In the first worker: the pictures but the animation (_draw_pictures),
    then these frames of it (_frames)."""
    from . import api

    files, warnings = api._draw_pictures(out, summary, history, False)
    return files, warnings, _frames(out, summary, frames)


def plot(out, history: bool, animation: bool) -> dict:
    """api.plot(out, history, animation) without `failed` (the first picture
    that cannot be drawn raises: NotDrawn with its message from the drawing
    process), in the drawing process when it runs, else here."""
    from . import api

    if _running():
        try:
            kind, value = _drawing().call(_plot_answer, (out, history, animation), DRAW_TIMEOUT)
        except RuntimeError:
            kind = None
        if kind == "ok":
            return value
        if kind == "failed":
            raise NotDrawn(value)
    return api.plot(out, history=history, animation=animation)


def _plot_answer(out, history: bool, animation: bool) -> tuple:
    """In the worker: ("ok", files) or ("failed", the exception's message)."""
    from . import api

    try:
        return "ok", api.plot(out, history=history, animation=animation)
    except Exception as err:  # noqa: BLE001 - the caller words it
        return "failed", str(err)
