"""A long-lived worker process, so that work (gmsh above all) runs under a
time limit without forking the (large) calling process, which holds DOLFINx
and PETSc, for every call. The worker is a fresh interpreter (`python -m procs.worker`),
started once (start(), or at the first call), in its own session (Ctrl-C is
the caller's), dying with its caller. A call sends the function (by
reference) and its arguments pickled on the worker's stdin (send) and reads
the pickled result from its stdout (Call.result), so the caller may do other
work in between; one call at a time is outstanding. On timeout, Ctrl-C or
any error on the way, and for a call that is abandoned, the worker is
killed, and the next call starts a new one.

A Channel is one such worker under its own name, which imports its own
`preload` first ("module" or "module:function", the function then called):
the meshing worker (meshing.worker.MESHING) and the drawing process of the
pictures (wingcrack.drawing) are two. The worker runs whatever function it
is sent, and never imports anything of its caller's but that and fn. This
package imports neither wingcrack nor meshing: both use it.
"""
from __future__ import annotations

import atexit
import contextlib
import ctypes
import importlib
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
    def __init__(self, channel: Channel):
        self.channel = channel
        env = dict(os.environ)
        env["PYTHONPATH"] = os.pathsep.join(p for p in sys.path if p)
        self.proc = subprocess.Popen([sys.executable, "-m", "procs.worker", channel.preload],
                                     stdin=subprocess.PIPE, stdout=subprocess.PIPE, start_new_session=True, env=env)

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
        # a bytearray grows in place: bytes += chunk copies all so far, and a
        # pipe gives 64 KiB at a time, quadratic in a large answer
        data, need = bytearray(), None
        while need is None or len(data) < need:
            left = deadline - time.monotonic()
            if left <= 0:
                raise WorkerTimeout(f"{self.channel.what} did not finish within {timeout:g} s")
            ready, _, _ = select.select([fd], [], [], min(left, 1.0))
            if not ready:
                continue
            chunk = os.read(fd, 1 << 20)
            if not chunk:
                raise RuntimeError(f"the {self.channel.name} process died without a result")
            data += chunk
            if need is None and len(data) >= _HEADER.size:
                need = _HEADER.size + _HEADER.unpack(data[:_HEADER.size])[0]
        return pickle.loads(memoryview(data)[_HEADER.size:need])


class Call:
    """A call sent to a worker: result() waits for its answer. Its time
    limit runs from the moment it was sent. A call that is not collected
    (cancel(), a new call sent, the caller's exit) kills the worker, so that
    no unread answer is left for the next call, which starts a new one."""

    def __init__(self, worker: _Worker, timeout: float):
        self._worker, self.timeout = worker, timeout
        self._channel = worker.channel
        self.deadline = time.monotonic() + timeout
        self.seconds = None   # the worker's own time for fn, once answered

    def result(self):
        """fn(*args) as the worker answered it; WorkerTimeout past the time
        limit, RuntimeError with the message of an exception in the worker."""
        channel = self._channel
        if channel._outstanding is not self:
            raise RuntimeError(f"this {channel.name} call was abandoned (another call was sent, or it was cancelled)")
        done = False
        try:
            kind, value, self.seconds = self._worker.receive(self.deadline, self.timeout)
            done = True
        finally:
            channel._outstanding = None
            if not done:   # timeout, Ctrl-C, a dead worker: never leave a half-read answer behind
                channel._kill(self._worker)
        if kind == "error":
            raise RuntimeError(value)
        return value

    def ready(self) -> bool:
        """Whether result() would find the answer (or the worker's death)
        coming already, without waiting for the worker to finish: true once
        its first bytes are there (a small answer is written at once), and
        for a call no longer outstanding (result() says so at once)."""
        if self._channel._outstanding is not self:
            return True
        ready, _, _ = select.select([self._worker.proc.stdout.fileno()], [], [], 0)
        return bool(ready)

    def signal(self, signum: int) -> None:
        """Send `signum` to the worker while the call is outstanding (a worker
        that handles it: the drawing process is told to finish its call
        soon); nothing once it is not."""
        if self._channel._outstanding is self and self._worker.alive():
            with contextlib.suppress(ProcessLookupError):
                os.kill(self._worker.proc.pid, signum)

    def cancel(self) -> None:
        """Abandon the call if it is still outstanding (the worker is killed)."""
        channel = self._channel
        if channel._outstanding is self:
            channel._outstanding = None
            channel._kill(self._worker)


