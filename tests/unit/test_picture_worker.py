"""The drawing process (wingcrack/drawing.py): `sif` and `run` draw their
pictures in a long-lived worker started at their top, and return with them.

References: the same pictures drawn in this process (plotting.draw_pictures, the
code `wingcrack plot` runs) from a copy of the result, compared pixel for
pixel (Agg is deterministic: the same figure gives the same pixels, so the
tolerance is none); the warnings of a picture that cannot be drawn in this
process, compared as text; a worker that is killed, which must cost nothing
but the time of drawing here."""
import errno
import json
import os
import shutil
import signal
import sys

import numpy as np
import pytest

import wingcrack
from builders import square_plate_with_cracks
from wingcrack import api, drawing
from wingcrack.io import plotting


def plate(steps=2):
    d = square_plate_with_cracks(4.0, [[[-0.5, 0.0], [0.5, 0.0]]], (0.0, 0.0, 0.0), size=0.5, tip_size=0.05)
    d["bc"] += [{"on": "top", "traction": [0.0, 1e5]}, {"on": "bottom", "traction": [0.0, -1e5]}]
    d["propagation"] = {"steps": steps, "length": 0.1}
    return wingcrack.Case.from_dict(d)


@pytest.fixture
def calls(monkeypatch):
    """What the drawing process was asked (function names), and its pid."""
    from procs.worker import Channel

    seen = []
    real = Channel.call

    def call(self, fn, args, timeout):
        if self.name == "drawing":
            seen.append((fn.__name__, self._worker.proc.pid))
        return real(self, fn, args, timeout)

    monkeypatch.setattr(Channel, "call", call)
    return seen


def pixels(path):
    from PIL import Image

    with Image.open(path) as im:
        frames = []
        for k in range(getattr(im, "n_frames", 1)):
            im.seek(k)
            frames.append(np.asarray(im.convert("RGBA")))
    return frames


def same_pixels(a, b):
    fa, fb = pixels(a), pixels(b)
    return len(fa) == len(fb) and all(x.shape == y.shape and np.array_equal(x, y) for x, y in zip(fa, fb))


def redrawn_here(out, tmp_path, history, animation):
    """The result's pictures drawn in this process, in a copy of `out`."""
    here = tmp_path / "here"
    shutil.copytree(out, here)
    for name in ("fractures.png", "history.png", "growth.gif", "growth.mp4"):
        (here / name).unlink(missing_ok=True)
    summary = json.loads((out / "summary.json").read_text())
    summary.pop("warnings", None)
    files, warnings = plotting.draw_pictures(here, summary, history, animation)
    return here, files, warnings


def test_sif_draws_in_the_worker_the_pictures_drawn_here(tmp_path, calls):
    out = tmp_path / "sif"
    r = wingcrack.sif(plate(), out=out)
    assert [name for name, _ in calls] == ["_pictures_answer"]
    assert os.getpid() != calls[0][1]
    assert r.files["picture"] == out / "fractures.png" and "warnings" not in r.summary
    here, files, warnings = redrawn_here(out, tmp_path, False, False)
    assert not warnings and set(files) == {"picture"}
    assert same_pixels(out / "fractures.png", here / "fractures.png")


def test_run_draws_in_the_worker_every_picture_drawn_here(tmp_path, calls):
    out = tmp_path / "run"
    r = wingcrack.run(plate(2), out=out)
    assert [name for name, _ in calls] == ["_pictures_answer"] and r.status == "finished"
    here, files, warnings = redrawn_here(out, tmp_path, True, True)
    assert not warnings and {k: v.name for k, v in files.items()} == {k: r.files[k].name for k in files}
    for name in ("fractures.png", "history.png", files["animation"].name):
        assert same_pixels(out / name, here / name), name
    # the worker's own start-up did not load the computation: no MPI, no DOLFINx in it
    loaded = drawing._drawing().call(api_modules_loaded, (("mpi4py", "dolfinx", "petsc4py", "gmsh"),), 60.0)
    assert loaded == [], loaded


def api_modules_loaded(names):
    """In the worker: which of `names` it has imported."""
    return [n for n in names if n in sys.modules]


