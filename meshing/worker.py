"""The meshing worker: the procs.worker channel in which gmsh runs under a
time limit (meshing.timeout), started early so that its gmsh import overlaps
the caller's start-up."""
from __future__ import annotations

import signal
import sys
import threading

from procs.worker import Call, Channel, NotPicklable, WorkerTimeout

__all__ = ["Call", "Channel", "MESHING", "NotPicklable", "WorkerTimeout", "call", "load_gmsh", "load_worker_modules",
           "send", "start", "start_worker"]

#: the meshing worker
MESHING = Channel("meshing", "meshing.worker:load_worker_modules", what="gmsh")


def start() -> None:
    """Start the meshing worker now if none is running, without waiting for
    it: its start-up (the gmsh import) overlaps the caller's own until the
    first call."""
    MESHING.start()


def send(fn, args: tuple, timeout: float) -> Call:
    """Send fn(*args) to the meshing worker and return at once (Channel.send)."""
    return MESHING.send(fn, args, timeout)


def call(fn, args: tuple, timeout: float):
    """fn(*args) in the meshing worker, within `timeout` seconds (send + result)."""
    return MESHING.call(fn, args, timeout)


def load_gmsh() -> None:
    """Import gmsh into this process now (gmsh is imported in meshing/ only),
    keeping the SIGINT handler: gmsh's import sets SIGINT to the default
    action (the process would die on Ctrl-C instead of raising
    KeyboardInterrupt, and a run's own handler would be gone). Everything
    that meshes in-process calls this before gmsh is first used; later
    imports are no-ops."""
    if "gmsh" in sys.modules:
        return
    main = threading.current_thread() is threading.main_thread()
    old = signal.getsignal(signal.SIGINT) if main else None
    import gmsh  # noqa: F401  (here, not at the top: a process that only checks a case never loads gmsh)
    if main and old is not None:   # None: a handler set outside Python, which gmsh's import replaced
        signal.signal(signal.SIGINT, old)


def load_worker_modules() -> None:
    """What the meshing worker imports at its start (overlapping its
    caller's start-up): gmsh (the meshing package, imported with this
    module, brings the compiled kernels that finish a mesh)."""
    import gmsh  # noqa: F401  (the worker's own start-up: meshing imports gmsh in functions only)


def start_worker() -> None:
    """Start the meshing worker now, without waiting (it imports gmsh while
    the caller goes on); meshing with a time limit uses it."""
    MESHING.start()