class Channel:
    """One named long-lived worker (started at the first start() or send())
    and its outstanding call: `name` says it in errors ("the <name> process
    died"), `what` in a timeout ("<what> did not finish"), `preload` is
    imported by the worker before its first request."""

    def __init__(self, name: str, preload: str, what: str | None = None):
        self.name, self.preload, self.what = name, preload, what or name
        self._worker: _Worker | None = None
        #: the call sent and not yet answered (one at most): its answer is the next on the worker's stdout
        self._outstanding: Call | None = None
        _channels.append(self)

    def _kill(self, w: _Worker) -> None:
        w.kill()
        if self._worker is w:
            self._worker = None

    def running(self) -> bool:
        """A worker is running (started and not dead)."""
        return self._worker is not None and self._worker.alive()

    def start(self) -> None:
        """Start the worker now if none is running, without waiting for it:
        its start-up (the preload's import) overlaps the caller's own until
        the first call."""
        if not self.running():
            self._worker = _Worker(self)

    def send(self, fn, args: tuple, timeout: float) -> Call:
        """Send fn(*args) to the worker and return at once; Call.result()
        waits for it, within `timeout` seconds of now. A call still
        outstanding is abandoned first (see Call). fn must be picklable by
        reference (a module-level function); NotPicklable at once when it
        is not."""
        try:
            payload = pickle.dumps((fn, args), protocol=pickle.HIGHEST_PROTOCOL)
        except (pickle.PicklingError, AttributeError, TypeError) as error:
            raise NotPicklable(str(error)) from None
        if self._outstanding is not None:
            self._outstanding.cancel()
        for _ in range(2):   # a worker that died after its last answer (not yet seen dead): once more, a new one
            self.start()
            w = self._worker
            sent = False
            try:
                w.send(payload)
                sent = True
            except BrokenPipeError:
                pass
            finally:
                if not sent:   # a dead worker, or Ctrl-C half-way through the request
                    self._kill(w)
            if sent:
                self._outstanding = Call(w, timeout)
                return self._outstanding
        raise RuntimeError(f"the {self.name} process died before it took the request")

    def call(self, fn, args: tuple, timeout: float):
        """fn(*args) in the worker, within `timeout` seconds (send + result)."""
        try:
            return self.send(fn, args, timeout).result()
        except BaseException:   # Ctrl-C between send and result: no call is left running
            if self._outstanding is not None:
                self._outstanding.cancel()
            raise

    def shutdown(self) -> None:
        """Kill the worker (an outstanding call is abandoned)."""
        self._outstanding = None
        if self._worker is not None:
            self._worker.kill()
            self._worker = None


_channels: list[Channel] = []
def _shutdown() -> None:
    for channel in _channels:
        channel.shutdown()


atexit.register(_shutdown)


def _read_exactly(stream, n: int) -> bytes:
    data = b""
    while len(data) < n:
        chunk = stream.read(n - len(data))
        if not chunk:
            return b""
        data += chunk
    return data


def _preload(spec: str) -> None:
    module, _, function = spec.partition(":")
    loaded = importlib.import_module(module)
    if function:
        getattr(loaded, function)()


def main(preload: str = "gmsh") -> None:
    """The worker's loop: one pickled (fn, args) in, one pickled result out."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        ctypes.CDLL(None, use_errno=True).prctl(1, int(signal.SIGKILL))   # PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        pass
    answers = os.fdopen(os.dup(1), "wb")
    os.dup2(2, 1)   # whatever gmsh or Python prints must not enter the answers
    requests = sys.stdin.buffer
    _preload(preload)   # loaded once, before the first request

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
    main(*sys.argv[1:2])