def test_a_picture_that_fails_in_the_worker_warns_as_here(tmp_path, monkeypatch, calls):
    """fractures.png and the animation cannot be drawn (the face file they
    read damaged between the solve and the drawing): the same warnings as
    drawn in-process, the status "finished", history.png drawn. (A picture
    that cannot be written is a failure of the run: test_unwritable_output.py.)"""
    real = drawing.pictures

    def damaged(out, summary, history, animation):
        (out / "faces_0000.vtu").write_text("not a VTU file")
        return real(out, summary, history, animation)

    monkeypatch.setattr(drawing, "pictures", damaged)
    out = tmp_path / "run"
    r = wingcrack.run(plate(1), out=out)
    assert [name for name, _ in calls] == ["_pictures_answer"]
    saved = json.loads((out / "summary.json").read_text())
    assert saved["status"] == "finished" and len(saved["warnings"]) == 2
    assert saved["warnings"][0].startswith("fractures.png could not be drawn (FolderError")
    assert saved["warnings"][1].startswith("the growth animation could not be drawn (FolderError")
    assert (out / "history.png").is_file() and "picture" not in r.files
    summary = dict(saved)
    summary.pop("warnings")
    _, here = plotting.draw_pictures(out, summary, True, True)
    assert here == saved["warnings"]


def test_a_picture_the_folder_refuses_in_the_worker_fails_the_run_without_drawing_it_here(tmp_path, monkeypatch,
                                                                                        calls):
    """fractures.png's name taken by a folder between the solve and the
    drawing (rename(2) refuses it with EISDIR): the worker's WriteError ends
    the run as drawn in-process, and the pictures are not drawn again here."""
    real = drawing.pictures

    def blocked(out, summary, history, animation):
        (out / "fractures.png").mkdir()
        return real(out, summary, history, animation)

    here = []   # the pictures drawn in this process (the worker's api is its own)
    plot_here = plotting.plot
    monkeypatch.setattr(drawing, "pictures", blocked)
    monkeypatch.setattr(plotting, "plot", lambda *args, **kwargs: here.append(args) or plot_here(*args, **kwargs))
    out = tmp_path / "run"
    with pytest.raises(wingcrack.ComputationError) as err:
        wingcrack.run(plate(1), out=out)
    status = f"failed: cannot write {out / 'fractures.png'}: {os.strerror(errno.EISDIR)}"
    assert str(err.value) == status and json.loads((out / "summary.json").read_text())["status"] == status
    assert here == []   # not drawn again here
    assert [name for name, _ in calls] == ["_pictures_answer"]


@pytest.mark.parametrize("when", ["before", "while"])
def test_a_dead_drawing_process_leaves_the_pictures_to_this_one(tmp_path, monkeypatch, when):
    """The worker killed before the pictures are asked for, or after the
    request is sent (the answer never comes): the pictures are drawn here,
    with no warning."""
    from procs.worker import Channel

    real_pictures, real_send = drawing.pictures, Channel.send
    killed = []

    def pictures(*args):
        proc = drawing._drawing()._worker.proc
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait()
        killed.append(proc.pid)
        return real_pictures(*args)

    def send(self, fn, args, timeout):
        call = real_send(self, fn, args, timeout)
        if self.name == "drawing":
            os.kill(call._worker.proc.pid, signal.SIGKILL)
            killed.append(call._worker.proc.pid)
        return call

    if when == "before":
        monkeypatch.setattr(drawing, "pictures", pictures)
    else:
        monkeypatch.setattr(Channel, "send", send)
    out = tmp_path / "sif"
    r = wingcrack.sif(plate(), out=out)
    assert killed and "warnings" not in r.summary and r.files["picture"] == out / "fractures.png"
    here, _, _ = redrawn_here(out, tmp_path, False, False)
    assert same_pixels(out / "fractures.png", here / "fractures.png")
    assert not drawing._running()   # the dead one is gone and no other was started for nothing


