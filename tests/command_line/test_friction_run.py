"""Issue 14 on whole runs: the friction law holds at every step of a Coulomb
run (verification 3), the slip history survives the remesh (verification
5), and a killed Coulomb run resumes on the uninterrupted run's geometry
and slip (verification 6; two processes: tests/mpi/test_mpi.py).

The case is cases/brazilian_disc_45_friction.toml (mu = 0.5 on the crack
and its wings), cut to a few steps."""
import json
import signal
import subprocess
import sys
import time
from pathlib import Path

import meshio
import numpy as np
import pytest

import wingcrack
from wingcrack.case import Case
from wingcrack.contact.friction import SLIP
from wingcrack.contact.slip_history import pair_arc_lengths
from wingcrack.propagation import checkpoint
from wingcrack.propagation.fracture_set import FractureSet
from wingcrack.step import Carried, Timer, discretise

ROOT = Path(__file__).resolve().parents[2]
WINGCRACK = Path(sys.executable).with_name("wingcrack")
CASE = ROOT / "cases" / "brazilian_disc_45_friction.toml"
R = 0.042
#: every friction residual is relative (contact.friction.friction_residuals):
#: each state set is one dense solve, so round-off (~1e-13 measured) is all
#: that is left; 1e-8 is the issue's bound
LAW_TOL = 1e-8


def with_steps(steps, path):
    text = CASE.read_text()
    path.write_text("\n".join(f"steps = {steps}" if line.startswith("steps =") else line
                              for line in text.splitlines()) + "\n")
    return path


