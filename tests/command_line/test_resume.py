"""Issue 7.5: checkpoint and resume, Ctrl-C.

Reference: the uninterrupted run of the same case. A run killed with SIGKILL
mid-run and resumed with --resume must end with the same fracture geometry
(tip positions within 1e-9 of the domain size: the resumed run meshes from
the same saved size field, and gmsh and MUMPS are deterministic, so the
paths agree to round-off), and summary.json must parse at any moment of the
kill (atomic writes). SIGINT stops at once with "stopped: interrupted",
exit 130, every finished step kept.
"""
import json
import random
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from builders import square_plate_with_cracks
from networks import to_toml

WINGCRACK = Path(sys.executable).with_name("wingcrack")
L = 4.0
STEPS = 6


def write_case(path, steps=STEPS, title="plate", E=None):
    d = square_plate_with_cracks(L, [[[-1.0, -0.3], [-0.4, 0.1]], [[0.3, 0.5], [1.0, 0.4]]], (0.0, 0.0, 0.0),
                                 size=0.5, tip_size=0.05)
    d["title"] = title
    if E is not None:
        d["material"]["E"] = E
    d["bc"] += [{"on": "top", "traction": [0.0, 1e5]}, {"on": "bottom", "traction": [0.0, -1e5]}]
    d["propagation"] = {"steps": steps, "length": 0.1}
    path.write_text(to_toml(d))
    return path


