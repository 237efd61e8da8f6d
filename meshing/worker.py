"""A long-lived meshing process, so that gmsh runs under a time limit without
forking the (large) calling process, which holds DOLFINx and PETSc, for every
mesh. The worker is a fresh interpreter (`python -m meshing.worker`),
started once (start(), or at the first call), in its own session (Ctrl-C is
the caller's), dying with its caller. A call sends the function (by
reference) and its arguments pickled on the worker's stdin (send) and reads
the pickled result from its stdout (Call.result), so the caller may do other
work in between; one call at a time is outstanding. On timeout, Ctrl-C or
any error on the way, and for a call that is abandoned, the worker is
killed, and the next call starts a new one.
"""
from __future__ import annotations

import atexit
import contextlib
import os
import pickle
import select
import signal
import struct
import subprocess
import sys
import time

_HEADER = struct.Struct(">Q")


class WorkerTimeout(RuntimeError):
    """The call did not finish within its time limit (the worker was killed)."""


class NotPicklable(TypeError):
    """fn or its arguments cannot be sent to the worker (a local function, a
    lambda): refused before anything runs."""


@contextlib.contextmanager
def _no_sigpipe():
    """Within, a write to a dead worker's pipe fails with BrokenPipeError
    only: PETSc (loaded by the caller) catches SIGPIPE and aborts the whole
    process, Python's own SIG_IGN notwithstanding. The signal is blocked in
    this thread, and one it raised is taken off before it is unblocked."""
    if not hasattr(signal, "pthread_sigmask"):
        yield
        return
    old = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGPIPE})
    try:
        yield
    finally:
        if signal.SIGPIPE in signal.sigpending():
            signal.sigtimedwait({signal.SIGPIPE}, 0)
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


class _Worker:
    def __init__(self):
        env = dict(os.environ)
        env["PYTHONPATH"] = os.pathsep.join(p for p in sys.path if p)
        self.proc = subprocess.Popen([sys.executable, "-m", "meshing.worker"], stdin=subprocess.PIPE,
                                     stdout=subprocess.PIPE, start_new_session=True, env=env)

    def alive(self) -> bool:
        return self.proc.poll() is None

    def kill(self) -> None:
        try:
            self.proc.kill()
        except ProcessLookupError:
            pass
        with _no_sigpipe():   # closing stdin flushes what a failed send left in its buffer
            for stream in (self.proc.stdin, self.proc.stdout):
                try:
                    stream.close()
                except OSError:
                    pass
        self.proc.wait()

    def send(self, payload: bytes) -> None:
        with _no_sigpipe():
            self.proc.stdin.write(_HEADER.pack(len(payload)) + payload)
            self.proc.stdin.flush()

    def receive(self, deadline: float, timeout: float):
        fd = self.proc.stdout.fileno()
        data, need = b"", None
        while need is None or len(data) < need:
            left = deadline - time.monotonic()
            if left <= 0:
                raise WorkerTimeout(f"gmsh did not finish within {timeout:g} s")
            ready, _, _ = select.select([fd], [], [], min(left, 1.0))
            if not ready:
                continue
            chunk = os.read(fd, 1 << 20)
            if not chunk:
                raise RuntimeError("the meshing process died without a result")
            data += chunk
            if need is None and len(data) >= _HEADER.size:
                need = _HEADER.size + _HEADER.unpack(data[:_HEADER.size])[0]
        return pickle.loads(data[_HEADER.size:need])


_worker: _Worker | None = None
#: the call sent and not yet answered (one at most): its answer is the next on the worker's stdout
_outstanding: Call | None = None


