"""Issue 5: the propagation loop (paper Fig. 8)."""
import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from builders import square_plate_with_cracks
from wingcrack.api import run, sif
from wingcrack.case import Case
from wingcrack.errors import ComputationError

A, L, SIGMA = 1.0, 100.0, 1.0e5


def tension_plate(steps=5, length=0.1, cracks=None, tip_size=0.05, **prop):
    d = square_plate_with_cracks(L, cracks or [[[-A, 0.0], [A, 0.0]]], (0.0, 0.0, 0.0),
                                 size=10 * A, tip_size=tip_size)
    d["bc"] += [{"on": "top", "traction": [0.0, SIGMA]}, {"on": "bottom", "traction": [0.0, -SIGMA]}]
    d["propagation"] = {"steps": steps, "length": length, **prop}
    return Case.from_dict(d)


def test_mode_one_growth_is_straight_and_follows_griffith(tmp_path):
    """A central crack under tension grows straight (|kink| < 0.1 deg every
    step) and KI = sigma sqrt(pi a(t)) within 1% (the plate is 100a wide:
    finite-width effect < 0.1% up to a = 1.5; SIFs are ~0.1% accurate)."""
    r = run(tension_plate(), out=tmp_path)
    assert r.status == "finished" and len(r.steps) == 5
    lam = r.steps[0]["load_factor"]
    for k, step in enumerate(r.steps):
        assert step["load_factor"] == lam   # unstable growth: no load increase needed
        a = A + 0.1 * k
        for t in step["tips"]:
            assert abs(np.degrees(t["theta"])) < 0.1
            assert abs(t["KI"] / (lam * SIGMA * np.sqrt(np.pi * a)) - 1) < 1e-2
            # both tips grow; the law shares Lmax by (G/max G)^0.35, and the two
            # tips differ by ~1e-5 in G on the unsymmetric mesh
            assert t["state"] == "growing" and abs(t["advance"] - 0.1) < 1e-5
    pts = r.fractures.fractures[0].points
    assert np.abs(pts[:, 1]).max() < 1e-3 * 0.1
    saved = json.loads((tmp_path / "summary.json").read_text())
    assert saved["status"] == "finished" and len(saved["steps"]) == 5
    origins = sorted(f["origin"] for f in saved["fractures"])
    assert origins == ["pre-existing", "wing", "wing"]


def test_a_wing_joins_another_fracture_as_a_t(tmp_path):
    """The right tip of a horizontal crack grows straight into a vertical
    fracture 0.35 away: it stops on it ('joined'), never crosses it, and the
    next mesh is conforming with contact pairs on the new faces."""
    cracks = [[[-A, 0.0], [A, 0.0]], [[A + 0.35, -0.6], [A + 0.35, 0.6]]]
    r = run(tension_plate(steps=4, cracks=cracks), out=tmp_path)
    states = [t["state"] for s in r.steps for t in s["tips"] if t["fracture"] == 0 and t["end"] == 1]
    assert "joined" in states
    f0 = r.fractures.fractures[0]
    assert f0.ends[1] == "joined"
    assert abs(f0.points[-1][0] - (A + 0.35)) < 1e-12
    # the join is recorded with the fracture it met (issue 15: what connects pressures)
    assert f0.joined_to == [None, 1] and r.fractures.fractures[1].joined_to == [None, None]
    # no crossing: the host is touched, not cut through
    assert np.all(f0.points[:, 0] <= A + 0.35 + 1e-12)
    joined_at = next(k for k, s in enumerate(r.steps) for t in s["tips"]
                     if (t["fracture"], t["end"], t["state"]) == (0, 1, "joined"))
    assert joined_at < len(r.steps) - 1   # the last step was meshed with the T
    cm = r.mesh
    at = np.flatnonzero(np.linalg.norm(cm.x - f0.points[-1], axis=1) < 1e-12)
    assert len(at) == 3
    assert not any(t.fracture == 0 and t.end == 1 for t in cm.tips)
    wing_pairs = cm.pair_fracture == 0
    assert np.any(np.isin(cm.pairs[wing_pairs], at).all(axis=1))  # the wing's pair at the T
    assert np.any(cm.x[cm.pairs[wing_pairs, 0], 0] > A + 0.2)      # pairs along the new faces


