"""Run a meshing function under a wall-clock limit.

gmsh's meshers can loop forever on awkward geometry (the published code of
the paper hangs at step 35 of the 45-degree disc), and a C++ loop cannot be
interrupted from Python. So the work runs in the long-lived meshing process
(meshing/worker.py), which is killed on timeout; `MeshTimeout` is raised.
"""
from __future__ import annotations

from collections.abc import Callable


class MeshTimeout(RuntimeError):
    """The meshing process did not finish within the time limit."""


def call_with_timeout(fn: Callable, args: tuple, timeout: float | None):
    """fn(*args) in the meshing process within `timeout` seconds, or
    in-process when `timeout` is None. fn and args must pickle by reference
    (a module-level function): worker.NotPicklable (a TypeError) otherwise.
    An exception in the worker is raised again here as RuntimeError with its
    message."""
    if timeout is None:
        return fn(*args)
    from meshing import worker

    try:
        return worker.call(fn, args, timeout)
    except worker.WorkerTimeout as error:
        raise MeshTimeout(str(error)) from None
