"""Issue 6: the Python API a user scripts with (wingcrack.sif / wingcrack.run
and their results). References: the summary.json the same run writes, and
the DOLFINx displacement evaluated against the nodal values wingcrack's own
SIF code uses."""
import json

import numpy as np
import pytest

import wingcrack
from builders import square_plate_with_cracks


def plate(steps=2):
    d = square_plate_with_cracks(4.0, [[[-0.5, 0.0], [0.5, 0.0]]], (0.0, 0.0, 0.0), size=0.5, tip_size=0.05)
    d["bc"] += [{"on": "top", "traction": [0.0, 1e5]}, {"on": "bottom", "traction": [0.0, -1e5]}]
    d["propagation"] = {"steps": steps, "length": 0.1}
    return wingcrack.Case.from_dict(d)


def test_run_result_is_plain_python_and_matches_summary(tmp_path, capsys):
    r = wingcrack.run(plate(), out=tmp_path / "o", progress=True, plots=False)
    assert r.status == "finished" and len(r.steps) == 2
    saved = json.loads((tmp_path / "o" / "summary.json").read_text())
    assert r.steps == saved["steps"]
    assert r.tips == saved["steps"][-1]["tips"] and all(isinstance(t["KI"], float) for t in r.tips)
    assert len(r.polylines) == 1 and r.polylines[0].shape[1] == 2
    # the polyline runs from the end-0 tip to the end-1 tip of the summary's last state
    ends = [p for f in saved["fractures"] for p in (f["points"][0], f["points"][-1])]
    assert min(np.linalg.norm(np.array(ends) - r.polylines[0][0], axis=1)) < 1e-12
    # DOLFINx objects of the last step, for users who compute more
    assert r.dolfinx_mesh is r.problem.fm.mesh and r.displacement is r.problem.u
    assert np.all(np.isfinite(r.displacement.x.array))
    assert "step" in capsys.readouterr().err   # progress=True shows the bar


def test_to_dataframe_with_or_without_pandas(tmp_path):
    r = wingcrack.sif(plate(), out=tmp_path / "s")
    try:
        import pandas  # noqa: F401
    except ImportError:
        with pytest.raises(ImportError, match="needs pandas"):
            r.to_dataframe()
        from wingcrack.results import tip_rows
        rows = tip_rows(r.summary["steps"])
        assert [row["KI"] for row in rows] == [t.KI for t in r.tips]
        return
    df = r.to_dataframe()
    assert list(df["KI"]) == [t.KI for t in r.tips]


def test_help_reads_well():
    for f in (wingcrack.run, wingcrack.sif, wingcrack.plot, wingcrack.Case.from_toml, wingcrack.Case.from_dict):
        assert f.__doc__ and len(f.__doc__.split()) > 10, f
    assert "progress" in wingcrack.run.__doc__ and "resume" in wingcrack.run.__doc__


def test_case_errors_are_exceptions_naming_the_key():
    bad = square_plate_with_cracks(4.0, [[[-0.5, 0.0], [0.5, 0.0]]], (0.0, 1e5, 0.0), size=0.5, tip_size=0.05)
    bad["material"]["nu"] = 0.7
    with pytest.raises(wingcrack.CaseError, match="material.nu"):
        wingcrack.Case.from_dict(bad)


# ---------------------------------------------------------------- issue 12: one step for sif and run


def fixed_plate(steps=1):
    """The plate under its load as given (factor 1), below KIc."""
    d = square_plate_with_cracks(4.0, [[[-0.5, 0.0], [0.5, 0.0]]], (0.0, 0.0, 0.0), size=0.5, tip_size=0.05)
    d["bc"] += [{"on": "top", "traction": [0.0, 1e5]}, {"on": "bottom", "traction": [0.0, -1e5]}]
    d["propagation"] = {"steps": steps, "length": 0.1, "load": "fixed"}
    return wingcrack.Case.from_dict(d)


def without_seconds(step):
    return {k: v for k, v in step.items() if k != "seconds"}


def test_sif_is_step_0_of_a_run(tmp_path):
    """Reference: the run of the same case at the same load factor (1,
    "fixed"), whose step 0 stops below KIc: the same record (mesh, DOFs,
    SIFs of both methods, contact, mesh statistics) bit for bit, and the same
    files, which read_result reads back the same way."""
    from wingcrack.io.outdir import read_result

    s = wingcrack.sif(fixed_plate(), out=tmp_path / "sif")
    r = wingcrack.run(fixed_plate(), out=tmp_path / "run", plots=False)
    assert r.status == "stopped: no tip reaches KIc under the fixed load" and len(r.steps) == 1
    assert without_seconds(s.summary["steps"][0]) == without_seconds(r.steps[0])
    assert s.summary["fractures"] == r.summary["fractures"]
    names = {"summary.json", "step_0000.vtu", "faces_0000.vtu", "fields.pvd", "faces.pvd", "fractures.png"}
    assert {p.name for p in (tmp_path / "sif").iterdir()} == names
    assert names - {"fractures.png"} <= {p.name for p in (tmp_path / "run").iterdir()}
    for folder in ("sif", "run"):
        stored = read_result(tmp_path / folder)
        assert [p.name for p in stored.fields] == ["step_0000.vtu"] and [p.name for p in stored.faces] == ["faces_0000.vtu"]
    a, b = read_result(tmp_path / "sif").fields_of(0), read_result(tmp_path / "run").fields_of(0)
    assert np.array_equal(a.x, b.x) and np.array_equal(a.von_mises, b.von_mises, equal_nan=True)


