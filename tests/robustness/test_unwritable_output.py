"""The output folder stops taking files in the middle of a run (a full disk,
a folder made read-only, a folder in a file's place): the run fails with
"failed: cannot write <file>: <reason>" in summary.json where it can still
be written (and on stderr), exit status 1, no temporary file left, every
finished step kept, and `--resume` finishes the run once the folder takes
files again.

Reference for the resumed run: the uninterrupted run of the same case (tip
positions within 1e-9 of the domain, as in test_resume.py: the resumed run
meshes from the checkpoint's size field and gmsh and MUMPS are
deterministic). The reasons are the system's own words for the errors the
file system gives (strerror): a folder in the file's place is refused by
rename(2) with EISDIR even to root, a small tmpfs in a private mount
namespace fills up for real, and ENOSPC at fsync(2) and EACCES at a file's
making or removal are injected where the system gives them (Refusals: root
ignores permission bits).
"""
from __future__ import annotations

import errno
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import wingcrack
from test_resume import L, write_case
from wingcrack import drawing
from wingcrack.errors import ComputationError
from wingcrack.io import atomic
from wingcrack.io.outdir import leftovers

STEPS = 3
WINGCRACK = Path(sys.executable).with_name("wingcrack")
IS_A_DIRECTORY = os.strerror(errno.EISDIR)


@pytest.fixture(scope="module")
def case(tmp_path_factory):
    return wingcrack.Case.from_toml(write_case(tmp_path_factory.mktemp("case") / "case.toml", steps=STEPS))


@pytest.fixture(scope="module")
def reference(case, tmp_path_factory):
    r = wingcrack.run(case, out=tmp_path_factory.mktemp("ref") / "out", plots=False)
    assert r.status == "finished" and len(r.steps) == STEPS
    return r


def tips(steps) -> np.ndarray:
    return np.array([[t["x"], t["y"]] for t in steps[-1]["tips"]])


def temporaries(out: Path) -> list[str]:
    """Every hidden file in `out` (a temporary of io/atomic.py is one)."""
    return sorted(p.name for p in out.iterdir() if p.name.startswith("."))


# (the file that cannot be written, the step after which its name is taken by a folder, plots):
# a step's files and the indices are written by step 1 first (after step 0), the checkpoint and
# summary.json in step 1's commit, the pictures after the last step
TARGETS = [("step_0001.vtu", 0, False), ("faces_0001.vtu", 0, False), ("fields.pvd", 0, False),
           ("faces.pvd", 0, False), ("checkpoint.npz", 0, False), ("summary.json", 0, False),
           ("fractures.png", STEPS - 1, False), ("history.png", STEPS - 1, True),
           ("growth.gif", STEPS - 1, True)]


@pytest.mark.parametrize("name, after, plots", TARGETS, ids=[t[0] for t in TARGETS])
def test_a_file_that_cannot_be_written_fails_the_run_and_resume_finishes_it(case, reference, tmp_path, name,
                                                                              after, plots):
    out = tmp_path / "out"
    target = out / name
    kept = []   # the file's content while a folder takes its place

    def progress(k, record):
        if k == after:
            if target.exists():
                kept.append(target.read_bytes())
                target.unlink()
            target.mkdir()   # rename(2) over it: EISDIR
            (target / "keep").write_text("a folder, not a file")

    with pytest.raises(ComputationError) as err:
        wingcrack.run(case, out=out, progress=progress, plots=plots)
    status = f"failed: cannot write {target}: {IS_A_DIRECTORY}"
    assert str(err.value) == status
    assert temporaries(out) == []
    if name != "summary.json":
        summary = json.loads((out / "summary.json").read_text())
        assert summary["status"] == status
        assert [s["step"] for s in summary["steps"]] == list(range(after + 1))   # every finished step
    shutil.rmtree(target)   # the folder takes the file again, as it was
    if kept:
        target.write_bytes(kept[0])
    resumed = wingcrack.run(case, out=out, resume=True, plots=plots)
    assert resumed.status == "finished" and len(resumed.steps) == STEPS
    assert np.abs(tips(resumed.steps) - tips(reference.steps)).max() < 1e-9 * L
    assert temporaries(out) == [] and leftovers(out) == []
    assert json.loads((out / "summary.json").read_text())["status"] == "finished"
    assert target.is_file()


