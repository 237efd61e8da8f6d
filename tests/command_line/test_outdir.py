"""Issue 6: nothing of a previous result is overwritten unless --force, and
an output folder that cannot be written is a bad input (exit 2, one line).

What --force means (wingcrack/io/outdir.py): the previous result's files
(summary.json, step and face files, the .pvd indices, the pictures) are
deleted before the new run, so no step file of a longer earlier run stays
among the new ones; nothing else in the folder is touched.
"""
from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from wingcrack import cli
from wingcrack.errors import FolderError
from wingcrack.io.outdir import prepare, result_files

ROOT = Path(__file__).resolve().parents[2]
CASE = ROOT / "cases" / "griffith_inclined.toml"
PREVIOUS = ["summary.json", "step_0000.vtu", "step_0041.vtu", "faces_0041.vtu", "fields.pvd", "faces.pvd",
            "fractures.png", "history.png", "growth.gif", "fields.vtu", "faces.vtu"]


def plant(folder: Path) -> dict:
    """A previous result and a file that is not ours; {name: content}."""
    folder.mkdir(parents=True, exist_ok=True)
    files = {name: f"previous {name}" for name in PREVIOUS + ["notes.txt", "step_final.vtu"]}
    for name, text in files.items():
        (folder / name).write_text(text)
    return files


def contents(folder: Path) -> dict:
    return {p.name: p.read_text() for p in folder.iterdir()}


def error_line(capsys) -> str:
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in captured.err, captured.err
    return lines[0]


def test_result_files_are_ours_only(tmp_path):
    plant(tmp_path)
    assert sorted(p.name for p in result_files(tmp_path)) == sorted(PREVIOUS)


@pytest.mark.parametrize("command", ["run", "sif"])
def test_a_previous_result_is_refused_without_force(tmp_path, capsys, command):
    before = plant(tmp_path / "out")
    assert cli.main([command, str(CASE), "-o", str(tmp_path / "out")]) == 2
    line = error_line(capsys)
    assert line.startswith(f"wingcrack: error: {tmp_path / 'out'}: holds a previous result (")
    assert "summary.json" in line and "3 step files" in line and line.endswith("replace it with --force (force=True from Python)")
    assert contents(tmp_path / "out") == before


def test_force_replaces_the_previous_result_and_nothing_else(tmp_path, capsys):
    """A real `sif --force` into a folder holding a 42-step result: the stale
    step files are gone, the new result is there, notes.txt is untouched."""
    out = tmp_path / "out"
    before = plant(out)
    assert cli.main(["sif", str(CASE), "-o", str(out), "--force", "--quiet"]) == 0
    after = {p.name for p in out.iterdir()}
    # the layout of a one-step run (the old fields.vtu and faces.vtu are gone with the previous result)
    assert after == {"summary.json", "step_0000.vtu", "faces_0000.vtu", "fields.pvd", "faces.pvd", "fractures.png",
                     "notes.txt", "step_final.vtu"}
    assert (out / "notes.txt").read_text() == before["notes.txt"]
    assert (out / "summary.json").read_text() != before["summary.json"]
    assert capsys.readouterr().out.startswith(f"wingcrack: finished; results in {out}/: ")
    # a `sif` result plots as any run: one step, one frame (from step_0000.vtu)
    assert cli.main(["plot", str(out)]) == 0
    animation = next(out.glob("growth.*"))
    if animation.suffix == ".gif":
        from PIL import Image

        with Image.open(animation) as im:
            assert im.n_frames == 1


def test_an_empty_or_foreign_folder_is_used_as_it_is(tmp_path):
    (tmp_path / "notes.txt").write_text("mine")
    assert prepare(tmp_path) == tmp_path
    assert prepare(tmp_path / "new" / "deeper").is_dir()
    assert (tmp_path / "notes.txt").read_text() == "mine"


@pytest.mark.parametrize("command", ["run", "sif"])
def test_an_output_path_below_a_file_exits_2(tmp_path, capsys, command):
    (tmp_path / "file").write_text("")
    assert cli.main([command, str(CASE), "-o", str(tmp_path / "file" / "out")]) == 2
    assert error_line(capsys) == f"wingcrack: error: {tmp_path / 'file' / 'out'}: cannot create the folder (Not a directory)"


@pytest.mark.parametrize("command", ["run", "sif"])
def test_an_output_path_that_is_a_file_exits_2(tmp_path, capsys, command):
    (tmp_path / "file").write_text("keep")
    assert cli.main([command, str(CASE), "-o", str(tmp_path / "file"), "--force"]) == 2
    assert error_line(capsys) == f"wingcrack: error: {tmp_path / 'file'}: is a file, not a folder"
    assert (tmp_path / "file").read_text() == "keep"


