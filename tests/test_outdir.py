"""Issue 6: nothing of a previous result is overwritten unless --force, and
an output folder that cannot be written is a bad input (exit 2, one line).

What --force means (wingcrack/io/outdir.py): the previous result's files
(summary.json, step and face files, the .pvd indices, the pictures) are
deleted before the new run, so no step file of a longer earlier run stays
among the new ones; nothing else in the folder is touched.
"""
from __future__ import annotations

import os
from pathlib import Path

import pytest

from wingcrack import cli
from wingcrack.errors import FolderError
from wingcrack.io.outdir import prepare, result_files

ROOT = Path(__file__).resolve().parents[1]
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
    assert "summary.json" in line and "3 step files" in line and line.endswith("use --force to replace it")
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


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes into read-only folders")
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


def test_prepare_raises_folder_error_naming_the_path(tmp_path):
    plant(tmp_path)
    with pytest.raises(FolderError) as err:
        prepare(tmp_path)
    assert err.value.path == str(tmp_path) and "--force" in err.value.reason