class Refusals:
    """OSErrors injected where the file system gives them (root writes
    through permission bits, so a folder made read-only must be played):
    once armed, fsync(2) of the temporary file of a file in `full` fails
    with ENOSPC (a disk that fills while the file is written: the temporary
    file exists and must go); in a folder in `locked` (made unwritable)
    creating or removing a file fails with EACCES; a folder in
    `locked_at_removal` is locked when a file in it is first removed (made
    unwritable between a temporary file's making and its removal)."""

    def __init__(self, monkeypatch):
        self.full, self.locked, self.locked_at_removal = set(), set(), set()
        fsync, mkstemp, unlink = os.fsync, atomic.tempfile.mkstemp, atomic.os.unlink

        def full_fsync(fd):
            tmp = Path(os.readlink(f"/proc/self/fd/{fd}"))
            stem = atomic.temporary_of(tmp.name)
            if stem is not None and tmp.parent / stem in {p.parent / p.stem for p in self.full}:
                raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
            return fsync(fd)

        def locked_mkstemp(*args, dir=None, **kwargs):
            if dir is not None and Path(dir) in self.locked:
                raise PermissionError(errno.EACCES, os.strerror(errno.EACCES), str(dir))
            return mkstemp(*args, dir=dir, **kwargs)

        def locked_unlink(path, *args, **kwargs):
            folder = Path(path).parent
            if folder in self.locked_at_removal:
                self.locked.add(folder)
            if folder in self.locked:
                raise PermissionError(errno.EACCES, os.strerror(errno.EACCES), str(path))
            return unlink(path, *args, **kwargs)

        monkeypatch.setattr(os, "fsync", full_fsync)
        monkeypatch.setattr(atomic.tempfile, "mkstemp", locked_mkstemp)
        monkeypatch.setattr(atomic.os, "unlink", locked_unlink)
        monkeypatch.setattr(drawing, "_running", lambda: False)   # the pictures drawn here, where this reaches


@pytest.fixture
def refusals(monkeypatch):
    return Refusals(monkeypatch)


# the file the disk is full for, the step after which it fills (as TARGETS), plots
FULL = [("step_0001.vtu", 0, False), ("checkpoint.npz", 0, False), ("fields.pvd", 0, False),
        ("summary.json", 0, False), ("growth.gif", STEPS - 1, True)]


@pytest.mark.parametrize("name, after, plots", FULL, ids=[t[0] for t in FULL])
def test_a_disk_that_fills_while_a_file_is_written_fails_the_run_leaving_no_temporary(case, tmp_path, refusals,
                                                                                    name, after, plots):
    out = tmp_path / "out"

    def progress(k, record):
        if k == after:
            refusals.full.add(out / name)

    with pytest.raises(ComputationError) as err:
        wingcrack.run(case, out=out, progress=progress, plots=plots)
    status = f"failed: cannot write {out / name}: {os.strerror(errno.ENOSPC)}"
    assert str(err.value) == status
    assert temporaries(out) == []
    summary = json.loads((out / "summary.json").read_text())
    assert [s["step"] for s in summary["steps"]] == list(range(after + 1))
    # summary.json itself cannot say it: it keeps the last status it took
    assert summary["status"] == ("running" if name == "summary.json" else status)


def test_a_folder_made_unwritable_fails_the_run_with_summary_json_untouched_and_resume_finishes_it(
        case, reference, tmp_path, refusals):
    """Every file refused after step 0: the status goes to the caller only,
    summary.json says "running" with step 0, as the checkpoint does."""
    out = tmp_path / "out"

    def progress(k, record):
        if k == 0:
            refusals.locked.add(out)

    with pytest.raises(ComputationError) as err:
        wingcrack.run(case, out=out, progress=progress, plots=False)
    denied = os.strerror(errno.EACCES)
    assert str(err.value) == f"failed: cannot write {out / 'step_0001.vtu'}: {denied} " \
                             f"(summary.json not updated: {denied})"
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "running" and [s["step"] for s in summary["steps"]] == [0]
    assert temporaries(out) == []
    refusals.locked.clear()
    resumed = wingcrack.run(case, out=out, resume=True, plots=False)
    assert resumed.status == "finished" and len(resumed.steps) == STEPS
    assert np.abs(tips(resumed.steps) - tips(reference.steps)).max() < 1e-9 * L


