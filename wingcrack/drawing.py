"""The drawing process: the pictures of a result drawn in a long-lived
worker (a procs.worker.Channel of its own, named "drawing"), on the io side
(it calls io.plotting, never api). api.sif and api.run start it at their top (rank 0 with an output
folder), so that its interpreter start-up and matplotlib's import run while
the case computes on the other core; at the end the pictures are drawn
there and the caller waits for them, so the result has its pictures when
the command returns, as when they were drawn in-process.

The worker runs io.plotting's drawing functions (the same code as `wingcrack
plot`), so the files and the warnings of a picture that cannot be drawn
are the same, and a picture the folder does not take fails as there (its
WriteError raised here, the picture not drawn again). A drawing process that is not running (never started, or
died) or dies while drawing: the pictures are drawn in this process
instead. Ctrl-C or SIGTERM while waiting kills the worker (see
procs.worker.Call) and reaches the caller as KeyboardInterrupt, as when
the drawing was in-process.
"""
from __future__ import annotations

import math

#: no time limit, as in-process: a drawing that runs long is a large result, not a hang
DRAW_TIMEOUT = math.inf

_channel = None


def _drawing():
    global _channel
    if _channel is None:
        from procs.worker import Channel

        _channel = Channel("drawing", f"{__name__}:preload")
    return _channel


def preload() -> None:
    """The worker's start-up: matplotlib (Agg) and the drawing modules, and a
    first text drawn (the font cache and the font file read once)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from .io import animation, history, pictures, plotting  # noqa: F401

    fig, ax = plt.subplots(figsize=(1, 1))
    ax.set_title("wingcrack")
    fig.canvas.draw()
    plt.close(fig)


def start() -> None:
    """Start the drawing process now, without waiting (rank 0 only: the
    other ranks draw nothing)."""
    from .parallel import world_rank

    if world_rank() == 0:
        _drawing().start()


def _running() -> bool:
    return _channel is not None and _channel.running()


class NotDrawn(Exception):
    """A picture that could not be drawn in the drawing process, with that
    exception's message (plot without `failed`)."""


def pictures(out, summary: dict, history: bool, animation: bool) -> tuple[dict, list]:
    """({name: path}, warnings) of plotting.draw_pictures(out, summary, history,
    animation), drawn in the drawing process when it runs, else here."""
    from .io import plotting

    args = (out, summary, history, animation)
    if _running():
        try:
            kind, value = _drawing().call(_pictures_answer, args, DRAW_TIMEOUT)
        except RuntimeError:   # the worker died (or its answer failed): draw here instead
            kind = None
        if kind == "ok":
            return value
        if kind == "unwritten":   # the folder refused a picture: drawn here it would refuse it again
            raise value
    return plotting.draw_pictures(*args)


def _pictures_answer(out, summary: dict, history: bool, animation: bool) -> tuple:
    """In the worker: ("ok", plotting.draw_pictures(...)) or ("unwritten", the
    WriteError of a picture the folder did not take), which the caller
    raises as it is (the worker's other errors reach it as RuntimeError)."""
    from .io import plotting
    from .errors import WriteError

    try:
        return "ok", plotting.draw_pictures(out, summary, history, animation)
    except WriteError as err:
        return "unwritten", err


def plot(out, history: bool, animation: bool) -> dict:
    """io.plotting.plot(out, history, animation) without `failed` (the first picture
    that cannot be drawn raises: NotDrawn with its message from the drawing
    process), in the drawing process when it runs, else here."""
    from .io import plotting

    if _running():
        try:
            kind, value = _drawing().call(_plot_answer, (out, history, animation), DRAW_TIMEOUT)
        except RuntimeError:
            kind = None
        if kind == "ok":
            return value
        if kind == "failed":
            raise NotDrawn(value)
    return plotting.plot(out, history=history, animation=animation)


def _plot_answer(out, history: bool, animation: bool) -> tuple:
    """In the worker: ("ok", files) or ("failed", the exception's message)."""
    from .io import plotting

    try:
        return "ok", plotting.plot(out, history=history, animation=animation)
    except Exception as err:  # noqa: BLE001 - the caller words it
        return "failed", str(err)
