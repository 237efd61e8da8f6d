"""Issue 16: the next step's mesh is begun before this step's files are
written (meshing.start_crack_mesh, worker.send, step.start_mesh) and
collected by the next step's discretise.

References: the synchronous call (crack_mesh, worker.call) for the values;
the wall clock for the overlap and the time limit (margins of seconds on
sleeps of one: the machine is shared, and the point is 1 s against 2 s);
the worker process's state (alive, killed) for what an abandoned call
leaves; the step numbering of the failure for a mesh that fails."""
import os
import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

from builders import square_plate_with_cracks
from processes import alive, working
from meshing import worker
from meshing import crack_mesh, start_crack_mesh
from meshing.domain import Domain
from meshing.timeout import MeshTimeout, start_with_timeout

CRACK = [np.array([[-0.3, -0.1], [0.3, 0.1]])]


def plate_args():
    return Domain("rectangle", corner=[-1.0, -1.0], size=[2.0, 2.0]), CRACK, [], 0.4, 0.04


def same_mesh(a, b) -> bool:
    return (np.array_equal(a.x, b.x) and np.array_equal(a.cells, b.cells) and np.array_equal(a.pairs, b.pairs)
            and [t.node for t in a.tips] == [t.node for t in b.tips])


def test_a_begun_mesh_is_the_mesh_of_the_synchronous_call():
    args = plate_args()
    reference = crack_mesh(*args)   # in-process, the way it always was
    pending = start_crack_mesh(*args, timeout=60.0)
    assert same_mesh(pending.result(), reference)
    assert same_mesh(start_crack_mesh(*args).result(), reference)   # in-process: computed at result()
    assert same_mesh(crack_mesh(*args, timeout=60.0), reference)


def test_bad_arguments_are_refused_at_the_start():
    with pytest.raises(ValueError, match="tip_size"):
        start_crack_mesh(Domain("rectangle", corner=[-1.0, -1.0], size=[2.0, 2.0]), CRACK, [], 0.4, 0.5, timeout=60.0)


def test_the_caller_works_while_the_worker_does():
    worker.call(sum, ([1],), 30.0)   # a worker that is up: its start-up is not what is judged here
    call = worker.send(working, (1.0,), 30.0)
    sent = time.time()
    time.sleep(0.2)   # the caller's own work
    start, end = call.result()
    # overlapped: the worker was still at its work when send() returned to the caller (a send that
    # waited for the answer would return after the work's end); no bound on how long anything took
    assert start < end and sent < end
    assert call.seconds >= 1.0   # the worker's own time comes back with the answer


def test_the_time_limit_runs_from_the_moment_the_work_is_sent():
    pending = start_with_timeout(time.sleep, (30,), 1.0)
    time.sleep(1.5)   # the caller busy past the limit: result() finds it passed and does not wait again
    t0 = time.perf_counter()
    with pytest.raises(MeshTimeout, match="within 1 s"):
        pending.result()
    # waiting again would take the whole limit (1 s) once more; finding it passed takes a kill and a
    # reap (measured 0.01 s): 0.9 s is past 10x that and still tells the two apart
    assert time.perf_counter() - t0 < 0.9 and worker.MESHING._worker is None


def test_an_abandoned_call_kills_the_worker_and_the_next_gets_a_new_one():
    call = worker.send(time.sleep, (30,), 60.0)
    pid = call._worker.proc.pid
    call.cancel()
    assert not alive(pid) and worker.MESHING._worker is None
    with pytest.raises(RuntimeError, match="abandoned"):
        call.result()
    assert worker.call(sum, ([1, 2],), 30.0) == 3
    # a call sent while another is outstanding abandons that one: its answer would come first
    first = worker.send(time.sleep, (30,), 60.0)
    pid = first._worker.proc.pid
    second = worker.send(sum, ([4, 5],), 30.0)
    assert not alive(pid)
    assert second.result() == 9
    with pytest.raises(RuntimeError, match="abandoned"):
        first.result()


def test_ctrl_c_while_waiting_kills_the_worker():
    call = worker.send(time.sleep, (30,), 60.0)
    pid = call._worker.proc.pid

    def interrupt(signum, frame):
        raise KeyboardInterrupt

    old = signal.signal(signal.SIGALRM, interrupt)
    try:
        signal.setitimer(signal.ITIMER_REAL, 0.3)
        with pytest.raises(KeyboardInterrupt):
            call.result()
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)
    assert not alive(pid) and worker.MESHING._worker is None and worker.MESHING._outstanding is None
    assert worker.call(sum, ([1],), 30.0) == 1