def start(case, out, *extra):
    return subprocess.Popen([str(WINGCRACK), "run", str(case), "-o", str(out), "--quiet", "--no-plots", *extra],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def finished_steps(out) -> int:
    """Steps recorded in summary.json now; it must always parse (atomic)."""
    p = out / "summary.json"
    if not p.exists():
        return 0
    return len(json.loads(p.read_text())["steps"])


def wait_for_steps(proc, out, n, limit=120.0):
    t0 = time.perf_counter()
    while finished_steps(out) < n:
        assert proc.poll() is None, "the run ended before it could be interrupted"
        assert time.perf_counter() - t0 < limit
        time.sleep(0.05)


def tips_of(out):
    s = json.loads((out / "summary.json").read_text())
    return s, np.array([[t["x"], t["y"]] for t in s["steps"][-1]["tips"]]), \
        [np.asarray(f["points"]) for f in s["fractures"]]


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("ref")
    case = write_case(tmp / "case.toml")
    proc = subprocess.run([str(WINGCRACK), "run", str(case), "-o", str(tmp / "out"), "--quiet", "--no-plots"],
                          capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    return tips_of(tmp / "out")


def same_geometry(a, b):
    sa, ta, fa = a
    sb, tb, fb = b
    assert sb["status"] == sa["status"] == "finished"
    assert len(sb["steps"]) == len(sa["steps"]) == STEPS
    assert np.abs(ta - tb).max() <= 1e-9 * L
    assert len(fa) == len(fb) and all(np.abs(p - q).max() <= 1e-9 * L for p, q in zip(fa, fb))


@pytest.mark.parametrize("seed", [1, 2])
def test_killed_run_resumes_to_the_same_geometry(tmp_path, reference, seed):
    case = write_case(tmp_path / "case.toml")
    out = tmp_path / "out"
    proc = start(case, out)
    wait_for_steps(proc, out, 1)
    # a random moment of the next two steps, in units of the reference's step
    # time: a fixed delay outlasted all the steps left on an idle machine
    step = float(np.median([st["seconds"]["total"] for st in reference[0]["steps"]]))
    time.sleep(random.Random(seed).uniform(0.0, 2.0) * step)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    kept = finished_steps(out)
    assert 1 <= kept < STEPS
    resumed = subprocess.run([str(WINGCRACK), "run", str(case), "-o", str(out), "--quiet", "--no-plots", "--resume"],
                             capture_output=True, text=True)
    assert resumed.returncode == 0, resumed.stderr
    same_geometry(reference, tips_of(out))


@pytest.mark.parametrize("delay", [0.0, 0.7])
def test_ctrl_c_stops_cleanly_and_resumes(tmp_path, delay):
    """SIGINT in the middle of a long run: exit 130, "stopped: interrupted",
    the finished steps kept; --resume (here asked for one step more, which
    a case may change: propagation.steps is not part of its fingerprint)
    continues from them. delay 0 signals right after summary.json shows a
    new step, while the step is being committed (CI once caught the
    checkpoint's zip half-written there); 0.7 s lands inside the next step."""
    stop_then_resume(tmp_path, signal.SIGINT, delay, 130, "interrupted", "stopped: interrupted")


def stop_then_resume(tmp_path, sig, delay, code, word, status):
    """Signal a 60-step run `delay` s after its second step is in
    summary.json; check the exit code, the one line on stderr, the status
    and the kept steps; resume it one step further and check that the kept
    steps' physics (everything but timings) is what the resumed run has."""
    case = write_case(tmp_path / "case.toml", steps=60)
    out = tmp_path / "out"
    proc = start(case, out)
    wait_for_steps(proc, out, 2)
    time.sleep(delay)
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == code, err
    s = json.loads((out / "summary.json").read_text())
    kept = len(s["steps"])
    assert s["status"] == status and 2 <= kept < 60
    # a clean stop, not an error: the one line says what is kept and how to go on
    assert err == f"wingcrack: stopped ({word}): {kept} steps kept; --resume goes on\n"
    write_case(case, steps=kept + 1)
    resumed = subprocess.run([str(WINGCRACK), "run", str(case), "-o", str(out), "--quiet", "--no-plots", "--resume"],
                             capture_output=True, text=True)
    assert resumed.returncode == 0, resumed.stderr
    r = json.loads((out / "summary.json").read_text())
    assert r["status"] == "finished" and len(r["steps"]) == kept + 1

    # the same physics (timings differ; a step whose checkpoint the interrupt
    # beat is computed again, to the same numbers)
    def physics(steps):
        return [{k: v for k, v in st.items() if k != "seconds"} for st in steps]
    assert physics(r["steps"][:kept]) == physics(s["steps"])


def test_a_killed_pumped_run_resumes_to_the_uninterrupted_runs_times_pressures_and_geometry(tmp_path):
    """A run driven by a pump (tests/verification/test_injection_breakdown.py's
    joins: its network takes in a dry and a wet fracture at step 2), killed
    with SIGKILL after its first step and resumed: the checkpoint's pump
    (the network, the fluid it held, the last time and pressure) carries it
    on to the uninterrupted run's steps, to the digits (the same meshes and
    solves: the run is deterministic), and the PVD's time axis is the steps'
    times."""
    from test_injection_breakdown import joining_dict
    from wingcrack.io.pvd import read_pvd

    case = tmp_path / "case.toml"
    case.write_text(to_toml(joining_dict(steps=4)))
    ref = subprocess.run([str(WINGCRACK), "run", str(case), "-o", str(tmp_path / "ref"), "--quiet", "--no-plots"],
                         capture_output=True, text=True)
    assert ref.returncode == 0, ref.stderr
    out = tmp_path / "out"
    proc = start(case, out)
    wait_for_steps(proc, out, 1)
    t0 = time.perf_counter()
    while not (out / "checkpoint.npz").exists():   # written just after summary.json
        assert time.perf_counter() - t0 < 60
        time.sleep(0.01)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    assert 1 <= finished_steps(out) < 4
    resumed = subprocess.run([str(WINGCRACK), "run", str(case), "-o", str(out), "--quiet", "--no-plots", "--resume"],
                             capture_output=True, text=True)
    assert resumed.returncode == 0, resumed.stderr
    a, b = (json.loads((d / "summary.json").read_text()) for d in (tmp_path / "ref", out))
    assert a["status"] == b["status"] and len(a["steps"]) == len(b["steps"]) == 4
    for sa, sb in zip(a["steps"], b["steps"]):
        assert sa["time"] == sb["time"] and sa["injection"] == sb["injection"] and sa["networks"] == sb["networks"]
    assert a["fractures"] == b["fractures"]
    assert [t for t, _ in read_pvd(out / "fields.pvd")] == [s["time"] for s in a["steps"]]


def test_resume_refuses_what_it_cannot_continue(tmp_path):
    case = write_case(tmp_path / "case.toml", steps=2)
    nothing = subprocess.run([str(WINGCRACK), "run", str(case), "-o", str(tmp_path / "none"), "--resume"],
                             capture_output=True, text=True)
    assert nothing.returncode == 2 and "nothing to resume" in nothing.stderr
    assert subprocess.run([str(WINGCRACK), "run", str(case), "-o", str(tmp_path / "out"), "--quiet", "--no-plots"],
                          capture_output=True).returncode == 0
    from wingcrack.case import Case

    E = Case.from_toml(case).material.E
    other = write_case(tmp_path / "other.toml", steps=3, E=2 * E)
    wrong = subprocess.run([str(WINGCRACK), "run", str(other), "-o", str(tmp_path / "out"), "--resume"],
                           capture_output=True, text=True)
    # the refusal names the key that differs, with both values
    assert wrong.returncode == 2 and wrong.stderr == (
        f"wingcrack: error: {tmp_path / 'out'}: {tmp_path / 'out' / 'checkpoint.npz'} was written for another "
        f"case: material.E is {2 * E!r} here, {E!r} there; resume with the case it was written for, or start the "
        "run again without --resume (with --force)\n"), wrong.stderr
    # asking for fewer steps than are done: said, not "finished" with more steps than asked
    fewer = subprocess.run([str(WINGCRACK), "run", str(write_case(tmp_path / "fewer.toml", steps=1)), "-o",
                            str(tmp_path / "out"), "--resume"], capture_output=True, text=True)
    assert fewer.returncode == 2 and fewer.stderr == (
        f"wingcrack: error: {tmp_path / 'out'}: holds 2 finished steps, more than the case's propagation.steps = "
        "1: nothing to resume; ask for more steps to go on\n"), fewer.stderr
    # a new title (and more steps) does not make another case: the run goes on, under the new title
    retitled = write_case(tmp_path / "retitled.toml", steps=3, title="another plate")
    more = subprocess.run([str(WINGCRACK), "run", str(retitled), "-o", str(tmp_path / "out"), "--resume", "--quiet",
                           "--no-plots"], capture_output=True, text=True)
    assert more.returncode == 0, more.stderr
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert s["title"] == "another plate" and len(s["steps"]) == 3


def test_resume_with_a_finished_step_file_missing_exits_2(tmp_path):
    """A folder whose checkpoint is good but a finished step's file was
    deleted: the resumed run went on, wrote "finished" and a warning that
    "the data are complete" over a result with a hole in it."""
    case = write_case(tmp_path / "case.toml", steps=2)
    out = tmp_path / "out"
    assert subprocess.run([str(WINGCRACK), "run", str(case), "-o", str(out), "--quiet", "--no-plots"],
                          capture_output=True).returncode == 0
    (out / "step_0001.vtu").unlink()
    summary = (out / "summary.json").read_bytes()
    more = write_case(tmp_path / "more.toml", steps=3)
    res = subprocess.run([str(WINGCRACK), "run", str(more), "-o", str(out), "--resume", "--quiet"],
                         capture_output=True, text=True)
    assert res.returncode == 2, res.stderr
    assert res.stderr == (f"wingcrack: error: {out}: step_0001.vtu of finished step 1 is missing: the result "
                          "cannot be completed; start the run again without --resume (with --force)\n")
    assert (out / "summary.json").read_bytes() == summary and not (out / "step_0002.vtu").exists()


def _truncated(path):
    path.write_bytes(path.read_bytes()[: path.stat().st_size // 2])


def _empty(path):
    path.write_bytes(b"")


def _garbage(path):
    path.write_bytes(bytes(range(256)) * 8)


def _no_fractures_key(path):
    data = dict(np.load(path))
    meta = json.loads(str(data["meta"]))
    del meta["fractures"]
    data["meta"] = np.array(json.dumps(meta))
    with open(path, "wb") as fh:
        np.savez(fh, **data)


def _no_points(path):
    data = {k: v for k, v in np.load(path).items() if not k.startswith("points_")}
    with open(path, "wb") as fh:
        np.savez(fh, **data)


def _meta_not_json(path):
    data = dict(np.load(path))
    data["meta"] = np.array("{not json")
    with open(path, "wb") as fh:
        np.savez(fh, **data)


def _bad_points(path):
    data = dict(np.load(path))
    data["points_0"] = np.zeros(3)
    with open(path, "wb") as fh:
        np.savez(fh, **data)


def _edit_meta(path, edit):
    data = dict(np.load(path))
    meta = json.loads(str(data["meta"]))
    edit(meta)
    data["meta"] = np.array(json.dumps(meta))
    with open(path, "wb") as fh:
        np.savez(fh, **data)


def _step_behind_records(path):
    """Resumed, it repeated steps: 0 1 2 1 2 ... in summary.json."""
    _edit_meta(path, lambda m: m.update(step=m["step"] - 1))


def _records_cut(path):
    """Resumed, it skipped steps: 0 3 4 ..."""
    _edit_meta(path, lambda m: m.update(steps=m["steps"][:-1]))


def _load_factor_nan(path):
    _edit_meta(path, lambda m: m.update(load_factor=float("nan")))


def _load_factor_negative(path):
    _edit_meta(path, lambda m: m.update(load_factor=-1.0))


def _friction_negative(path):
    _edit_meta(path, lambda m: m["fractures"][0].update(friction=-0.6))


def _cohesion_nan(path):
    _edit_meta(path, lambda m: m["fractures"][1].update(cohesion=float("nan")))


def _friction_missing(path):
    _edit_meta(path, lambda m: m["fractures"][0].pop("friction"))


def _pressure_negative(path):
    _edit_meta(path, lambda m: m["fractures"][0].update(pressure=-1e5))


def _pressure_inf(path):
    _edit_meta(path, lambda m: m["fractures"][1].update(pressure=float("inf")))


def _pressure_string(path):
    _edit_meta(path, lambda m: m["fractures"][1].update(pressure="1e6"))


def _joined_to_missing(path):
    _edit_meta(path, lambda m: m["fractures"][0].pop("joined_to"))


def _joined_to_no_such_fracture(path):
    _edit_meta(path, lambda m: m["fractures"][0].update(joined_to=[None, 2]))   # two fractures: 0 and 1


def _joined_to_not_a_pair(path):
    _edit_meta(path, lambda m: m["fractures"][1].update(joined_to=[0]))


def _joined_to_float(path):
    _edit_meta(path, lambda m: m["fractures"][1].update(joined_to=[0.0, None]))


@pytest.mark.parametrize("damage", [_truncated, _empty, _garbage, _no_fractures_key, _no_points, _meta_not_json,
                                    _bad_points, _step_behind_records, _records_cut, _load_factor_nan,
                                    _load_factor_negative, _friction_negative, _cohesion_nan, _friction_missing,
                                    _pressure_negative, _pressure_inf, _pressure_string, _joined_to_missing,
                                    _joined_to_no_such_fracture, _joined_to_not_a_pair, _joined_to_float],
                         ids=lambda f: f.__name__.strip("_"))
def test_resume_from_a_damaged_checkpoint_exits_2_naming_it(tmp_path, capsys, damage):
    """Issue 12.8: a checkpoint.npz that cannot be read (cut short, empty,
    not a zip, keys or arrays missing, a polyline of the wrong shape) is a
    bad input: exit 2 and one line naming the file, never "unexpected
    BadZipFile"; nor one that reads but does not hold steps 0 ... step and
    that step's load factor (the resumed run repeated or skipped steps, or
    started from NaN). Reference: the same file undamaged loads."""
    from wingcrack import cli
    from wingcrack.case import Case
    from wingcrack.propagation import checkpoint
    from wingcrack.propagation.fracture_set import FractureSet

    path = write_case(tmp_path / "case.toml", steps=3)
    case = Case.from_toml(path)
    out = tmp_path / "out"
    out.mkdir()
    checkpoint.save(out, case, 1, FractureSet.from_case(case), 1.0,
                    [{"step": 0, "load_factor": 0.5}, {"step": 1, "load_factor": 1.0}], None)
    assert checkpoint.load(out, case)["step"] == 1
    damage(out / checkpoint.NAME)
    assert cli.main(["run", str(path), "-o", str(out), "--resume", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and "unexpected" not in err, err
    assert err.startswith(f"wingcrack: error: {out}: {out / checkpoint.NAME} cannot be read as a checkpoint ("), err


def _coulomb_case(tmp_path):
    """write_case's plate with Coulomb faces on its first crack."""
    from wingcrack.case import Case

    path = write_case(tmp_path / "case.toml", steps=3)
    path.write_text(path.read_text().replace('faces = "open"', 'faces = "coulomb"\nfriction = 0.6\ncohesion = 2e5', 1))
    case = Case.from_toml(path)
    assert [f.faces for f in case.fractures] == ["coulomb", "open"]
    return path, case


def test_a_checkpoint_keeps_friction_and_cohesion(tmp_path):
    """Issue 14: a resumed run goes on with the case fracture's law (the
    records' friction and cohesion, which its wings take), exactly."""
    from wingcrack.propagation import checkpoint
    from wingcrack.propagation.fracture_set import FractureSet

    _, case = _coulomb_case(tmp_path)
    fset = FractureSet.from_case(case)
    fset.fractures[0].extend(1, fset.fractures[0].points[-1] + [0.05, 0.1])   # a wing: the law is per fracture
    checkpoint.save(tmp_path, case, 0, fset, 0.5, [{"step": 0, "load_factor": 0.5}], None)
    got = checkpoint.load(tmp_path, case)["fset"].fractures
    assert [(f.law.faces, f.law.friction, f.law.cohesion, f.law.wings().faces) for f in got] == \
        [("coulomb", 0.6, 2e5, "coulomb"), ("open", 0.0, 0.0, "open")]
    assert all(type(f.law.friction) is float and type(f.law.cohesion) is float for f in got)
    assert np.array_equal(got[0].points, fset.fractures[0].points) and got[0].pre == (0, 1)


def test_the_face_law_keeps_the_format_4_fracture_keys(tmp_path):
    """The checkpoint writes a fracture's face law by its field names beside
    the other keys: the fracture keys of format 4 (format 5 added the pump's
    state, not a fracture key), so a folder written before the law was one
    record reads as it did. A field added to the law changes them, and must
    change checkpoint.VERSION with them."""
    from wingcrack.propagation import checkpoint
    from wingcrack.propagation.fracture_set import FractureSet

    _, case = _coulomb_case(tmp_path)
    checkpoint.save(tmp_path, case, 0, FractureSet.from_case(case), 0.5, [{"step": 0, "load_factor": 0.5}], None)
    with np.load(tmp_path / checkpoint.NAME) as data:
        meta = json.loads(str(data["meta"]))
    assert checkpoint.VERSION == meta["version"] == 5
    assert [sorted(f) for f in meta["fractures"]] == [sorted(["pre", "ends", "faces", "gap", "slip", "slip_profile",
                                                             "grow", "friction", "cohesion", "pressure",
                                                             "joined_to"])] * 2
    old = [dict(sorted(f.items())) for f in meta["fractures"]]   # another order of the same keys reads the same
    _edit_meta(tmp_path / checkpoint.NAME, lambda m: m.update(fractures=old))
    got = checkpoint.load(tmp_path, case)["fset"].fractures
    assert [f.law for f in got] == [f.law for f in case.fractures]


def test_a_checkpoint_keeps_pressure_and_joined_to(tmp_path):
    """Issue 15: a resumed run goes on with the pressures after connection
    (not the case's) and with what each joined end met, so that later
    connections still flood through earlier joins."""
    from wingcrack.case import Case
    from wingcrack.propagation import checkpoint
    from wingcrack.propagation.fracture_set import FractureSet

    path = write_case(tmp_path / "case.toml", steps=3)
    path.write_text(path.read_text().replace('faces = "open"', 'faces = "open"\npressure = 3e5', 1))
    case = Case.from_toml(path)
    fset = FractureSet.from_case(case)
    assert [f.law.pressure for f in fset.fractures] == [3e5, 0.0]
    fset.fractures[0].ends[1], fset.fractures[0].joined_to[1] = "joined", 1   # a wing of 0 ended on 1 as a T
    assert fset.connect_pressures()
    checkpoint.save(tmp_path, case, 0, fset, 0.5, [{"step": 0, "load_factor": 0.5}], None)
    got = checkpoint.load(tmp_path, case)["fset"].fractures
    assert [(f.law.pressure, f.joined_to, f.ends) for f in got] == \
        [(3e5, [None, 1], ["tip", "joined"]), (3e5, [None, None], ["tip", "tip"])]
    assert all(type(f.law.pressure) is float for f in got)


def test_a_format_2_checkpoint_is_refused_naming_both(tmp_path, capsys):
    """A format-2 checkpoint (issue 14, before fluid pressure) holds no
    pressure and no joined_to: refused in one line naming its format."""
    from wingcrack import cli
    from wingcrack.case import Case
    from wingcrack.propagation import checkpoint
    from wingcrack.propagation.fracture_set import FractureSet

    path = write_case(tmp_path / "case.toml", steps=3)
    case = Case.from_toml(path)
    out = tmp_path / "out"
    out.mkdir()
    checkpoint.save(out, case, 0, FractureSet.from_case(case), 1.0, [{"step": 0, "load_factor": 1.0}], None)

    def format_2(meta):
        meta["version"] = 2
        for f in meta["fractures"]:
            del f["pressure"], f["joined_to"]

    _edit_meta(out / checkpoint.NAME, format_2)
    assert cli.main(["run", str(path), "-o", str(out), "--resume", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err == (f"wingcrack: error: {out}: {out / checkpoint.NAME} was written by another wingcrack version "
                   f"(checkpoint format 2, this one reads {checkpoint.VERSION}); start the run again without "
                   "--resume (with --force)\n"), err


def test_a_checkpoint_of_another_format_is_refused_naming_both(tmp_path, capsys):
    """A format-1 checkpoint (before friction) holds no friction and cohesion
    and, once slip history is recorded, no slip either: refused with exit 2
    and one line that says which format it is, not "damaged"."""
    from wingcrack import cli
    from wingcrack.case import Case
    from wingcrack.propagation import checkpoint
    from wingcrack.propagation.fracture_set import FractureSet

    path = write_case(tmp_path / "case.toml", steps=3)
    case = Case.from_toml(path)
    out = tmp_path / "out"
    out.mkdir()
    checkpoint.save(out, case, 0, FractureSet.from_case(case), 1.0, [{"step": 0, "load_factor": 1.0}], None)

    def format_1(meta):
        meta["version"] = 1
        for f in meta["fractures"]:
            del f["friction"], f["cohesion"]

    _edit_meta(out / checkpoint.NAME, format_1)
    assert cli.main(["run", str(path), "-o", str(out), "--resume", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err == (f"wingcrack: error: {out}: {out / checkpoint.NAME} was written by another wingcrack version "
                   f"(checkpoint format 1, this one reads {checkpoint.VERSION}); start the run again without "
                   "--resume (with --force)\n"), err


@pytest.mark.parametrize("kind", ["folder", "fifo"])
def test_resume_from_a_checkpoint_that_is_not_a_file_says_so(tmp_path, capsys, kind):
    """A checkpoint.npz that is a folder or a FIFO was reported as "does not
    exist: nothing to resume"; it exists, and is not a regular file."""
    import os

    from wingcrack import cli
    from wingcrack.propagation import checkpoint

    path = write_case(tmp_path / "case.toml", steps=3)
    out = tmp_path / "out"
    out.mkdir()
    (out / checkpoint.NAME).mkdir() if kind == "folder" else os.mkfifo(out / checkpoint.NAME)
    assert cli.main(["run", str(path), "-o", str(out), "--resume", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err == f"wingcrack: error: {out}: {out / checkpoint.NAME} is not a regular file: it cannot be a " \
                  "checkpoint; start the run again without --resume (with --force)\n", err


def test_sigterm_stops_like_ctrl_c_and_resumes(tmp_path):
    """Issue 12.9: SIGTERM (kill, a batch system's time limit) in the middle
    of a run: exit 143 (128 + 15, what a shell reports for a process the
    signal ended), status "stopped: terminated" (not "running"), the finished
    steps kept, and --resume goes on from them to the same numbers."""
    stop_then_resume(tmp_path, signal.SIGTERM, 0.3, 143, "terminated", "stopped: terminated")


def test_resume_of_a_run_that_stopped_at_step_0_says_why(tmp_path):
    """A run stopped in its first step (here: the fixed load is below KIc)
    keeps step 0 without a checkpoint; --resume says so instead of asking
    whether the run was started with this -o."""
    import pytest

    import wingcrack
    from builders import square_plate_with_cracks
    from wingcrack.errors import FolderError

    d = square_plate_with_cracks(4.0, [[[-0.5, 0.0], [0.5, 0.0]]], (0.0, 0.0, 0.0), size=0.5, tip_size=0.05)
    d["bc"] += [{"on": "top", "traction": [0.0, 1e3]}, {"on": "bottom", "traction": [0.0, -1e3]}]
    d["propagation"] = {"steps": 3, "length": 0.1, "load": "fixed"}
    case = wingcrack.Case.from_dict(d)
    r = wingcrack.run(case, out=tmp_path / "o", plots=False)
    assert r.status == "stopped: no tip reaches KIc under the fixed load"
    with pytest.raises(FolderError, match="result \\(\"stopped: no tip reaches KIc under the fixed load\"\\) "
                                          "without checkpoint.npz: no step of a run was committed"):
        wingcrack.run(case, out=tmp_path / "o", resume=True)
    wingcrack.sif(case, out=tmp_path / "s")
    with pytest.raises(FolderError, match="a `sif` result"):
        wingcrack.run(case, out=tmp_path / "s", resume=True)