@pytest.mark.parametrize("connect", [True, False])
def test_a_join_connects_the_pressures(tmp_path, connect):
    """Issue 15: the run of the T above with fracture 0 pressurised. Once its
    wing has joined fracture 1, the dry fracture 1 carries fracture 0's
    pressure (propagation.connect_pressure = true), in the run's fracture
    set and in the checkpoint the next step would resume from; with false
    each keeps its own. 1 Pa against the 1e5 Pa tension changes K by about
    1e-5, far from moving the wing off the path of the test above."""
    from wingcrack.propagation import checkpoint

    cracks = [[[-A, 0.0], [A, 0.0]], [[A + 0.35, -0.6], [A + 0.35, 0.6]]]
    case = tension_plate(steps=4, cracks=cracks, connect_pressure=connect)
    case = replace(case, fractures=(replace(case.fractures[0], pressure=1.0), case.fractures[1]))
    r = run(case, out=tmp_path)
    f0, f1 = r.fractures.fractures
    assert f0.ends[1] == "joined" and f0.joined_to == [None, 1]
    want = [1.0, 1.0] if connect else [1.0, 0.0]
    assert [f0.law.pressure, f1.law.pressure] == want
    saved = checkpoint.load(tmp_path, case)["fset"].fractures
    assert [f.law.pressure for f in saved] == want and saved[0].joined_to == [None, 1]


def test_a_failure_keeps_the_finished_steps(tmp_path, monkeypatch):
    """A failure at step 2 (here: meshing) ends the run with 'failed: ...'
    and summary.json still holds steps 0 and 1."""
    import wingcrack.step as step

    real = step.discretise
    calls = {"n": 0}

    def flaky(*a, **k):
        calls["n"] += 1
        if calls["n"] == 3:
            raise RuntimeError("gmsh could not mesh (simulated)")
        return real(*a, **k)

    monkeypatch.setattr(step, "discretise", flaky)
    with pytest.raises(ComputationError, match="failed: step 2"):
        run(tension_plate(), out=tmp_path)
    saved = json.loads((tmp_path / "summary.json").read_text())
    assert saved["status"].startswith("failed: step 2") and len(saved["steps"]) == 2


def test_load_factor_limit_stops_the_run():
    """The limit below the critical load: the step is solved and recorded at the limit, and the status
    says how far from KIc its tips stayed: Griffith's K = sigma sqrt(pi a) at load factor 1, within 1 %
    (the plate is 100a wide; SIFs ~0.1 %)."""
    r = run(tension_plate(max_load_factor=1.0))
    assert len(r.steps) == 1 and r.steps[0]["load_factor"] == 1.0
    ratio = max(t["K_eq"] for t in r.steps[0]["tips"]) / 1e6
    assert abs(ratio / (SIGMA * np.sqrt(np.pi * A) / 1e6) - 1) < 1e-2
    assert r.status == f"stopped: no tip reaches KIc below the load factor limit 1 (there the largest K_eq is " \
                       f"{ratio:.3g} KIc)"


def test_fixed_load_below_kic_stops_with_a_complete_result(tmp_path):
    """load = "fixed" and no tip at KIc: one solved step, recorded with its
    files (so the pictures can be drawn), status stopped, no growth."""
    case = tension_plate(steps=3, load="fixed")      # load factor 1: K = 1e5 sqrt(pi) << KIc = 1e6
    r = run(case, out=tmp_path)
    assert r.status == "stopped: no tip reaches KIc under the fixed load" and len(r.steps) == 1
    step = r.steps[0]
    assert all(t["K_eq"] < 1e6 for t in step["tips"]) and "total" in step["seconds"] and step["solves"] == 1
    assert (tmp_path / "step_0000.vtu").exists() and (tmp_path / "faces_0000.vtu").exists()
    assert (tmp_path / "fractures.png").exists()