class Call:
    """A call sent to the worker: result() waits for its answer. Its time
    limit runs from the moment it was sent. A call that is not collected
    (cancel(), a new call sent, the caller's exit) kills the worker, so that
    no unread answer is left for the next call, which starts a new one."""

    def __init__(self, worker: _Worker, timeout: float):
        self._worker, self.timeout = worker, timeout
        self.deadline = time.monotonic() + timeout
        self.seconds = None   # the worker's own time for fn, once answered

    def result(self):
        """fn(*args) as the worker answered it; WorkerTimeout past the time
        limit, RuntimeError with the message of an exception in the worker."""
        global _outstanding
        if _outstanding is not self:
            raise RuntimeError("this meshing call was abandoned (another call was sent, or it was cancelled)")
        done = False
        try:
            kind, value, self.seconds = self._worker.receive(self.deadline, self.timeout)
            done = True
        finally:
            _outstanding = None
            if not done:   # timeout, Ctrl-C, a dead worker: never leave a half-read answer behind
                _kill(self._worker)
        if kind == "error":
            raise RuntimeError(value)
        return value

    def cancel(self) -> None:
        """Abandon the call if it is still outstanding (the worker is killed)."""
        global _outstanding
        if _outstanding is self:
            _outstanding = None
            _kill(self._worker)


def _kill(w: _Worker) -> None:
    global _worker
    w.kill()
    if _worker is w:
        _worker = None


def start() -> None:
    """Start the worker now if none is running, without waiting for it: its
    start-up (the gmsh import) overlaps the caller's own until the first call."""
    global _worker
    if _worker is None or not _worker.alive():
        _worker = _Worker()


def send(fn, args: tuple, timeout: float) -> Call:
    """Send fn(*args) to the worker and return at once; Call.result() waits
    for it, within `timeout` seconds of now. A call still outstanding is
    abandoned first (see Call). fn must be picklable by reference (a
    module-level function); NotPicklable at once when it is not."""
    global _outstanding
    try:
        payload = pickle.dumps((fn, args), protocol=pickle.HIGHEST_PROTOCOL)
    except (pickle.PicklingError, AttributeError, TypeError) as error:
        raise NotPicklable(str(error)) from None
    if _outstanding is not None:
        _outstanding.cancel()
    for _ in range(2):   # a worker that died after its last answer (not yet seen dead): once more, a new one
        start()
        w = _worker
        sent = False
        try:
            w.send(payload)
            sent = True
        except BrokenPipeError:
            pass
        finally:
            if not sent:   # a dead worker, or Ctrl-C half-way through the request
                _kill(w)
        if sent:
            _outstanding = Call(w, timeout)
            return _outstanding
    raise RuntimeError("the meshing process died before it took the request")


def call(fn, args: tuple, timeout: float):
    """fn(*args) in the worker, within `timeout` seconds (send + result)."""
    return send(fn, args, timeout).result()


def _shutdown() -> None:
    global _worker, _outstanding
    _outstanding = None
    if _worker is not None:
        _worker.kill()
        _worker = None


atexit.register(_shutdown)


def _read_exactly(stream, n: int) -> bytes:
    data = b""
    while len(data) < n:
        chunk = stream.read(n - len(data))
        if not chunk:
            return b""
        data += chunk
    return data


def main() -> None:
    """The worker's loop: one pickled (fn, args) in, one pickled result out."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        import ctypes

        ctypes.CDLL(None, use_errno=True).prctl(1, int(signal.SIGKILL))   # PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        pass
    answers = os.fdopen(os.dup(1), "wb")
    os.dup2(2, 1)   # whatever gmsh or Python prints must not enter the answers
    requests = sys.stdin.buffer
    import gmsh  # noqa: F401 - loaded once, before the first request

    while True:
        header = _read_exactly(requests, _HEADER.size)
        if not header:
            return
        body = _read_exactly(requests, _HEADER.unpack(header)[0])
        if not body:
            return
        t0 = time.perf_counter()
        try:
            fn, args = pickle.loads(body)
            result = ("ok", fn(*args), time.perf_counter() - t0)
        except BaseException as error:  # noqa: BLE001 - everything goes back to the caller
            result = ("error", f"{type(error).__name__}: {error}", time.perf_counter() - t0)
        payload = pickle.dumps(result, protocol=pickle.HIGHEST_PROTOCOL)
        answers.write(_HEADER.pack(len(payload)) + payload)
        answers.flush()


if __name__ == "__main__":
    main()
