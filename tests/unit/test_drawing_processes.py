"""What draws the pictures beside a run: a function run in a forked child
(procs/forked.py, fractures.png drawn on the other core at a run's end) and
a worker's call that says when its answer is there (procs.worker.Call.ready:
the run sends the next steps' frames without waiting for the drawing)."""
import os
import time

import pytest

from wingcrack.errors import FolderError


def answer(x):
    return {"twice": 2 * x, "pid": os.getpid()}


def refuse(path):
    raise FolderError(path, "not a wingcrack result")


class Unpicklable(Exception):
    def __init__(self, a, b):
        super().__init__(f"{a} and {b}")


def unpicklable():
    raise Unpicklable(1, 2)


def test_a_forked_child_answers_or_raises_here():
    """procs.forked: fn's value from another process; its exception here
    with its class and message (a FolderError as made); one whose class
    cannot be made again, a RuntimeError that names it."""
    from procs import forked

    got = forked.start(lambda: answer(21)).result()
    assert got["twice"] == 42 and got["pid"] != os.getpid()
    with pytest.raises(FolderError) as err:
        forked.start(lambda: refuse("/x")).result()
    assert err.value.path == "/x" and str(err.value) == "/x: not a wingcrack result"
    with pytest.raises(RuntimeError, match="Unpicklable: 1 and 2"):
        forked.start(unpicklable).result()


def nap(seconds):
    time.sleep(seconds)
    return seconds


def test_a_call_says_when_its_answer_is_there():
    """Call.ready(): false while the worker works, true once it answered."""
    from procs.worker import Channel

    channel = Channel("test-ready", "os")
    try:
        assert channel.call(nap, (0.0,), 60.0) == 0.0   # started, and its start-up done
        call = channel.send(nap, (0.5,), 60.0)
        assert not call.ready()
        t0 = time.monotonic()
        while not call.ready():
            assert time.monotonic() - t0 < 60.0
            time.sleep(0.01)
        assert time.monotonic() - t0 >= 0.2   # not before the worker answered (it naps 0.5 s)
        assert call.result() == 0.5
    finally:
        channel.shutdown()


def worker_pid():
    return os.getpid()


def test_the_drawing_process_takes_hurry_at_any_moment():
    """drawing.HURRY (what Frames.settle sends while a frames' call runs)
    kills no drawing process: neither one still starting (its preload not
    done: the signal's default action is to be ignored) nor one at work."""
    import signal

    from wingcrack import drawing

    channel = drawing._drawing()
    channel.shutdown()
    channel.start()
    pid = channel._worker.proc.pid
    os.kill(pid, drawing.HURRY)   # at once: the worker is importing matplotlib
    assert channel.call(worker_pid, (), 60.0) == pid
    os.kill(pid, drawing.HURRY)   # after its preload: its handler
    assert channel.call(worker_pid, (), 60.0) == pid and channel.running()
    assert signal.getsignal(drawing.HURRY) == signal.SIG_DFL   # this process's own is untouched


def clear_hurry_for(seconds):
    """In the drawing process: _draw_frames' clear() of the hurry flag, again
    and again for `seconds` (HURRY may come at any moment of one)."""
    from wingcrack import drawing

    end, n = time.monotonic() + seconds, 0
    while time.monotonic() < end:
        drawing._hurry.clear()
        n += 1
    return n


def test_hurry_inside_the_flags_clear_does_not_hang_the_drawing_process():
    """HURRY coming while the drawing process clears the flag (a frames'
    call just begun as Frames.settle sends it): with a threading.Event the
    handler's set() waited on the lock clear() held, for ever (the run with
    it: the drawing has no time limit; CI's suite hung so). Here HURRY comes
    every millisecond for 2 s of clears; the call must answer. The Event
    failed so in each of 3 tries (one signal waits for ever; the next ones
    nest their handlers on the same wait until Python's recursion limit,
    which is the error the call then reports); the 60 s limit catches a
    single wait, 30 times the work."""
    from procs.worker import WorkerTimeout

    from wingcrack import drawing

    channel = drawing._drawing()
    channel.shutdown()
    assert channel.call(worker_pid, (), 60.0) > 0   # started, its preload (and handler) done
    pid = channel._worker.proc.pid
    call = channel.send(clear_hurry_for, (2.0,), 60.0)
    end = time.monotonic() + 2.0
    while time.monotonic() < end:
        os.kill(pid, drawing.HURRY)
        time.sleep(0.001)
    try:
        assert call.result() > 1000
    except (WorkerTimeout, RuntimeError) as err:
        pytest.fail(f"the drawing process stuck on HURRY inside the flag's clear(): {err}")
    finally:
        channel.shutdown()