def test_a_run_where_no_tip_can_move_stops_at_once(tmp_path):
    """Promise 4: an inclined crack whose tips kink, with Lmax under L_min
    (which `check` refuses; a case built past it): no tip can advance, so
    the run records its one solved step and stops, saying why, instead of
    repeating that step to the end ("finished" after 3 identical steps)."""
    case = tension_plate(steps=3, cracks=[[[-A, -A], [A, A]]])
    case = replace(case, propagation=replace(case.propagation, length=0.3 * case.mesh.tip_size))
    r = run(case, out=tmp_path)
    assert r.status == "stopped: no tip can grow (its advance would be under L_min = 0.4 mesh.tip_size)"
    assert len(r.steps) == 1 and all(t["advance"] == 0.0 and t["state"] == "arrested" for t in r.steps[0]["tips"])
    assert max(t["K_eq"] for t in r.steps[0]["tips"]) >= 1e6 * (1 - 1e-3)    # at KIc: the law, not the load
    saved = json.loads((tmp_path / "summary.json").read_text())
    assert saved["status"] == r.status and len(saved["steps"]) == 1
    assert (tmp_path / "step_0000.vtu").exists() and not (tmp_path / "step_0001.vtu").exists()


def test_the_open_disc_with_half_steps_grows_every_step(tmp_path):
    """Promise 4 (c): the 45-degree open disc with length = 0.25 mm and
    tip_size 0.5 mm grew one step and then sat at K_eq = 1.11 KIc,
    "arrested", advance 0 (see test_growth_module.py for why). Every tip
    the growth law advances (K_eq at KIc, its share of Lmax at least L_min)
    now advances, by that share, every step."""
    from wingcrack.propagation.growth_law import advances

    case = Case.from_toml(Path(__file__).resolve().parents[2] / "cases" / "brazilian_disc_45_open.toml")
    case = replace(case, propagation=replace(case.propagation, length=0.00025, steps=4))
    r = run(case, out=tmp_path, plots=False)
    assert r.status == "finished" and len(r.steps) == 4
    m = case.material
    for s in r.steps:
        keq = np.array([t["K_eq"] for t in s["tips"]])
        G = np.where(keq >= m.KIc * (1 - 1e-3), keq ** 2 / m.E, 0.0)
        L = advances(G, 0.00025, case.propagation.alpha, 0.4 * case.mesh.tip_size,
                     np.array([t["theta"] for t in s["tips"]]))
        assert np.all(L > 0)
        # the advance is the law's L (rounded to its 1e-8 grid of Lmax)
        assert np.allclose([t["advance"] for t in s["tips"]], L, rtol=0, atol=1e-7 * 0.00025)
        assert all(t["state"] == "growing" for t in s["tips"])


def test_a_step_that_cannot_be_recorded_fails_with_a_summary(tmp_path):
    """A step whose record holds an inf (here: Lmax = 1e300 m, which `check`
    refuses, set past it) fails with "failed: step 0: ..." and a summary
    without that step, not "unexpected" with no summary at all."""
    case = tension_plate(steps=2)
    case = replace(case, propagation=replace(case.propagation, length=1e300))
    with pytest.raises(ComputationError, match="failed: step 0: "):
        run(case, out=tmp_path)
    saved = json.loads((tmp_path / "summary.json").read_text())
    assert saved["status"].startswith("failed: step 0: ") and saved["steps"] == []


def test_a_case_with_no_tip_that_may_grow_stops_at_once():
    """Every fracture `grow = false`: no step can be taken, and the status
    says why (a run whose tips all joined or reached the boundary after
    growing is "finished" instead: tests/verification/test_growth_to_rim.py)."""
    from wingcrack.propagation.loop import NO_TIP_AT_ALL

    d = square_plate_with_cracks(L, [[[-A, 0.0], [A, 0.0]]], (0.0, 0.0, 0.0), size=10 * A, tip_size=0.05)
    d["fractures"][0]["grow"] = False
    d["bc"] += [{"on": "top", "traction": [0.0, SIGMA]}, {"on": "bottom", "traction": [0.0, -SIGMA]}]
    d["propagation"] = {"steps": 3, "length": 0.1}
    r = run(Case.from_dict(d))
    assert r.status == NO_TIP_AT_ALL == "stopped: no tip can grow (no fracture has a free tip that may grow)"
    assert r.steps == []