def test_an_error_of_the_start_is_raised_where_the_result_is_collected(monkeypatch):
    from meshing import mesher   # where wingcrack.mesh_request looks start_crack_mesh up
    from wingcrack.mesh_request import MeshRequest

    def start(*args, **kw):
        raise ValueError("mesh.tip_size: simulated")

    monkeypatch.setattr(mesher, "start_crack_mesh", start)
    case = plate_case(1)
    pending = MeshRequest(case, case.fractures, None, 60.0)   # nothing raised here: the others would never hear
    with pytest.raises(ValueError, match="simulated"):
        pending.result()


def run_python(code: str) -> str:
    proc = subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True,
                          timeout=300)
    assert proc.returncode == 0, proc.stderr
    return proc.stdout.strip()


def test_meshing_in_the_worker_leaves_gmsh_out_of_this_process_and_in_process_keeps_the_sigint_handler():
    out = run_python("""
        import signal, sys
        import numpy as np
        from meshing import crack_mesh
        from meshing.domain import Domain
        args = (Domain("rectangle", corner=[-1.0, -1.0], size=[2.0, 2.0]), [np.array([[-0.3, -0.1], [0.3, 0.1]])], [], 0.4, 0.04)
        crack_mesh(*args, timeout=60.0)
        print("gmsh" in sys.modules)
        def mine(signum, frame):
            pass
        signal.signal(signal.SIGINT, mine)
        crack_mesh(*args)   # in-process: gmsh is imported here, and its import sets SIGINT to SIG_DFL
        print("gmsh" in sys.modules, signal.getsignal(signal.SIGINT) is mine)
        """)
    assert out.split() == ["False", "True", "True"]


def test_a_run_does_not_import_gmsh_and_ctrl_c_still_stops_an_in_process_run():
    """With the worker the run's own process never imports gmsh; with
    in-process meshing (timeout None) the first mesh imports it inside the
    run, and Ctrl-C must still raise KeyboardInterrupt (not kill the
    process): the handler of interrupt.watching stays."""
    out = run_python(f"""
        import signal, sys
        sys.path.insert(0, {os.path.dirname(os.path.dirname(__file__))!r})
        from builders import square_plate_with_cracks
        from wingcrack.case import Case
        from wingcrack.propagation import loop
        d = square_plate_with_cracks(2.0, [[[-0.3, -0.1], [0.3, 0.1]]], (0.0, 0.0, 0.0), size=0.4, tip_size=0.04)
        d["bc"] += [{{"on": "top", "traction": [0.0, 1e5]}}, {{"on": "bottom", "traction": [0.0, -1e5]}}]
        d["propagation"] = {{"steps": 2, "length": 0.05}}
        case = Case.from_dict(d)
        r = loop.run(case)
        print(len(r.steps), "gmsh" in sys.modules)
        seen = []
        def progress(k, step):
            seen.append(signal.getsignal(signal.SIGINT))
            signal.raise_signal(signal.SIGINT)
        try:
            loop.run(case, mesh_timeout=None, progress=progress)
        except KeyboardInterrupt:
            print("interrupted", "gmsh" in sys.modules, callable(seen[0]) and seen[0] is not signal.SIG_DFL)
        """)
    assert out.splitlines() == ["2 False", "interrupted True True"]


def plate_case(steps):
    from wingcrack.case import Case

    d = square_plate_with_cracks(2.0, [[[-0.3, -0.1], [0.3, 0.1]]], (0.0, 0.0, 0.0), size=0.4, tip_size=0.04)
    d["bc"] += [{"on": "top", "traction": [0.0, 1e5]}, {"on": "bottom", "traction": [0.0, -1e5]}]
    d["propagation"] = {"steps": steps, "length": 0.05}
    return Case.from_dict(d)


