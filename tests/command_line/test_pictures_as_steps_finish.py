"""The growth animation drawn as the steps finish (wingcrack/drawing.py,
io/growing_animation.py): the frames the drawing process draws while the
run goes are taken at the end only where they are what the finished run
would draw, so that the run's pictures are those `wingcrack plot` draws
from the folder, however the run went.

References: `wingcrack plot` of a copy of the folder (every picture drawn
at once from the step files, no frame kept), compared byte for byte (the
drawing is deterministic: the same data give the same bytes); the
uninterrupted run of the same case, for a run stopped and resumed. The case
is the 45-degree disc coarsened to run in seconds; its colour scale settles
after the load's peak, so that frames are kept (checked: the tests would
otherwise compare a drawing with itself)."""
import json
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
WINGCRACK = Path(sys.executable).with_name("wingcrack")
STEPS = 10
PICTURES = ("growth.gif", "history.png", "fractures.png")


def disc_case(path: Path, steps: int = STEPS) -> Path:
    """cases/brazilian_disc_45.toml with the paper's coarser mesh and longer
    advance (docs/theory/propagation.md, "The paper's f0"), `steps` steps."""
    text = (ROOT / "cases" / "brazilian_disc_45.toml").read_text()
    for old, new in (("steps = 100", f"steps = {steps}"), ("length = 0.0005", "length = 0.0012"),
                     ("size = 0.004", "size = 0.008"), ("tip_size = 0.0005", "tip_size = 0.001"),
                     ("sectors = 32", "sectors = 16")):
        assert f"\n{old}" in text, old
        text = text.replace(f"\n{old}", f"\n{new}")
    path.write_text(text)
    return path


def run(case, out, *extra, check=True):
    proc = subprocess.run([str(WINGCRACK), "run", str(case), "-o", str(out), "--quiet", *extra],
                          capture_output=True, text=True)
    if check:
        assert proc.returncode == 0, proc.stderr
    return proc