def test_a_folder_that_cannot_be_created_exits_2(capsys):
    """/proc refuses new folders, even to root."""
    assert cli.main(["sif", str(CASE), "-o", "/proc/wingcrack-out"]) == 2
    assert error_line(capsys).startswith("wingcrack: error: /proc/wingcrack-out: cannot create the folder (")


@pytest.mark.skipif(os.geteuid() == 0, reason="root ignores permission bits; "
                    "test_a_read_only_file_system_exits_2 binds root instead")
def test_a_read_only_folder_exits_2(tmp_path, capsys):
    out = tmp_path / "ro"
    out.mkdir()
    out.chmod(0o555)
    try:
        assert cli.main(["run", str(CASE), "-o", str(out)]) == 2
        assert error_line(capsys) == f"wingcrack: error: {out}: cannot write into the folder (Permission denied)"
        assert cli.main(["plot", str(out)]) == 2   # not a result either
    finally:
        out.chmod(0o755)


def read_only(folder: Path, *command) -> subprocess.CompletedProcess:
    """`command` run in a private mount namespace where `folder` is a
    read-only bind mount of itself: refused even to root (EROFS, checked
    before any permission). As root `unshare -m`; otherwise `unshare -rm`
    (a user namespace maps us to root in it). Nothing outside sees the mount,
    and it goes with the namespace's last process."""
    ns = ["unshare", "-m"] if os.geteuid() == 0 else ["unshare", "-r", "-m"]
    script = 'mount --bind "$1" "$1" && mount -o remount,ro,bind "$1" "$1" && shift && exec "$@"'
    return subprocess.run([*ns, "sh", "-c", script, "sh", str(folder), *map(str, command)],
                          capture_output=True, text=True, timeout=300)


def test_a_read_only_file_system_exits_2(tmp_path):
    """A read-only output folder for root too (CI runs as root): `run` into
    it and `plot` of a result in it exit 2 naming the folder; nothing in it
    changes."""
    probe = tmp_path / "probe"
    probe.mkdir()
    setup = read_only(probe, "sh", "-c", ': > "$0/x"', probe)
    if setup.returncode != 0 and "Read-only file system" not in setup.stderr:
        pytest.skip(f"no private read-only mount here: {' '.join(setup.stderr.split())}")
    assert not (probe / "x").exists()
    out = tmp_path / "ro"
    assert cli.main(["sif", str(CASE), "-o", str(out), "--quiet"]) == 0   # a result to plot, made writable
    for name in ("fractures.png", "growth.gif", "growth.mp4", "history.png"):
        (out / name).unlink(missing_ok=True)
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    wingcrack = Path(sys.executable).with_name("wingcrack")
    run = read_only(out, wingcrack, "run", CASE, "-o", out, "--force", "--quiet")
    assert run.returncode == 2, run.stderr
    assert run.stderr == f"wingcrack: error: {out}: cannot write into the folder (Read-only file system)\n"
    plot = read_only(out, wingcrack, "plot", out)
    assert plot.returncode == 2, plot.stderr
    assert plot.stderr == f"wingcrack: error: {out}: cannot write into the folder (Read-only file system)\n"
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before


def test_prepare_raises_folder_error_naming_the_path(tmp_path):
    plant(tmp_path)
    with pytest.raises(FolderError) as err:
        prepare(tmp_path)
    assert err.value.path == str(tmp_path) and "--force" in err.value.reason


# ---------------------------------------------------------------- one command per folder (issue 12.5)

HOLD = ("import sys, time\nfrom wingcrack.io.outdir import locked\n"
        "with locked(sys.argv[1]):\n    print('locked', flush=True)\n    time.sleep(600)")


def hold(folder: Path) -> subprocess.Popen:
    """Another process holding the folder's lock (as a running command does)."""
    proc = subprocess.Popen([sys.executable, "-c", HOLD, str(folder)], stdout=subprocess.PIPE, text=True)
    assert proc.stdout.readline() == "locked\n"
    return proc


def in_use(folder: Path, pid: int) -> str:
    return (f"wingcrack: error: {folder}: is in use by another wingcrack run (pid {pid}); "
            "wait for it to end or use another folder")


@pytest.mark.parametrize("command", [["run", str(CASE), "--force"], ["sif", str(CASE), "--force"],
                                     ["run", str(CASE), "--resume"], ["plot"]],
                         ids=["run", "sif", "resume", "plot"])
def test_a_folder_in_use_is_refused_and_left_alone(tmp_path, capsys, command):
    """While another process holds the folder, every command that writes
    there exits 2 naming the folder and the holder, and touches nothing;
    even --force, which would otherwise delete the previous result."""
    out = tmp_path / "out"
    before = plant(out)
    holder = hold(out)
    try:
        args = command[:1] + ([str(out)] if command == ["plot"] else command[1:2] + ["-o", str(out)] + command[2:])
        assert cli.main(args) == 2
        assert error_line(capsys) == in_use(out, holder.pid)
        assert contents(out) == before
    finally:
        holder.kill()
        holder.wait()