def test_sif_meshes_in_the_worker_under_the_time_limit(monkeypatch):
    """`sif` meshed in its own process with no time limit; now through the
    meshing worker with the run's limit, like every step of a run."""
    from meshing import worker

    from wingcrack import step

    seen = []
    real = worker.send

    def send(fn, args, timeout):
        seen.append(timeout)
        return real(fn, args, timeout)

    monkeypatch.setattr(worker, "send", send)
    wingcrack.sif(fixed_plate())
    assert seen == [step.MESH_TIMEOUT]


@pytest.mark.parametrize("error", [RuntimeError("gmsh could not mesh the domain: simulated"),
                                   ValueError("tip at (0, 0) is closer than 1.5 tip_size to the boundary"),
                                   np.linalg.LinAlgError("singular matrix"),
                                   wingcrack.ComputationError("contact did not converge")])
def test_sif_and_run_fail_the_same_way(tmp_path, monkeypatch, error):
    """Either command: exit 1's ComputationError and summary.json saying
    "failed: step 0: <reason>" (a RuntimeError in `sif` was "unexpected",
    with no summary)."""
    from wingcrack import step

    def fail(*a, **k):
        raise error

    monkeypatch.setattr(step, "discretise", fail)
    for name, command in (("sif", wingcrack.sif), ("run", lambda c, out: wingcrack.run(c, out=out, plots=False))):
        out = tmp_path / name
        with pytest.raises(wingcrack.ComputationError) as err:
            command(fixed_plate(), out=out)
        assert str(err.value) == f"failed: step 0: {error}"
        saved = json.loads((out / "summary.json").read_text())
        assert saved["status"] == str(err.value) and saved["steps"] == []


PLATE_TOML = """
title = "plate"
[material]
E = 10e9
nu = 0.25
KIc = 1.0e6
[domain]
shape = "rectangle"
corner = [-2.0, -2.0]
size = [4.0, 4.0]
[[fractures]]
points = [[-0.5, 0.0], [0.5, 0.0]]
[[bc]]
on = "top"
traction = [0.0, 1e5]
[[bc]]
on = "bottom"
traction = [0.0, -1e5]
[[bc]]
at = [-2.0, -2.0]
displacement = [0.0, 0.0]
[[bc]]
at = [2.0, -2.0]
displacement_y = 0.0
[mesh]
size = 0.5
tip_size = 0.05
[propagation]
steps = 2
length = 0.1
"""


@pytest.mark.parametrize("command", ["sif", "run"])
def test_a_picture_that_fails_is_a_warning_not_a_failure(tmp_path, monkeypatch, capsys, command):
    """Promise 3: fractures.png cannot be drawn (here: a simulated raster
    overflow). Exit 0, status "finished", every data file written and
    readable, the other pictures drawn, the failure in summary.json's
    "warnings" and once on stderr."""
    from wingcrack import cli, drawing
    from wingcrack.io import pictures
    from wingcrack.io.outdir import read_result

    def broken(path, result):
        raise ValueError("Image size of 60000000x600 pixels is too large (simulated)")

    monkeypatch.setattr(pictures, "fractures_of_result", broken)
    monkeypatch.setattr(drawing, "_running", lambda: False)   # drawn here, where the failure is simulated
    path = tmp_path / "plate.toml"
    path.write_text(PLATE_TOML)
    out = tmp_path / "out"
    assert cli.main([command, str(path), "-o", str(out), "--quiet"]) == 0
    captured = capsys.readouterr()
    saved = json.loads((out / "summary.json").read_text())
    assert saved["status"] == "finished"
    assert len(saved["warnings"]) == 1 and saved["warnings"][0].startswith(
        "fractures.png could not be drawn (ValueError: Image size of 60000000x600 pixels is too large (simulated))")
    assert captured.err == f"wingcrack: warning: {saved['warnings'][0]}\n"
    assert "fractures.png" not in captured.out and not (out / "fractures.png").exists()
    stored = read_result(out)
    assert len(stored.steps) == (1 if command == "sif" else 2) and stored.fields_of(len(stored.steps) - 1).x.size
    if command == "run":
        assert (out / "history.png").is_file()