def test_a_run_of_zero_steps_is_not_finished(tmp_path):
    """propagation.steps = 0: nothing is done, and the status says so
    instead of "finished" (a run that did nothing is never finished)."""
    from wingcrack.propagation.loop import NO_STEPS

    r = run(tension_plate(steps=0), out=tmp_path / "r", plots=False)
    assert r.status == NO_STEPS and r.steps == []
    assert json.loads((tmp_path / "r" / "summary.json").read_text())["status"] == NO_STEPS


def test_a_run_stopped_on_the_load_limit_records_the_step_at_the_limit():
    """A compressed frictionless crack whose critical load rises (2.570, then 3.413), limited to 2.8:
    step 0 grows at 2.570 and step 1, which no tip can start below the limit, is recorded at the limit
    with its files, so that the user sees how far from KIc its tips stayed. Frictionless contact under
    a scaled load is homogeneous (K proportional to the load on the same geometry and mesh), so K_eq at
    2.8 is KIc * 2.8 / 3.413, the unlimited run's critical load of step 1, to round-off (1e-9); the
    status says that ratio, and the result's mesh is the recorded step's (it was once the limit
    search's trial solve, unrecorded)."""
    d = {"material": {"E": 10e9, "nu": 0.25, "KIc": 1e6},
         "domain": {"shape": "rectangle", "corner": [-1.0, -1.0], "size": [2.0, 2.0]},
         "fractures": [{"points": [[-0.1, -0.1], [0.1, 0.1]], "faces": "frictionless"}],
         "bc": [{"on": "top", "traction": [0.0, -1e6]}, {"on": "bottom", "traction": [0.0, 1e6]},
                {"at": [-1.0, 0.0], "displacement": [0.0, 0.0]}, {"at": [1.0, 0.0], "displacement_y": 0.0}],
         "mesh": {"size": 0.25, "tip_size": 0.02, "sectors": 16},
         "propagation": {"steps": 3, "length": 0.02, "max_load_factor": 2.8}}
    r = run(Case.from_dict(d))
    free = run(Case.from_dict({**d, "propagation": {**d["propagation"], "steps": 2, "max_load_factor": 100}}))
    critical = free.steps[1]["load_factor"]
    assert 2.8 < critical and free.steps[0]["load_factor"] < 2.8
    ratio = 2.8 / critical
    assert r.status == f"stopped: no tip reaches KIc below the load factor limit 2.8 (there the largest K_eq is " \
                       f"{ratio:.3g} KIc)" and len(r.steps) == 2
    assert r.steps[0]["load_factor"] == free.steps[0]["load_factor"] and r.steps[1]["load_factor"] == 2.8
    np.testing.assert_allclose([t["K_eq"] for t in r.steps[1]["tips"]],
                               [ratio * t["K_eq"] for t in free.steps[1]["tips"]], rtol=1e-9)
    assert all(t["state"] == "arrested" and t["advance"] == 0.0 for t in r.steps[1]["tips"])
    assert r.dolfinx_mesh is not None and len(r.tips) == 2
    assert r.displacement.function_space.dofmap.index_map.size_global * 2 == r.steps[1]["dofs"]


def test_the_load_limit_status_says_when_nothing_scales():
    """Only an in-situ stress (not scaled) and zero displacements: the load
    factor multiplies nothing, and the status says so (it read as if a
    larger max_load_factor could help)."""
    from wingcrack.propagation.loop import NOTHING_SCALES

    d = square_plate_with_cracks(L, [[[-A, 0.0], [A, 0.0]]], (0.0, 1e4, 0.0), size=10 * A, tip_size=0.05)
    d["propagation"] = {"steps": 2, "length": 0.1}
    case = Case.from_dict(d)
    r = run(case)
    # the step is recorded at the limit; nothing scales, so its K_eq is step 0's at load factor 1 (`sif`)
    k_eq = [t.K_eq for t in sif(case).tips]
    assert len(r.steps) == 1 and r.steps[0]["load_factor"] == 100
    np.testing.assert_allclose([t["K_eq"] for t in r.steps[0]["tips"]], k_eq, rtol=1e-12)
    assert r.status == "stopped: no tip reaches KIc below the load factor limit 100 (there the largest K_eq is " \
                       f"{max(k_eq) / case.material.KIc:.3g} KIc)" + NOTHING_SCALES
    assert not run(tension_plate(max_load_factor=1.0)).status.endswith(NOTHING_SCALES)
