"""Run a meshing function under a wall-clock limit.

gmsh's meshers can loop forever on awkward geometry (the paper's published
code hangs so in one of its own runs), and a C++ loop cannot be
interrupted from Python. So the work runs in the long-lived meshing process
(meshing/worker.py), which is killed on timeout; `MeshTimeout` is raised.
The work may be started and collected later (start_with_timeout), so that
the caller does something else meanwhile.
"""
from __future__ import annotations

import time
from collections.abc import Callable

from meshing import worker


class MeshTimeout(RuntimeError):
    """The meshing process did not finish within the time limit."""


class Pending:
    """fn(*args) started: result() waits for it (and raises what it raised),
    cancel() abandons it. `seconds`: fn's own time, once it has answered."""

    def __init__(self, fn: Callable, args: tuple, timeout: float | None):
        self.seconds = None
        self._call = None
        if timeout is None:
            self._work = (fn, args)   # in-process: computed at result(), where the caller waits anyway
        else:
            self._work = None
            self._call = worker.send(fn, args, timeout)

    def result(self):
        if self._call is None:
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
        try:
            value = self._call.result()
        except worker.WorkerTimeout as error:
            raise MeshTimeout(str(error)) from None
        finally:
            self.seconds = self._call.seconds
        return value

    def cancel(self) -> None:
        self._work = None
        if self._call is not None:
            self._call.cancel()


def start_with_timeout(fn: Callable, args: tuple, timeout: float | None) -> Pending:
    """fn(*args) begun in the meshing process, to finish within `timeout`
    seconds of now (Pending.result() collects it), or in-process at
    result() when `timeout` is None. fn and args must pickle by reference (a
    module-level function): worker.NotPicklable (a TypeError) at once
    otherwise. An exception in the worker is raised again by result() as
    RuntimeError with its message."""
    return Pending(fn, args, timeout)


def call_with_timeout(fn: Callable, args: tuple, timeout: float | None):
    """fn(*args) in the meshing process within `timeout` seconds, or
    in-process when `timeout` is None (start_with_timeout + result)."""
    return start_with_timeout(fn, args, timeout).result()