@pytest.mark.parametrize("when", ["sent", "waiting"])
def test_ctrl_c_while_the_worker_draws(tmp_path, monkeypatch, when):
    """Ctrl-C just after the request is sent, or while waiting for the
    answer: as in-process, status "stopped: interrupted" with every step
    kept and KeyboardInterrupt; the worker is killed (it would otherwise
    write pictures after the final status); `wingcrack plot` draws them
    afterwards."""
    import threading

    from procs.worker import Channel

    real = Channel.send
    sent = []

    def send(self, fn, args, timeout):
        call = real(self, fn, args, timeout)
        if self.name == "drawing":
            sent.append(call._worker.proc)
            if when == "sent":
                os.kill(os.getpid(), signal.SIGINT)
            else:   # fractures.png takes longer than this to draw
                threading.Timer(0.05, os.kill, (os.getpid(), signal.SIGINT)).start()
        return call

    monkeypatch.setattr(Channel, "send", send)
    out = tmp_path / "run"
    case = plate(2)
    with pytest.raises(KeyboardInterrupt):
        wingcrack.run(case, out=out, plots=False)
    saved = json.loads((out / "summary.json").read_text())
    assert saved["status"] == "stopped: interrupted" and len(saved["steps"]) == 2
    assert len(sent) == 1 and sent[0].poll() is not None and not drawing._running()
    monkeypatch.setattr(Channel, "send", real)
    assert set(wingcrack.plot(out, history=False, animation=False)) == {"picture"}


def test_only_rank_0_starts_a_drawing_process(monkeypatch):
    """Under mpirun only rank 0 draws (api.run and api.sif), so only it has a
    drawing process."""
    from wingcrack import parallel

    drawing._drawing().shutdown()
    monkeypatch.setattr(parallel, "world_rank", lambda: 1)
    drawing.start()
    assert drawing._drawing()._worker is None and not drawing._running()
    monkeypatch.setattr(parallel, "world_rank", lambda: 0)
    drawing.start()
    assert drawing._running()


@pytest.mark.parametrize("blocked", [False, True])
def test_a_failed_run_draws_its_finished_steps_in_the_worker(tmp_path, monkeypatch, calls, blocked):
    """A run that fails in its second step: its pictures (of step 0) drawn
    in the worker, as `wingcrack plot` draws them here; fractures.png that
    cannot be written: the ComputationError says "pictures not drawn" with
    the message drawn here gives."""
    from wingcrack import step

    real = step.discretise
    seen = []

    def fails_second(case, fractures, timer, **kw):
        seen.append(1)
        if len(seen) == 2:
            if blocked:
                (out / "fractures.png").mkdir()
            raise wingcrack.ComputationError("contact did not converge (simulated)")
        return real(case, fractures, timer, **kw)

    monkeypatch.setattr(step, "discretise", fails_second)
    out = tmp_path / "run"
    with pytest.raises(wingcrack.ComputationError) as err:
        wingcrack.run(plate(3), out=out)
    assert [name for name, _ in calls] == ["_plot_answer"]
    saved = json.loads((out / "summary.json").read_text())
    assert saved["status"].startswith("failed: step 1") and len(saved["steps"]) == 1
    if blocked:
        with pytest.raises(Exception) as here:
            api.plot(out, history=True, animation=True)
        assert str(err.value) == f"{saved['status']} (pictures not drawn: {' '.join(str(here.value).split())})"
        assert "IsADirectoryError" not in str(err.value) and "Is a directory" in str(err.value)
        return
    assert str(err.value) == saved["status"]
    worker = tmp_path / "worker"
    shutil.copytree(out, worker)
    drawn = api.plot(out, history=True, animation=True)   # a second time, here
    assert {k: v.name for k, v in drawn.items()} == {"picture": "fractures.png", "history": "history.png",
                                                   "animation": drawn["animation"].name}
    for path in drawn.values():
        assert same_pixels(worker / path.name, path), path.name


def test_a_large_answer_comes_back_in_linear_time():
    """A worker's answer is read from a pipe 64 KiB at a time: gathering it
    by bytes concatenation was quadratic (a 96 MB answer took 40 s, 8 MB 0.3
    s). Reference: the time of an answer 8 times smaller; linear reading
    gives about 8 times that (plus a fixed cost, which only lowers the
    ratio), quadratic 64 times, so 25 separates them with room for a busy
    machine."""
    import time

    from procs import worker

    channel = worker.Channel("test", "numpy")
    try:
        assert channel.call(np.zeros, (1,), 60.0).shape == (1,)
        seconds = []
        for n in (1_000_000, 8_000_000):
            t0 = time.perf_counter()
            a = channel.call(np.ones, (n,), 600.0)
            seconds.append(time.perf_counter() - t0)
            assert a.shape == (n,) and a.sum() == n
        assert seconds[1] < 25 * seconds[0] + 0.5, seconds
    finally:
        channel.shutdown()
