"""Ctrl-C during a propagation run: it must stop the run at once and never
be lost.

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

_pressed = False


def _handler(signum, frame):
    global _pressed
    _pressed = True
    raise KeyboardInterrupt


def _main_thread() -> bool:
    return threading.current_thread() is threading.main_thread()


class watching:
    """The SIGINT handling of one run (main thread only; elsewhere a no-op).
    `import gmsh` resets SIGINT to its default (the process would just
    die), so gmsh is imported first; on leaving, Python's own handler is
    put back."""

    def __enter__(self):
        global _pressed
        import gmsh  # noqa: F401 - its import is what resets SIGINT: have it done first

        _pressed = False
        self.active = _main_thread()
        if self.active:
            self.old = signal.signal(signal.SIGINT, _handler)
            self.old_hook = sys.unraisablehook
            sys.unraisablehook = self._unraisable
        return self

    def _unraisable(self, unraisable):
        if isinstance(unraisable.exc_value, KeyboardInterrupt):
            return   # remembered: check() raises it at the next safe point
        self.old_hook(unraisable)

    def __exit__(self, *exc):
        if self.active:
            keep = self.old if callable(self.old) else signal.default_int_handler
            signal.signal(signal.SIGINT, keep)
            sys.unraisablehook = self.old_hook
        return False


def check() -> None:
    """Raise KeyboardInterrupt if Ctrl-C was pressed and swallowed."""
    global _pressed
    if _pressed:
        _pressed = False
        raise KeyboardInterrupt


class deferred:
    """Within: Ctrl-C only sets a flag; on leaving, KeyboardInterrupt is
    raised if it was pressed (here or, swallowed, before)."""

    def __enter__(self):
        self.active = _main_thread()
        if self.active:
            self.old = signal.signal(signal.SIGINT, self._flag)
        return self

    def _flag(self, *_):
        global _pressed
        _pressed = True

    def __exit__(self, *exc):
        if self.active:
            signal.signal(signal.SIGINT, self.old)
        if exc[0] is None:
            check()
        return False