@pytest.mark.parametrize("command", ["sif", "run"])
def test_ctrl_c_while_the_pictures_are_drawn(tmp_path, monkeypatch, command):
    """Promise 9 (SIGINT): a Ctrl-C while fractures.png is drawn left
    "finished" without fractures.png. The pictures come before the final
    status: the status is then "stopped: interrupted", with every step
    kept; `run --resume` (or `wingcrack plot`) draws them."""
    import os
    import signal

    from wingcrack import drawing
    from wingcrack.io import pictures

    real = pictures.fractures_of_result

    def interrupted(path, result):
        os.kill(os.getpid(), signal.SIGINT)
        for _ in range(10 ** 6):   # the handler runs here
            pass
        return real(path, result)

    monkeypatch.setattr(pictures, "fractures_of_result", interrupted)
    monkeypatch.setattr(drawing, "_running", lambda: False)   # drawn here, where the Ctrl-C is simulated
    out = tmp_path / "out"
    case = plate(2)
    with pytest.raises(KeyboardInterrupt):
        wingcrack.sif(case, out=out) if command == "sif" else wingcrack.run(case, out=out, plots=False)
    saved = json.loads((out / "summary.json").read_text())
    assert saved["status"] == "stopped: interrupted" and not (out / "fractures.png").exists()
    assert len(saved["steps"]) == (1 if command == "sif" else 2)
    monkeypatch.setattr(pictures, "fractures_of_result", real)
    if command == "run":
        r = wingcrack.run(case, out=out, plots=False, resume=True)
        assert r.status == "finished" and len(r.steps) == 2
        assert json.loads((out / "summary.json").read_text())["status"] == "finished"
    else:
        wingcrack.plot(out, history=False, animation=False)
    assert (out / "fractures.png").is_file()


def test_the_api_refuses_what_is_not_a_case_or_a_folder_name(tmp_path, monkeypatch):
    """A dict, a path or None instead of a Case, an empty folder name and a
    progress that is no callable are refused at once with a clear error,
    not an AttributeError from deep inside or a result in the current folder."""
    from wingcrack.errors import CaseError, FolderError

    case = plate(steps=1)
    for wrong in ({"material": {}}, "cases/griffith_inclined.toml", None):
        for f in (wingcrack.run, wingcrack.sif):
            with pytest.raises(CaseError, match="expected a wingcrack.Case.*Case.from_toml"):
                f(wrong)
    monkeypatch.chdir(tmp_path)
    for f in (wingcrack.run, wingcrack.sif, wingcrack.plot):
        with pytest.raises(FolderError, match="empty folder name"):
            f("  ") if f is wingcrack.plot else f(case, out="")
    with pytest.raises(TypeError, match="progress: expected"):
        wingcrack.run(case, progress=5)
    assert list(tmp_path.iterdir()) == []


def test_a_progress_callback_that_raises_keeps_the_committed_step(tmp_path):
    """The caller's progress(k, step) runs after step k is committed: its
    exception goes up unchanged (it was a "failed: step 1" ComputationError
    that dropped step 1 from summary.json while the checkpoint kept it), and
    the run resumes from there."""
    case = plate(steps=3)

    def progress(k, step):
        if k == 1:
            raise ValueError("the caller's bug")

    with pytest.raises(ValueError, match="the caller's bug"):
        wingcrack.run(case, out=tmp_path / "o", progress=progress, plots=False)
    saved = json.loads((tmp_path / "o" / "summary.json").read_text())
    assert saved["status"] == "running" and [s["step"] for s in saved["steps"]] == [0, 1]
    r = wingcrack.run(case, out=tmp_path / "o", plots=False, resume=True)
    assert r.status == "finished" and [s["step"] for s in r.steps] == [0, 1, 2]


def test_the_api_locks_its_folder_as_the_command_line_does(tmp_path):
    """wingcrack.run / sif from Python hold the folder's lock (as the
    commands do): while another process holds it, each is refused at once
    with FolderError "is in use", and nothing is written there."""
    import subprocess
    import sys

    from wingcrack.errors import FolderError

    out = tmp_path / "o"
    out.mkdir()
    holder = subprocess.Popen([sys.executable, "-c", "import fcntl, os, sys, time; fd = os.open(sys.argv[1], "
                               "os.O_RDONLY); fcntl.flock(fd, fcntl.LOCK_EX); print('held', flush=True); "
                               "time.sleep(60)", str(out)], stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline().strip() == "held"
        case = plate(steps=1)
        for call in (lambda: wingcrack.run(case, out=out), lambda: wingcrack.sif(case, out=out)):
            with pytest.raises(FolderError, match=f"in use by another wingcrack run \\(pid {holder.pid}\\)"):
                call()
        assert list(out.iterdir()) == []
    finally:
        holder.kill()
        holder.wait()
    assert wingcrack.sif(plate(steps=1), out=out).summary["status"] == "finished"
