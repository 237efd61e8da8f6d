"""A function run beside the caller in a forked child, on another core:
start(fn) forks at once, Child.result() waits for fn()'s value (or raises
its exception). For a process that holds no threads and no MPI or PETSc
state (the drawing process: a fork copies the one thread that forks, and
MPI forbids it), on a machine of more than one core (elsewhere
`available()` is false and the caller runs fn itself). The child dies with
its parent (a killed drawing process leaves no child writing on), and
never runs the parent's exit handlers.
"""
from __future__ import annotations

import ctypes
import os
import pickle
import signal
import sys


def available() -> bool:
    """More than one core for this process, and fork on this system."""
    if not hasattr(os, "fork"):
        return False
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    return cores > 1


class Child:
    def __init__(self, pid: int, fd: int):
        self.pid, self.fd = pid, fd

    def result(self):
        """fn()'s value, or its exception raised here (one that cannot come
        through a pipe: a RuntimeError with its type and message)."""
        data = bytearray()
        try:
            while chunk := os.read(self.fd, 1 << 20):
                data += chunk
        finally:
            os.close(self.fd)
            os.waitpid(self.pid, 0)
        if not data:
            raise RuntimeError("the process drawing beside died without a result")
        kind, value = pickle.loads(data)
        if kind == "error":
            raise value
        return value


def start(fn) -> Child:
    """Run fn() in a forked child (see the module doc)."""
    read, write = os.pipe()
    parent = os.getpid()
    sys.stdout.flush()
    sys.stderr.flush()
    pid = os.fork()
    if pid:
        os.close(write)
        return Child(pid, read)
    # the child: dies with its parent, answers on the pipe, and leaves without the parent's atexit
    status = 0
    try:
        os.close(read)
        try:
            ctypes.CDLL(None, use_errno=True).prctl(1, int(signal.SIGKILL))   # PR_SET_PDEATHSIG
        except (OSError, AttributeError):
            pass
        if os.getppid() != parent:   # the parent died before the line above
            os._exit(1)
        try:
            answer = ("ok", fn())
        except BaseException as err:  # noqa: BLE001 - everything goes back to the parent
            answer = ("error", err)
        try:
            payload = pickle.dumps(answer, protocol=pickle.HIGHEST_PROTOCOL)
            pickle.loads(payload)   # an exception whose class cannot be rebuilt there
        except Exception:  # noqa: BLE001
            payload = pickle.dumps(("error", RuntimeError(f"{type(answer[1]).__name__}: {answer[1]}")))
        with os.fdopen(write, "wb") as fh:
            fh.write(payload)
    except BaseException:  # noqa: BLE001 - never return into the parent's code
        status = 1
    finally:
        os._exit(status)
