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

While a run goes, the frames of its animation are drawn there too, each
once its step is committed (Frames; io.growing_animation keeps them): the
run sends the steps and never waits for the drawing, which runs only on
a core nothing else wants. The pictures at the end take the frames that
still hold.
"""
from __future__ import annotations

import math
import os
import signal
import threading

from procs import forked
from procs.worker import Channel

from . import parallel
from .errors import WriteError
from .io import growing_animation, plotting

#: no time limit, as in-process: a drawing that runs long is a large result, not a hang
DRAW_TIMEOUT = math.inf

_channel = None
#: the run whose steps are sent to be drawn (Frames), until the pictures at its end
_feeding = None


def _drawing():
    global _channel
    if _channel is None:
        _channel = Channel("drawing", f"{__name__}:preload")
    return _channel


def preload() -> None:
    """The worker's start-up: matplotlib (Agg) and the drawing modules, and a
    first text drawn (the font cache and the font file read once). Imported
    here, in the worker: the caller's start-up never pays for matplotlib."""
    import matplotlib   # lazy: start-up

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from .io import animation, history, pictures, plotting  # noqa: F401

    fig, ax = plt.subplots(figsize=(1, 1))
    ax.set_title("wingcrack")
    fig.canvas.draw()
    plt.close(fig)
    signal.signal(HURRY, lambda *_: _hurry.set())


#: the signal that tells the drawing process to end the frames' call it is in (Frames.settle): one whose
#: default action is to be ignored, so that a worker still starting (its preload not done) is not killed by it
HURRY = signal.SIGURG


class _Flag:
    """A flag that a signal handler sets. Python runs a handler in the main
    thread between two of its bytecodes, also inside a lock that thread
    holds: with a threading.Event, HURRY arriving inside _draw_frames'
    clear() ran set() on the lock clear() held, and the drawing process
    waited for itself forever (the run with it: DRAW_TIMEOUT). One
    attribute's store takes no lock; the frames' thread reads it."""

    __slots__ = ("up",)

    def __init__(self):
        self.up = False

    def set(self) -> None:
        self.up = True

    def clear(self) -> None:
        self.up = False

    def is_set(self) -> bool:
        return self.up


#: set in the worker by HURRY: the frames' thread stops after the frame it draws
_hurry = _Flag()


def start() -> None:
    """Start the drawing process now, without waiting (rank 0 only: the
    other ranks draw nothing)."""
    if parallel.world_rank() == 0:
        _drawing().start()


def _running() -> bool:
    return _channel is not None and _channel.running()


class NotDrawn(Exception):
    """A picture that could not be drawn in the drawing process, with that
    exception's message (plot without `failed`)."""


class Frames:
    """loop.run's `committed`: the steps committed by a run into `out` (its
    case's title, propagation_asked and whether it has fractures), sent to
    the drawing process to draw their frames (io.growing_animation), never
    waiting for it: a step goes when the call before it is answered, with
    the steps that came meanwhile. The first call begins the run's frames
    there (any other run's dropped)."""

    def __init__(self, out, title: str, propagation: dict, fractured: bool):
        global _feeding
        self.out, self.head = out, (title, propagation, fractured)
        self.pending, self.call, self.first = [], None, True
        _feeding = self

    def __call__(self, k: int, record: dict) -> None:
        self.pending.append((k, record))
        if self.call is not None:
            if not self.call.ready():
                return
            self.settle()
        if not _running():   # not started, or died: the pictures at the end draw every frame
            return
        try:
            self.call = _drawing().send(_draw_frames, (self.out, self.first, self.head, self.pending), DRAW_TIMEOUT)
        except RuntimeError:   # died on the way
            return
        self.pending, self.first = [], False

    def settle(self) -> None:
        """Wait for the call under way: a new call would abandon it (and the
        worker with it). The worker is told to hurry: its frames run only on
        a core nothing else wants, and the run now waits for them; the
        frames it leaves are drawn with the pictures, at its own priority."""
        call, self.call = self.call, None
        if call is not None:
            if not call.ready():
                call.signal(HURRY)
            try:
                call.result()
            except RuntimeError:   # its frames not drawn: the end draws them
                pass


def _draw_frames(out, first: bool, head: tuple, records: list) -> None:
    """In the worker: the frames of `records` [(k, step record)] committed
    into `out` (the run's first call: `first`, which begins its frames with
    `head`, Frames' title, propagation and fractured), at a low priority,
    until HURRY comes."""
    _hurry.clear()
    _yielding(_frames_of, out, first, head, records)


def _frames_of(out, first: bool, head: tuple, records: list) -> None:
    if first:
        growing_animation.begin(out, *head)
    growing_animation.add(out, records, _hurry.is_set)


#: the niceness of the frames drawn while a run goes where the idle policy is not to be had
FRAMES_NICE = 19


def _yielding(fn, *args):
    """fn(*args) in a thread of this process that runs only when a core has
    nothing else to do (Linux's SCHED_IDLE; else niced by FRAMES_NICE), so
    that the frames never take a core from the run's steps or its meshing
    (niced by 10 only, they still took a share of one on a busy machine).
    Linux schedules a thread alone: the worker's own thread, which draws
    the pictures at the end while the run waits for them, keeps its
    priority."""
    failed = []

    def work():
        tid = threading.get_native_id()
        try:
            os.sched_setscheduler(tid, os.SCHED_IDLE, os.sched_param(0))
        except (OSError, AttributeError):
            try:
                os.setpriority(os.PRIO_PROCESS, tid, FRAMES_NICE)
            except (OSError, AttributeError):   # neither: drawn at the worker's priority
                pass
        try:
            fn(*args)
        except BaseException as err:  # noqa: BLE001 - raised in the caller's thread
            failed.append(err)

    thread = threading.Thread(target=work, name="frames")
    thread.start()
    thread.join()
    if failed:
        raise failed[0]


def _settled() -> None:
    """The frames sent so far drawn, and no more sent (before the pictures)."""
    global _feeding
    feeding, _feeding = _feeding, None
    if feeding is not None:
        feeding.settle()


def pictures(out, summary: dict, history: bool, animation: bool) -> tuple[dict, list]:
    """({name: path}, warnings) of plotting.draw_pictures(out, summary, history,
    animation), drawn in the drawing process when it runs, else here."""
    _settled()
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
    try:
        return "ok", plotting.draw_pictures(out, summary, history, animation, beside=_beside())
    except WriteError as err:
        return "unwritten", err


def plot(out, history: bool, animation: bool) -> dict:
    """io.plotting.plot(out, history, animation) without `failed` (the first picture
    that cannot be drawn raises: NotDrawn with its message from the drawing
    process), in the drawing process when it runs, else here."""
    _settled()
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
    try:
        return "ok", plotting.plot(out, history=history, animation=animation, beside=_beside())
    except Exception as err:  # noqa: BLE001 - the caller words it
        return "failed", str(err)


def _beside():
    """In the worker: procs.forked.start where a second core can draw a
    picture beside this process (io.plotting.plot's `beside`), else None.
    The run is over: its process waits for the pictures."""
    return forked.start if forked.available() else None