@pytest.fixture(scope="module")
def run6(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("coulomb")
    case = Case.from_toml(with_steps(6, tmp / "case.toml"))
    return case, wingcrack.run(case, out=tmp / "out", plots=False), tmp / "out"


def test_every_step_of_a_coulomb_run_holds_the_friction_law(run6):
    case, result, _ = run6
    assert result.status == "finished" and len(result.steps) == 6
    for st in result.steps:
        c = st["contact"]
        assert c["closed"] == c["stick"] + c["slip"] > 0
        assert max(c["friction"].values()) <= LAW_TOL, (st["step"], c["friction"])
        assert max(c["kkt"].values()) <= LAW_TOL, (st["step"], c["kkt"])
        # the critical-load search from the last converged state (the target: <= 8 solves)
        assert st["solves"] <= 8
    # step 0: the closed crack slips, KI = 0 and the wings kink at -70.5 deg (MTS with KI = 0)
    s0 = result.steps[0]
    assert s0["contact"]["slip"] == s0["contact"]["closed"]
    for t in s0["tips"]:
        assert abs(t["KI"]) <= 1e-8 * abs(t["KII"])
        assert np.degrees(t["theta"]) == pytest.approx(-70.5288, abs=1e-3)


def _face_slip(out, k):
    faces = meshio.read(out / f"faces_{k:04d}.vtu")
    return faces.points[:, :2], faces.point_data["slip"], faces.point_data["state"]


def test_the_slip_history_carries_the_converged_slip_across_the_remesh(tmp_path):
    """After step 0 the checkpoint holds the slip history recorded on step
    0's mesh. On that mesh again (gmsh is deterministic) it gives step 0's
    converged slip back to round-off; on the next mesh (the grown
    fractures) the pre-existing part keeps it at unchanged arc lengths and
    the new wing segments start from zero."""
    case = Case.from_toml(with_steps(1, tmp_path / "case.toml"))
    out = tmp_path / "out"
    result = wingcrack.run(case, out=out, plots=False)
    assert result.status.startswith("stopped") or result.status == "finished"
    ck = checkpoint.load(out, case)
    history = ck["history"]
    assert history is not None and not history.is_zero()
    x0, slip0, state0 = _face_slip(out, 0)
    assert np.all(state0[np.abs(slip0) > 0] == SLIP)
    scale = np.max(np.abs(slip0))

    first = FractureSet.from_case(case)
    d0 = discretise(case, first.fractures, Timer())
    pairs = np.asarray(d0.cm.pairs).reshape(-1, 2)
    plus = np.asarray(d0.cm.x)[pairs[:, 0]]
    lookup = {tuple(np.round(p, 12)): s for p, s in zip(x0, slip0)}
    again = history.at(d0.cm, first.fractures)
    expect = np.array([lookup[tuple(np.round(p, 12))] for p in plus])
    np.testing.assert_allclose(again, expect, atol=1e-10 * scale)
    arcs0 = pair_arc_lengths(d0.cm, first.fractures)
    d0.solver.release()

    grown = ck["fset"]
    d1 = discretise(case, grown.fractures, Timer(), carried=Carried(sizes=ck["sizes"], history=history))
    ref = d1.contact.reference
    rows = d1.contact.rows
    arcs1 = pair_arc_lengths(d1.cm, grown.fractures)[rows.pair[rows.coulomb]]
    ref = ref[rows.coulomb]
    pre_length = float(np.linalg.norm(np.diff(grown.fractures[0].pre_points, axis=0), axis=1).sum())
    # at the arc length of step 0's pair in the middle: the same slip (1e-10 of it)
    same = [(i, np.flatnonzero(np.abs(arcs1 - a) <= 1e-12 * R)) for i, a in enumerate(arcs0)]
    hits = [(i, j[0]) for i, j in same if len(j)]
    assert hits   # measured: 1; the mesher moves the other nodes once the tips moved
    for i, j in hits:
        assert ref[j] == pytest.approx(again[i], abs=1e-10 * scale)
    # everywhere else on the pre-existing part: step 0's P2 slip at the new arc lengths, by Lagrange
    # interpolation in arc length through the three nodes of step 0's face edges (read from its face
    # file; exact for the straight edges with their mid node in the middle, i.e. all but the two tip edges)
    faces = meshio.read(out / "faces_0000.vtu")
    p0, d = grown.fractures[0].pre_points[0], np.diff(grown.fractures[0].pre_points, axis=0)[0]
    d = d / np.linalg.norm(d)
    node_arc = (faces.points[:, :2] - p0) @ d
    checked = 0
    for a_, b_, m_ in faces.cells_dict["line3"]:
        xs = node_arc[[a_, b_, m_]]
        if abs((xs[2] - xs[0]) / (xs[1] - xs[0]) - 0.5) > 1e-9:
            continue   # a quarter-point edge at an old tip
        inside = (arcs1 > min(xs[0], xs[1])) & (arcs1 < max(xs[0], xs[1]))
        for j in np.flatnonzero(inside):
            lag = [np.prod([(arcs1[j] - xs[q]) / (xs[p] - xs[q]) for q in range(3) if q != p]) for p in range(3)]
            assert ref[j] == pytest.approx(float(np.dot(lag, faces.point_data["slip"][[a_, b_, m_]])),
                                           abs=1e-10 * scale)
            checked += 1
    assert checked >= 20, checked
    # the new wings (arc beyond the pre-existing part) start from zero slip
    wing = (arcs1 < -1e-12 * R) | (arcs1 > pre_length + 1e-12 * R)
    assert wing.any() and np.all(ref[wing] == 0.0)
    d1.solver.release()


def test_a_killed_coulomb_run_resumes_to_the_same_geometry_and_slip(tmp_path, run6):
    _, reference, ref_out = run6
    case = with_steps(6, tmp_path / "case.toml")
    out = tmp_path / "out"
    proc = subprocess.Popen([str(WINGCRACK), "run", str(case), "-o", str(out), "--quiet", "--no-plots"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    t0 = time.perf_counter()
    while not (out / "summary.json").exists() or len(json.loads((out / "summary.json").read_text())["steps"]) < 2:
        assert proc.poll() is None, "the run ended before it could be killed"
        assert time.perf_counter() - t0 < 120
        time.sleep(0.05)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    resumed = subprocess.run([str(WINGCRACK), "run", str(case), "-o", str(out), "--quiet", "--no-plots", "--resume"],
                             capture_output=True, text=True)
    assert resumed.returncode == 0, resumed.stderr
    s = json.loads((out / "summary.json").read_text())
    assert s["status"] == reference.status and len(s["steps"]) == len(reference.steps)
    # gmsh and MUMPS are deterministic and the resumed run starts from the saved slip history:
    # the paths and the last step's slip agree to round-off
    for a, b in zip(reference.summary["fractures"], s["fractures"]):
        assert np.abs(np.array(a["points"]) - np.array(b["points"])).max() <= 1e-9 * R
    k = len(s["steps"]) - 1
    xa, sa, ta = _face_slip(ref_out, k)
    xb, sb, tb = _face_slip(out, k)
    assert np.abs(xa - xb).max() <= 1e-9 * R
    np.testing.assert_allclose(sb, sa, atol=1e-9 * np.max(np.abs(sa)))
    np.testing.assert_array_equal(ta, tb)
