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
summary and checkpoint; a forced collection; the form compiler's cache
entries), deferred() only records it and raises it on leaving.

A signal's exception does not always reach the top as itself: raised
inside an extension module's initialisation (DOLFINx's, numpy's: a signal
during their import) it comes out as an ImportError, chained to it
(pybind11's "initialization failed") or with the chain dropped (a C API
that replaces the error), and code that catches Exception may turn it into
anything else. Every handler here therefore remembers the signal it
received, and cause(err) says which stop an exception stands for: after a
stop was asked for, an error is its consequence, not a failure to report.
"""
from __future__ import annotations

import signal
import sys
import threading

_SIGNALS = (signal.SIGINT, signal.SIGTERM)
_pressed = None   # the exception class of a signal received and not yet raised
_received = None  # the exception class of the last signal that a handler here received (cause())
_runs = 0         # how many watching() are entered (a run goes on)


class Terminated(KeyboardInterrupt):
    """Raised by the SIGTERM handler: stop as after Ctrl-C."""


def _exception(signum):
    return Terminated if signum == signal.SIGTERM else KeyboardInterrupt


def _handler(signum, frame):
    global _pressed, _received
    _pressed = _received = _exception(signum)
    raise _pressed


def cause(err: BaseException) -> KeyboardInterrupt | None:
    """The stop (KeyboardInterrupt, or Terminated) that `err` stands for, or
    None when it is an error of its own: `err` itself when it is one; one in
    the chain of exceptions `err` was raised from or while handling; else,
    when a handler here received SIGINT or SIGTERM since the command or the
    run began (forget()), that signal's, whose exception was turned into
    `err` on its way up (see the module doc)."""
    seen = set()
    e = err
    while e is not None and id(e) not in seen:
        if isinstance(e, KeyboardInterrupt):
            return e
        seen.add(id(e))
        e = e.__cause__ or e.__context__
    return _received() if _received is not None else None


def forget() -> None:
    """A new command or run begins: signals received before it (their
    exceptions delivered) are past, for cause() and check()."""
    global _pressed, _received
    _pressed = _received = None


def message(err: BaseException) -> str:
    """The word for a stop by `err` (a KeyboardInterrupt): "interrupted" or "terminated"."""
    return "terminated" if isinstance(err, Terminated) else "interrupted"


def stop_line(err: BaseException, kept: int | None = None) -> str:
    """What the command line says for a stop by `err`: a clean stop, not an
    error. kept: the steps a stopped `run` left to resume (None for the
    other commands, or before a run had its folder)."""
    said = f"stopped ({message(err)})"
    if kept is None:
        return said
    if kept == 0:
        return f"{said}: no step was finished, so nothing to resume: run it again"
    return f"{said}: {kept} step{'' if kept == 1 else 's'} kept; --resume goes on"


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
    KeyboardInterrupt, instead of ending the process at once, and both are
    remembered for cause(). The command's entry point (wingcrack/__main__.py)
    holds this from its first line and the CLI for the whole command, so
    that a terminated `sif` or `plot`, or a command stopped while it
    imports its modules, also ends through the normal path (output folder
    released, one line, 143 or 130). A signal that the process was started
    with ignored (a background job of a script: SIGINT) stays ignored."""

    def __enter__(self):
        self.active = _main_thread()
        if self.active:
            forget()
            self.old = {s: signal.getsignal(s) for s in _SIGNALS}
            for s in _SIGNALS:
                if self.old[s] is not signal.SIG_IGN:
                    signal.signal(s, self._raise)
        return self

    @staticmethod
    def _raise(signum, frame):
        global _received
        _received = _exception(signum)
        raise _received

    def __exit__(self, *exc):
        if self.active:
            for s, h in self.old.items():
                signal.signal(s, h if h is not None else signal.SIG_DFL)
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
        global _runs
        forget()
        _runs += 1
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
        global _runs
        _runs -= 1
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
    is raised if it came (here or, in a run, swallowed before). An
    exception raised within goes up as it is (cause() tells when the signal
    caused it: a compiler that the same Ctrl-C stopped)."""

    def __enter__(self):
        global _pressed
        self.active = _main_thread()
        if self.active:
            if not _runs:
                _pressed = None   # outside a run nothing is pending but what comes here
            self.old = _install(self._flag)
        return self

    @staticmethod
    def _flag(signum, frame):
        global _pressed, _received
        _pressed = _received = _exception(signum)

    def __exit__(self, *exc):
        if self.active:
            for s, h in self.old.items():
                signal.signal(s, h if h is not None else signal.SIG_DFL)
        if exc[0] is None:
            check()
        return False