def test_a_temporary_the_folder_refused_to_remove_goes_with_resume(case, reference, tmp_path, refusals):
    """The disk fills while the checkpoint is written and the folder is made
    read-only before its temporary file can go: it is left (the only file
    a failed write leaves), and `--resume` removes it before going on."""
    out = tmp_path / "out"

    def progress(k, record):
        if k == 0:
            refusals.full.add(out / "checkpoint.npz")
            refusals.locked_at_removal.add(out)

    with pytest.raises(ComputationError) as err:
        wingcrack.run(case, out=out, progress=progress, plots=False)
    assert str(err.value).startswith(f"failed: cannot write {out / 'checkpoint.npz'}: {os.strerror(errno.ENOSPC)}")
    left = [out / n for n in temporaries(out)]
    assert [atomic.temporary_of(p.name) for p in left] == ["checkpoint"] and leftovers(out) == left
    refusals.full.clear()
    refusals.locked.clear()
    refusals.locked_at_removal.clear()
    resumed = wingcrack.run(case, out=out, resume=True, plots=False)
    assert resumed.status == "finished" and len(resumed.steps) == STEPS
    assert temporaries(out) == []
    assert np.abs(tips(resumed.steps) - tips(reference.steps)).max() < 1e-9 * L


def _private_tmpfs(folder: Path, size_kib: int, *command) -> subprocess.CompletedProcess:
    """`command` run where `folder` is a tmpfs of `size_kib` KiB of its own,
    in a private mount namespace (as root `unshare -m`, else `unshare -rm`);
    the folder's files are copied to `folder`.copy before the namespace ends."""
    ns = ["unshare", "-m"] if os.geteuid() == 0 else ["unshare", "-r", "-m"]
    script = ('mount -t tmpfs -o size="$2"k tmpfs "$1" || exit 97; d="$1"; shift 2; "$@"; rc=$?; '
              'cp -a "$d" "$d.copy"; exit $rc')
    return subprocess.run([*ns, "sh", "-c", script, "sh", str(folder), str(size_kib), *map(str, command)],
                          capture_output=True, text=True, timeout=300)


def test_a_full_disk_exits_1_naming_the_file_and_resume_finishes(case, reference, tmp_path):
    """The command line on a real full disk: a tmpfs that holds step 0
    (a 0.6 MB field file, the checkpoint, the face file, the indices and
    the summary: ~0.9 MB) but not step 1's field file as well."""
    if not WINGCRACK.exists():
        pytest.skip("the wingcrack console script is not installed (make setup)")
    case_file = write_case(tmp_path / "case.toml", steps=STEPS)
    out = tmp_path / "out"
    out.mkdir()
    res = _private_tmpfs(out, 1200, WINGCRACK, "run", case_file, "-o", out, "--quiet", "--no-plots")
    if res.returncode == 97 or "unshare" in res.stderr:
        pytest.skip(f"no private tmpfs here: {' '.join(res.stderr.split())}")
    status = f"failed: cannot write {out / 'step_0001.vtu'}: {os.strerror(errno.ENOSPC)}"
    assert res.returncode == 1, res.stderr
    assert res.stderr == f"wingcrack: error: {status}\n"
    full = Path(f"{out}.copy")
    assert temporaries(full) == []
    summary = json.loads((full / "summary.json").read_text())
    assert summary["status"] == status and [s["step"] for s in summary["steps"]] == [0]
    resumed = subprocess.run([WINGCRACK, "run", case_file, "-o", full, "--quiet", "--no-plots", "--resume"],
                             capture_output=True, text=True, timeout=300)
    assert resumed.returncode == 0, resumed.stderr
    summary = json.loads((full / "summary.json").read_text())
    assert summary["status"] == "finished" and len(summary["steps"]) == STEPS
    assert np.abs(tips(summary["steps"]) - tips(reference.steps)).max() < 1e-9 * L


# sif's files: its step's, the picture, its summary
SIF = [("faces_0000.vtu", []), ("fractures.png", [0]), ("summary.json", None)]


@pytest.mark.parametrize("name, steps", SIF, ids=[t[0] for t in SIF])
def test_sif_into_a_full_disk_fails_naming_the_file(case, tmp_path, refusals, name, steps):
    out = tmp_path / "sif"
    refusals.full.add(out / name)
    with pytest.raises(ComputationError) as err:
        wingcrack.sif(case, out=out)
    status = f"failed: cannot write {out / name}: {os.strerror(errno.ENOSPC)}"
    assert str(err.value) == status
    assert temporaries(out) == []
    if steps is None:   # summary.json never written
        assert not (out / "summary.json").exists()
    else:
        summary = json.loads((out / "summary.json").read_text())
        assert summary["status"] == status and [s["step"] for s in summary["steps"]] == steps
