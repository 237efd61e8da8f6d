"""The long-lived meshing process (meshing/worker.py) behind every timed mesh:
results and errors come back as from an in-process call, a call past its
time limit kills the worker and the next call gets a new one, closures are
refused (they cannot be sent), and the worker neither sees the caller's Ctrl-C
(own session) nor outlives the caller."""
import os
import subprocess
import sys
import time

import numpy as np
import pytest

from meshing import worker
from processes import alive
from meshing.timeout import MeshTimeout, call_with_timeout


def test_results_errors_and_timeouts():
    assert call_with_timeout(np.arange, (5,), 30.0).tolist() == [0, 1, 2, 3, 4]
    first = worker.MESHING._worker.proc.pid
    with pytest.raises(RuntimeError, match="ValueError: invalid literal"):
        call_with_timeout(int, ("x",), 30.0)
    assert worker.MESHING._worker.proc.pid == first   # an error does not cost the worker
    t0 = time.perf_counter()
    with pytest.raises(MeshTimeout, match="did not finish within 0.5 s"):
        call_with_timeout(time.sleep, (30,), 0.5)
    assert time.perf_counter() - t0 < 5 and worker.MESHING._worker is None
    assert call_with_timeout(sum, ([1, 2, 3],), 30.0) == 6     # a new worker
    assert worker.MESHING._worker.proc.pid != first
    # the worker is in its own session: Ctrl-C at the terminal is the caller's alone
    assert os.getsid(worker.MESHING._worker.proc.pid) != os.getsid(0)


def test_closures_are_refused_before_anything_runs():
    ran = []
    t0 = time.perf_counter()
    with pytest.raises(worker.NotPicklable):
        call_with_timeout(lambda: ran.append(time.sleep(30)), (), 60.0)
    assert not ran and time.perf_counter() - t0 < 5


def test_the_worker_dies_with_its_caller():
    code = ("import sys, time; from meshing import worker; worker.call(sum, ([1],), 30); "
            "print(worker.MESHING._worker.proc.pid, flush=True); time.sleep(60)")
    caller = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True)
    pid = int(caller.stdout.readline())
    caller.kill()
    caller.wait()
    for _ in range(50):
        if not alive(pid):
            return
        time.sleep(0.1)
    raise AssertionError(f"worker {pid} outlived its caller")
