"""Run a function in another process under a wall-clock limit.

gmsh's meshers can loop forever on awkward geometry (the published code of
the paper hangs at step 35 of the 45-degree disc), and a C++ loop cannot be
interrupted from Python. The child does the work and sends back its pickled
result; on timeout it is killed (SIGKILL) and `MeshTimeout` is raised.
`call_with_timeout` uses the long-lived meshing process (meshing/worker.py)
for module-level functions and falls back to a forked child for closures.
"""
from __future__ import annotations

import os
import pickle
import select
import signal
import time
from collections.abc import Callable


def _child_signals(parent: int) -> None:
    """The child inherits the parent's C-level signal handlers (PETSc's call
    MPI_Abort, which in a forked child waits forever for a daemon): back to
    the defaults, so that a failing child just dies. SIGPIPE is ignored (a
    write to a gone parent raises instead), Ctrl-C is the parent's, and the
    child is killed when the parent dies (Linux prctl PR_SET_PDEATHSIG)."""
    for sig in (signal.SIGTERM, signal.SIGSEGV, signal.SIGBUS, signal.SIGFPE, signal.SIGILL, signal.SIGABRT,
                signal.SIGHUP, signal.SIGUSR1, signal.SIGUSR2):
        try:
            signal.signal(sig, signal.SIG_DFL)
        except (OSError, ValueError):
            pass
    signal.signal(signal.SIGPIPE, signal.SIG_IGN)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        import ctypes

        ctypes.CDLL(None, use_errno=True).prctl(1, int(signal.SIGKILL))   # PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        pass
    if os.getppid() != parent:   # the parent died before prctl took effect
        os._exit(1)


class MeshTimeout(RuntimeError):
    """The child did not finish within the time limit."""


def run_with_timeout(fn: Callable[[], object], timeout: float | None):
    """fn() in a child process, its result in the parent. An exception in the
    child is raised again in the parent as RuntimeError with its message;
    `timeout` None (or no fork on this platform) runs fn() in-process."""
    if timeout is None or not hasattr(os, "fork"):
        return fn()
    read_fd, write_fd = os.pipe()
    parent = os.getpid()
    pid = os.fork()
    if pid == 0:  # child: never return into the caller's stack
        status = 0
        try:
            _child_signals(parent)
            os.close(read_fd)
            try:
                payload = pickle.dumps(("ok", fn()), protocol=pickle.HIGHEST_PROTOCOL)
            except BaseException as error:  # noqa: BLE001 - everything goes to the parent
                payload = pickle.dumps(("error", f"{type(error).__name__}: {error}"))
            with os.fdopen(write_fd, "wb") as pipe:
                pipe.write(payload)
        except BaseException:  # noqa: BLE001
            status = 1
        finally:
            os._exit(status)
    os.close(write_fd)
    chunks, deadline = [], time.monotonic() + timeout
    done = False
    try:
        while True:
            left = deadline - time.monotonic()
            if left <= 0:
                raise MeshTimeout(f"gmsh did not finish within {timeout:g} s")
            ready, _, _ = select.select([read_fd], [], [], min(left, 1.0))
            if ready:
                chunk = os.read(read_fd, 1 << 20)
                if not chunk:
                    break
                chunks.append(chunk)
        done = True
    finally:
        os.close(read_fd)
        if not done:   # timeout, Ctrl-C or any error here: the child must not outlive us
            try:
                os.kill(pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
        os.waitpid(pid, 0)
    if not chunks:
        raise RuntimeError("the meshing process died without a result")
    kind, value = pickle.loads(b"".join(chunks))
    if kind == "error":
        raise RuntimeError(value)
    return value


def call_with_timeout(fn: Callable, args: tuple, timeout: float | None):
    """fn(*args) under the time limit: in the long-lived meshing process when
    fn and args pickle by reference, else in a forked child (run_with_timeout);
    in-process when `timeout` is None."""
    if timeout is None:
        return fn(*args)
    from meshing import worker

    try:
        return worker.call(fn, args, timeout)
    except worker.NotPicklable:
        return run_with_timeout(lambda: fn(*args), timeout)
    except worker.WorkerTimeout as error:
        raise MeshTimeout(str(error)) from None