@pytest.mark.parametrize("where", ["start", "result"])
def test_a_mesh_that_fails_is_the_failure_of_its_own_step(tmp_path, monkeypatch, where):
    """The mesh of step 1 is begun during step 0; when it fails (refused at
    the start, or in gmsh), step 1 fails and step 0 stays whole on disk."""
    import json

    from meshing import mesher   # where wingcrack.mesh_request looks start_crack_mesh up
    from wingcrack.api import run
    from wingcrack.errors import ComputationError

    calls = []
    real = mesher.start_crack_mesh

    class Failing:
        def result(self):
            raise RuntimeError("gmsh: simulated")

        def cancel(self):
            pass

    def start(*args, **kw):
        calls.append(len(calls))
        if len(calls) == 2:
            if where == "start":
                raise ValueError("simulated refusal")
            return Failing()
        return real(*args, **kw)

    monkeypatch.setattr(mesher, "start_crack_mesh", start)
    with pytest.raises(ComputationError, match="failed: step 1: "):
        run(plate_case(3), tmp_path / "out", plots=False)
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["status"].startswith("failed: step 1: ") and "simulated" in summary["status"]
    assert [s["step"] for s in summary["steps"]] == [0]
    assert (tmp_path / "out" / "step_0000.vtu").is_file() and not (tmp_path / "out" / "step_0001.vtu").exists()
    assert len(calls) == 2   # step 1's mesh was begun once, during step 0


def test_a_run_stopped_while_the_next_mesh_is_made_leaves_no_call_behind(monkeypatch):
    """Ctrl-C in step 0's output, while step 1's mesh is in the worker:
    the run stops, and that call is abandoned (the worker killed)."""
    from wingcrack import step
    from wingcrack.propagation import loop

    real = step.finish
    seen = {}

    def finish(*args, **kw):
        seen["call"] = worker.MESHING._outstanding
        seen["pid"] = None if worker.MESHING._worker is None else worker.MESHING._worker.proc.pid
        raise KeyboardInterrupt

    monkeypatch.setattr(step, "finish", finish)
    with pytest.raises(KeyboardInterrupt):
        loop.run(plate_case(3))
    assert seen["call"] is not None   # step 1's mesh was under way when step 0 was written
    assert worker.MESHING._outstanding is None and not alive(seen["pid"])
    monkeypatch.setattr(step, "finish", real)
    assert len(loop.run(plate_case(2)).steps) == 2   # and the next run meshes with a new worker


# -- summary.json and the checkpoint, rewritten after every step at the cost of that step --------------


def test_the_summary_after_every_step_is_what_the_whole_encoding_writes(tmp_path):
    """Reference: json.dumps(indent=1) of the whole summary, the way
    write_summary encodes it, and of the checkpoint's meta as
    checkpoint.save encodes it from the records' dicts."""
    import json

    from wingcrack.propagation import checkpoint, loop
    from wingcrack.results import StepRecord

    out = tmp_path / "out"
    out.mkdir()
    texts = []

    def progress(k, record):
        texts.append((out / "summary.json").read_text())

    case = plate_case(3)
    result = loop.run(case, out, progress=progress)
    assert len(result.steps) == 3 and len(texts) == 3
    for k, text in enumerate(texts):   # valid JSON after every step, in write_summary's layout
        parsed = json.loads(text)
        assert [s["step"] for s in parsed["steps"]] == list(range(k + 1))
        assert text == json.dumps(parsed, indent=1)
    records = [StepRecord.from_dict(s) for s in result.steps]
    fset = result.fractures
    lam = records[-1].load_factor
    checkpoint.save(tmp_path, case, 2, fset, lam, [r.to_dict() for r in records], None)
    writer = checkpoint.Writer(tmp_path / "w", case)
    (tmp_path / "w").mkdir()
    writer.save(1, fset, records[1].load_factor, records[:2], None)   # the texts of steps 0 and 1 made here, reused below
    writer.save(2, fset, lam, records, None)
    metas = [str(np.load(p / checkpoint.NAME)["meta"]) for p in (tmp_path, tmp_path / "w")]
    assert metas[0] == metas[1]
    assert checkpoint.load(tmp_path / "w", case)["steps"] == result.steps


def test_a_worker_that_died_between_calls_is_replaced():
    """Also with PETSc loaded, which aborts the process on SIGPIPE (a write
    to the dead worker's pipe raises it)."""
    from petsc4py import PETSc  # noqa: F401 - its signal handlers installed

    assert worker.call(sum, ([1],), 30.0) == 1
    dead = worker.MESHING._worker
    dead.proc.kill()
    dead.proc.stdout.close()   # its death not yet seen: the request meets a closed pipe or a dead process
    for _ in range(50):
        if dead.proc.poll() is not None:
            break
        time.sleep(0.05)
    dead.proc.poll = lambda: None   # and the check before the send still takes it for alive
    assert worker.call(sum, ([2, 3],), 30.0) == 5
    assert worker.MESHING._worker is not dead