def test_the_lock_dies_with_its_process_and_leaves_nothing(tmp_path):
    """SIGKILL cannot run any clean-up: the kernel drops a flock with the
    last descriptor of the process that held it, so the folder is free at
    once, and no lock file is there to be taken for a result or left stale."""
    from wingcrack.io.outdir import locked

    out = tmp_path / "out"
    out.mkdir()
    holder = hold(out)
    with pytest.raises(FolderError, match=f"in use by another wingcrack run \\(pid {holder.pid}\\)"):
        with locked(out):
            pass
    holder.send_signal(signal.SIGKILL)
    holder.wait()
    with locked(out):
        with locked(out):   # re-entrant within a process: the CLI's command, then the api
            pass
        other = subprocess.run([sys.executable, "-c", HOLD, str(out)], capture_output=True, text=True, timeout=60)
        assert other.returncode == 1 and f"in use by another wingcrack run (pid {os.getpid()})" in other.stderr
    holder = hold(out)   # released on leaving
    holder.kill()
    holder.wait()
    assert list(out.iterdir()) == []


def test_two_runs_into_one_folder(tmp_path):
    """The reproduction of issue 12.5: a second `run --force` started into
    the folder of a running `run` exits 2 at once; the first ends finished
    with its own files only (its title, its number of steps, one step file
    of each kind per step), none deleted by the second's --force."""
    from builders import square_plate_with_cracks
    from networks import to_toml

    def case(path, title, steps):
        d = square_plate_with_cracks(4.0, [[[-1.0, -0.3], [-0.4, 0.1]]], (0.0, 0.0, 0.0), size=0.5, tip_size=0.05)
        d["title"] = title
        d["bc"] += [{"on": "top", "traction": [0.0, 1e5]}, {"on": "bottom", "traction": [0.0, -1e5]}]
        d["propagation"] = {"steps": steps, "length": 0.1}
        path.write_text(to_toml(d))
        return path

    wingcrack = Path(sys.executable).with_name("wingcrack")
    out = tmp_path / "out"
    first = subprocess.Popen([str(wingcrack), "run", str(case(tmp_path / "a.toml", "first", 8)), "-o", str(out),
                              "--quiet", "--no-plots"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    t0 = time.perf_counter()
    while not (out / "summary.json").exists():   # the first has its lock and has written
        assert first.poll() is None, first.communicate()
        assert time.perf_counter() - t0 < 120
        time.sleep(0.05)
    second = subprocess.run([str(wingcrack), "run", str(case(tmp_path / "b.toml", "second", 2)), "-o", str(out),
                             "--force", "--quiet", "--no-plots"], capture_output=True, text=True, timeout=120)
    running = first.poll() is None
    _, err = first.communicate(timeout=300)
    assert running, "the first run ended before the second started: nothing was tested"
    assert second.returncode == 2 and second.stderr == in_use(out, first.pid) + "\n"
    assert first.returncode == 0, err
    s = json.loads((out / "summary.json").read_text())
    assert (s["title"], s["status"], len(s["steps"])) == ("first", "finished", 8)
    assert sorted(p.name for p in out.glob("*_*.vtu")) == [f"{k}_{i:04d}.vtu" for k in ("faces", "step")
                                                           for i in range(8)]


def test_the_folder_is_collective_exactly_where_a_launcher_names_the_rank(tmp_path):
    """One rank detection (wingcrack.parallel): the folder's lock is taken
    collectively where world_rank reads a launcher's rank from the
    environment (each of its variables), and a serial command locks its
    folder without starting MPI."""
    from wingcrack import parallel

    code = ("import sys; from wingcrack.io.outdir import locked; from wingcrack.parallel import launched, world_rank\n"
            "with locked(sys.argv[1]):\n"
            "    print(launched(), world_rank(), 'mpi4py.MPI' in sys.modules)\n")
    clean = {k: v for k, v in os.environ.items() if k not in parallel._RANK_VARIABLES and "OMPI" not in k
             and not k.startswith(("PMI", "PMIX"))}
    serial = subprocess.run([sys.executable, "-c", code, str(tmp_path)], env=clean, capture_output=True, text=True,
                            timeout=120)
    assert serial.stdout == "False 0 False\n", serial.stderr
    for name in parallel._RANK_VARIABLES:   # rank 0 of a launcher (a singleton MPI here)
        ranked = subprocess.run([sys.executable, "-c", code, str(tmp_path)], env={**clean, name: "0"},
                                capture_output=True, text=True, timeout=120)
        assert ranked.stdout == "True 0 True\n", (name, ranked.stderr)