def plotted(out: Path, to: Path) -> Path:
    """A copy of `out` without its pictures, drawn again by `wingcrack plot`."""
    shutil.copytree(out, to)
    for name in PICTURES:
        (to / name).unlink(missing_ok=True)
    proc = subprocess.run([str(WINGCRACK), "plot", str(to)], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    return to


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """The disc run uninterrupted, with its pictures, by the command line."""
    tmp = tmp_path_factory.mktemp("reference")
    out = tmp / "out"
    run(disc_case(tmp / "disc.toml"), out)
    return out


def test_the_runs_pictures_are_those_plot_draws(reference, tmp_path, monkeypatch):
    """A run from Python sends every committed step to the drawing process
    as it goes; its pictures are, byte for byte, those `wingcrack plot`
    draws of its folder, and the command line's."""
    import wingcrack
    from procs.worker import Channel

    sent = []
    real = Channel.send

    def send(self, fn, args, timeout):
        if fn.__name__ == "_draw_frames":
            sent.extend(k for k, _ in args[3])
        return real(self, fn, args, timeout)

    monkeypatch.setattr(Channel, "send", send)
    out = tmp_path / "out"
    r = wingcrack.run(wingcrack.Case.from_toml(disc_case(tmp_path / "disc.toml")), out=out)
    assert r.status == "finished" and len(r.steps) == STEPS
    # each step once, in order; the steps committed while the drawing process was busy go with the next
    # call, and those after the last call with the pictures at the end
    assert sent and sent == list(range(len(sent)))
    again = plotted(out, tmp_path / "plotted")
    for name in PICTURES:
        assert (out / name).read_bytes() == (again / name).read_bytes() == (reference / name).read_bytes(), name


def replay(out: Path, monkeypatch) -> dict:
    """The frames of the run in `out` drawn here as the drawing process
    draws them while it goes (its steps committed one by one), then its
    animation drawn from them: {"during": frames drawn as the steps came,
    "end": frames drawn at the end}."""
    from wingcrack.io import animation, frames, growing_animation
    from wingcrack.io.outdir import read_result

    count = {"during": 0, "end": 0}
    when = ["during"]
    real = frames.FrameDrawer.draw

    def draw(self, *args, **kwargs):
        count[when[0]] += 1
        return real(self, *args, **kwargs)

    monkeypatch.setattr(frames.FrameDrawer, "draw", draw)
    result = read_result(out)
    growing_animation.begin(out, result.summary["title"], result.summary["propagation"], True)
    for k, record in enumerate(result.steps):
        growing_animation.add(out, [(k, record)])
    when[0] = "end"
    animation.animate_growth(out, result, "gif")
    return count


def drawn_at_once(out: Path, to: Path) -> bytes:
    from wingcrack.io import animation
    from wingcrack.io.outdir import read_result

    shutil.copytree(out, to)
    animation.animate_growth(to, read_result(to), "gif")
    return (to / "growth.gif").read_bytes()


def test_frames_drawn_as_the_steps_come_are_taken_at_the_end(reference, tmp_path, monkeypatch):
    """The steps committed one by one: most frames drawn then, once the
    colour scale settled, and taken at the end, which draws the few before
    it; the movie is the one drawn at once."""
    out = tmp_path / "out"
    shutil.copytree(reference, out)
    count = replay(out, monkeypatch)
    assert count["during"] >= STEPS // 2 and count["end"] < STEPS // 2, count
    assert count["during"] + count["end"] >= STEPS
    assert (out / "growth.gif").read_bytes() == drawn_at_once(reference, tmp_path / "once") \
        == (reference / "growth.gif").read_bytes()


def scale_von_mises(path: Path, factor: float) -> None:
    import meshio

    m = meshio.read(path)
    m.point_data["von_mises"] = np.asarray(m.point_data["von_mises"]) * factor
    m.write(path)


def test_a_colour_scale_that_rises_at_the_last_step_draws_every_frame_again(reference, tmp_path, monkeypatch):
    """The last step's stress ten times higher: the colour scale's top
    changes with the last step, no frame drawn before holds, and the end
    draws them all; the movie is the one drawn at once."""
    out = tmp_path / "out"
    shutil.copytree(reference, out)
    scale_von_mises(out / f"step_{STEPS - 1:04d}.vtu", 10.0)
    count = replay(out, monkeypatch)
    assert count["during"] > 0 and count["end"] == STEPS, count
    assert (out / "growth.gif").read_bytes() == drawn_at_once(out, tmp_path / "once")


def test_a_step_file_rewritten_after_its_frame_is_drawn_again(reference, tmp_path, monkeypatch):
    """A frame kept for a step whose file changed since (its von Mises
    field lowered by a tenth at its median node, which leaves the colour
    scale as it was) is not taken: the end reads the file as it is."""
    from wingcrack.io import growing_animation

    out = tmp_path / "out"
    shutil.copytree(reference, out)
    count = replay(out, monkeypatch)   # the frames drawn as the steps came; the animation drawn once
    ends = count["end"]
    # again, with step STEPS - 2's file changed after the steps were committed
    from wingcrack.io import animation, frames
    from wingcrack.io.outdir import read_result

    result = read_result(out)
    growing_animation.begin(out, result.summary["title"], result.summary["propagation"], True)
    for k, record in enumerate(result.steps):
        growing_animation.add(out, [(k, record)])
    path = out / f"step_{STEPS - 2:04d}.vtu"
    import meshio

    m = meshio.read(path)
    vm = np.asarray(m.point_data["von_mises"]).copy()
    vm[np.argmin(np.abs(vm - np.median(vm)))] *= 0.9
    m.point_data["von_mises"] = vm
    time.sleep(0.01)   # a new modification time, whatever the file system's resolution
    m.write(path)
    drawn = []
    real = frames.FrameDrawer.draw
    monkeypatch.setattr(frames.FrameDrawer, "draw", lambda self, *a, **k: drawn.append(1) or real(self, *a, **k))
    animation.animate_growth(out, read_result(out), "gif")
    assert len(drawn) == ends + 1
    assert (out / "growth.gif").read_bytes() == drawn_at_once(out, tmp_path / "once")


def finished_steps(out) -> int:
    p = out / "summary.json"
    return len(json.loads(p.read_text())["steps"]) if p.exists() else 0


def test_an_interrupted_run_leaves_a_folder_plot_completes_and_resumed_its_pictures_are_the_whole_runs(
        reference, tmp_path):
    """Ctrl-C after four steps: the run stops cleanly (exit 130), with no
    pictures and no file half-written (the frames drawn were a cache of the
    drawing process); `wingcrack plot` draws its pictures, a frame a kept
    step; --resume finishes it, and its pictures are the uninterrupted
    run's, byte for byte (the frames of the steps kept drawn again by the
    new drawing process)."""
    from PIL import Image

    from wingcrack.io.outdir import leftovers

    case = disc_case(tmp_path / "disc.toml")
    out = tmp_path / "out"
    proc = subprocess.Popen([str(WINGCRACK), "run", str(case), "-o", str(out), "--quiet"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    t0 = time.perf_counter()
    while finished_steps(out) < 4:
        assert proc.poll() is None, "the run ended before it could be interrupted"
        assert time.perf_counter() - t0 < 120
        time.sleep(0.05)
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130, err
    kept = finished_steps(out)
    assert 4 <= kept < STEPS and json.loads((out / "summary.json").read_text())["status"] == "stopped: interrupted"
    assert not any((out / name).exists() for name in PICTURES) and leftovers(out) == []
    drawn = plotted(out, tmp_path / "plotted")
    with Image.open(drawn / "growth.gif") as im:
        assert im.n_frames == kept
    run(case, out, "--resume")
    for name in PICTURES:
        assert (out / name).read_bytes() == (reference / name).read_bytes(), name


def test_frames_left_when_the_run_hurries_the_drawing_are_drawn_at_the_end(reference, tmp_path, monkeypatch):
    """The drawing process told to hurry (the run ended and waits for its
    pictures) after two frames: it draws no more, and the end draws the
    rest; the movie is the one drawn at once."""
    from wingcrack.io import animation, frames, growing_animation
    from wingcrack.io.outdir import read_result

    out = tmp_path / "out"
    shutil.copytree(reference, out)
    drawn = []
    real = frames.FrameDrawer.draw
    monkeypatch.setattr(frames.FrameDrawer, "draw", lambda self, *a, **k: drawn.append(1) or real(self, *a, **k))
    result = read_result(out)
    growing_animation.begin(out, result.summary["title"], result.summary["propagation"], True)
    growing_animation.add(out, list(enumerate(result.steps)), hurry=lambda: len(drawn) >= 2)
    assert len(drawn) == 2
    animation.animate_growth(out, result, "gif")
    assert len(drawn) == 2 + STEPS - 2
    assert (out / "growth.gif").read_bytes() == drawn_at_once(reference, tmp_path / "once")
