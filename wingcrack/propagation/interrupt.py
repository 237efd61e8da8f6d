"""Ctrl-C (SIGINT) or SIGTERM during a propagation run: it must stop the run
at once and never be lost.

SIGTERM (`kill PID`, a batch system's time limit, mpirun passing it on to
every rank) is handled like Ctrl-C: the handler raises Terminated, a
KeyboardInterrupt, so the run stops the same way (every finished step kept,
resumable) with status "stopped: terminated" instead of "stopped:
interrupted" (stop_status), and the CLI exits 128 + 15 as a process killed
by the signal would.

Python raises KeyboardInterrupt wherever the main thread happens to be when
the signal arrives. If that is a finalizer or a weakref callback that the
garbage collector is running (DOLFINx and logging leave plenty), Python
prints "Exception ignored in ..." with a traceback and goes on: the
interrupt is lost and the run continues (CI caught this once). So during a
run the SIGINT handler also remembers the press; check() raises it again at
the loop's next safe point, and such a swallowed KeyboardInterrupt is not
printed. Where an interrupt must not land at all (the step's commit of
summary and checkpoint; a forced collection), deferred() only records it
and raises it on leaving.
"""
from __future__ import annotations

import signal
import sys
import threading

_SIGNALS = (signal.SIGINT, signal.SIGTERM)
_pressed = None   # the exception class of a signal received and not yet raised


class Terminated(KeyboardInterrupt):
    """Raised by the SIGTERM handler: stop as after Ctrl-C."""


def _exception(signum):
    return Terminated if signum == signal.SIGTERM else KeyboardInterrupt


def _handler(signum, frame):
    global _pressed
    _pressed = _exception(signum)
    raise _pressed


def stop_status(err: BaseException) -> str:
    """The status of a run stopped by `err` (a KeyboardInterrupt)."""
    return "stopped: terminated" if isinstance(err, Terminated) else "stopped: interrupted"


def exit_code(err: BaseException) -> int:
    """The exit status after `err`: 128 + the signal's number, as a shell
    reports a process that the signal ended (130 Ctrl-C, 143 SIGTERM)."""
    return 128 + (signal.SIGTERM if isinstance(err, Terminated) else signal.SIGINT)


def _install(handler) -> dict:
    """Set `handler` for SIGINT and SIGTERM; the previous handlers."""
    return {s: signal.signal(s, handler) for s in _SIGNALS}


def _restore(old: dict) -> None:
    for s, h in old.items():
        if s == signal.SIGINT and not callable(h):
            h = signal.default_int_handler   # gmsh's import left SIG_DFL: Python's own again
        signal.signal(s, h if h is not None else signal.SIG_DFL)


class terminate_raises:
    """Within (main thread only): SIGTERM raises Terminated, as Ctrl-C raises
    KeyboardInterrupt, instead of ending the process at once. The CLI holds
    this for a whole command, so that a terminated `sif` or `plot` also
    ends through the normal path (output folder released, one line, 143)."""

    def __enter__(self):
        self.active = _main_thread()
        if self.active:
            self.old = signal.signal(signal.SIGTERM, self._raise)
        return self

    @staticmethod
    def _raise(signum, frame):
        raise Terminated

    def __exit__(self, *exc):
        if self.active:
            signal.signal(signal.SIGTERM, self.old if self.old is not None else signal.SIG_DFL)
        return False


def _main_thread() -> bool:
    return threading.current_thread() is threading.main_thread()


class watching:
    """The SIGINT and SIGTERM handling of one run (main thread only; elsewhere a no-op).
    `import gmsh` resets SIGINT to its default (the process would just
    die): gmsh runs in the meshing worker, and where it is imported in this
    process (an in-process mesh) meshing.load_gmsh keeps the handler in
    place. On leaving, Python's own handler is put back (and the SIGTERM
    handler that was there)."""

    def __enter__(self):
        global _pressed
        _pressed = None
        self.active = _main_thread()
        if self.active:
            self.old = _install(_handler)
            self.old_hook = sys.unraisablehook
            sys.unraisablehook = self._unraisable
        return self

    def _unraisable(self, unraisable):
        if isinstance(unraisable.exc_value, KeyboardInterrupt):
            return   # remembered: check() raises it at the next safe point
        self.old_hook(unraisable)

    def __exit__(self, *exc):
        if self.active:
            _restore(self.old)
            sys.unraisablehook = self.old_hook
        return False


def check() -> None:
    """Raise KeyboardInterrupt (Terminated after SIGTERM) if the signal came
    and its exception was swallowed."""
    global _pressed
    if _pressed is not None:
        exc, _pressed = _pressed, None
        raise exc


class deferred:
    """Within: Ctrl-C or SIGTERM only sets a flag; on leaving, its exception
    is raised if it came (here or, swallowed, before)."""

    def __enter__(self):
        self.active = _main_thread()
        if self.active:
            self.old = _install(self._flag)
        return self

    @staticmethod
    def _flag(signum, frame):
        global _pressed
        _pressed = _exception(signum)

    def __exit__(self, *exc):
        if self.active:
            for s, h in self.old.items():
                signal.signal(s, h if h is not None else signal.SIG_DFL)
        if exc[0] is None:
            check()
        return False
