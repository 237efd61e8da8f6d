"""Run a meshing function under a wall-clock limit.

gmsh's meshers can loop forever on awkward geometry (the paper's published
code hangs so in one of its own runs), and a C++ loop cannot be
interrupted from Python. So the work runs in the long-lived meshing process
(meshing/worker.py), which is killed on timeout; `MeshTimeout` is raised.
The work may be started and collected later (start_with_timeout), so that
the caller does something else meanwhile. What it returns is the worker's
own call (procs.worker.Call), or, without a limit, an InProcess call of the
same face: nothing wraps the call.
"""
from __future__ import annotations

import time
from collections.abc import Callable

from meshing import worker

#: the meshing process did not finish within the time limit (the worker's own timeout: a RuntimeError)
MeshTimeout = worker.WorkerTimeout


class InProcess:
    """fn(*args) computed in this process at result(), where the caller
    waits anyway (no time limit): the face of procs.worker.Call (result(),
    cancel(), `seconds`: fn's own time, once it has answered)."""

    def __init__(self, fn: Callable, args: tuple):
        self._work = (fn, args)
        self.seconds = None

    def result(self):
        if self._work is None:
            raise RuntimeError("this meshing call was cancelled")
        fn, args = self._work
        self._work = None
        worker.load_gmsh()   # in this process: its import must not leave SIGINT to the default action
        t0 = time.perf_counter()
        try:
            return fn(*args)
        finally:
            self.seconds = time.perf_counter() - t0

    def cancel(self) -> None:
        self._work = None


def start_with_timeout(fn: Callable, args: tuple, timeout: float | None) -> worker.Call | InProcess:
    """fn(*args) begun in the meshing process, to finish within `timeout`
    seconds of now (its result() collects it, MeshTimeout past the limit),
    or in-process at result() when `timeout` is None. fn and args must
    pickle by reference (a module-level function): worker.NotPicklable (a
    TypeError) at once otherwise. An exception in the worker is raised
    again by result() as RuntimeError with its message."""
    return InProcess(fn, args) if timeout is None else worker.send(fn, args, timeout)


def call_with_timeout(fn: Callable, args: tuple, timeout: float | None):
    """fn(*args) in the meshing process within `timeout` seconds, or
    in-process when `timeout` is None (start_with_timeout + result)."""
    return start_with_timeout(fn, args, timeout).result()
