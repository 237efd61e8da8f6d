"""How a pumped run ends and what it says (load = "injection"): end_time
and shut-in before breakdown stop the run with the state at that time
recorded (its files, its K_eq against KIc, the fluid balance), `sif` solves
a pumped case at t = 0, `check` prints the schedule.

The case: an open crack 2a = 2 m in a plate of 40 m, no far stress, an
incompressible fluid, no residual aperture: V(p) = C p with C = 2 pi a^2 / E'
(Sneddon; 1e-2 in this small plate, measured 3.2e-3), so the pressure at time t
is p = Q t / C and KI = p sqrt(pi a); breakdown at t_c = C KIc / (Q sqrt(pi a)).
"""
import numpy as np
import pytest

import wingcrack
from wingcrack import cli
from wingcrack.case import Case

E, NU, KIC, A, Q = 10e9, 0.25, 1e6, 1.0, 1e-5
C = 2 * np.pi * A * A / (E / (1 - NU ** 2))
T_C = C * KIC / (Q * np.sqrt(np.pi * A))
#: the small plate's compliance against Sneddon's infinite one (measured 3.2e-3 on p, 2.8e-4 on K)
PLATE_TOL = 1e-2


def pumped(**injection):
    W = 40.0
    return Case.from_dict({
        "title": "pumped crack", "material": {"E": E, "nu": NU, "KIc": KIC, "plane": "strain"},
        "domain": {"shape": "rectangle", "corner": [-W / 2, -W / 2], "size": [W, W]},
        "fractures": [{"points": [[-A, 0.0], [A, 0.0]]}],
        "bc": [{"at": [-W / 2, -W / 2], "displacement": [0.0, 0.0]}, {"at": [W / 2, -W / 2], "displacement_y": 0.0}],
        "mesh": {"size": 4.0, "tip_size": 0.1},
        "propagation": {"steps": 3, "length": 0.2, "load": "injection"},
        "injection": {"fracture": 0, "compressibility": 0.0, **injection}})


def test_end_time_before_breakdown_records_the_state_there(tmp_path):
    end = 0.5 * T_C
    run = wingcrack.run(pumped(rate=Q, end_time=end), out=tmp_path / "out", plots=False)
    assert run.status.startswith(f"stopped: end_time reached: at {end:g} s the network holds ")
    assert len(run.steps) == 1 and (tmp_path / "out" / "step_0000.vtu").exists()
    s = run.steps[0]
    assert s["time"] == end and s["injection"]["injected"] == pytest.approx(Q * end, rel=1e-15)
    p = s["injection"]["pressure"]
    assert p == pytest.approx(Q * end / C, rel=PLATE_TOL)
    ratio = max(t["K_eq"] for t in s["tips"]) / KIC
    assert ratio == pytest.approx(0.5, rel=PLATE_TOL)
    assert f"the largest K_eq is {ratio:.3g} KIc" in run.status
    fluid = s["injection"]["volume"]
    assert abs(fluid - Q * end) <= 1e-10 * fluid   # the balance at end_time


def test_a_shut_in_before_breakdown_stops_when_the_pump_stops():
    stop = 0.3 * T_C
    run = wingcrack.run(pumped(times=[0.0, stop], rates=[Q, 0.0]), plots=False)
    assert run.status.startswith(f"stopped: shut-in from {stop:g} s: the network's fluid holds ")
    assert run.steps[-1]["time"] == stop
    assert run.steps[-1]["injection"]["pressure"] == pytest.approx(Q * stop / C, rel=PLATE_TOL)


def test_a_late_start_then_shut_in_keeps_the_history_to_the_runs_times(tmp_path):
    """A closed Coulomb crack 2a = 0.2 m under 1 MPa normal stress, water,
    no residual aperture; the pump starts at 10 s and stops at 20 s, before
    breakdown. The search's trials above the pressure the pumped fluid
    reaches are states the run never reaches (after the shut-in: at no
    time): the history keeps only the run's states, in time order, so
    summary.json holds finite times (it refused to be written: an
    "unexpected" ValueError) and history.png marks the stop, not a
    critical pressure."""
    d = {"title": "closed pumped crack", "material": {"E": E, "nu": NU, "KIc": KIC, "plane": "strain"},
         "domain": {"shape": "rectangle", "corner": [-1.0, -1.0], "size": [2.0, 2.0]},
         "fractures": [{"points": [[-0.1, 0.0], [0.1, 0.0]], "faces": "coulomb", "friction": 0.6}],
         "bc": [{"at": [-1.0, -1.0], "displacement": [0.0, 0.0]}, {"at": [1.0, -1.0], "displacement_y": 0.0}],
         "stress": {"sxx": -2e6, "syy": -1e6, "sxy": 0.0},
         "mesh": {"size": 0.1, "tip_size": 0.01},
         "propagation": {"steps": 3, "length": 0.01, "load": "injection"},
         "injection": {"fracture": 0, "times": [10.0, 20.0], "rates": [1e-7, 0.0]}}
    run = wingcrack.run(Case.from_dict(d), out=tmp_path / "out", plots=False)
    assert run.status.startswith("stopped: shut-in from 20 s: the network's fluid holds ")
    last = run.steps[-1]["injection"]
    assert last["stopped"] is True
    # the fluid pumped, 1e-6 m^3/m, opens the crack under p - 1 MPa: exp(c p) C (p - 1 MPa) = 1e-6 with
    # Sneddon's C = 2 pi a^2 / E'; within 3 % on the net pressure (a plate of 10 crack lengths: 1.4 % measured)
    c, C_a = 4.5e-10, 2 * np.pi * 0.1 ** 2 / (E / (1 - NU ** 2))
    from scipy.optimize import brentq
    p = brentq(lambda p: np.exp(c * p) * C_a * (p - 1e6) - 1e-6, 1e6, 1e7)
    assert last["pressure"] - 1e6 == pytest.approx(p - 1e6, rel=0.03)
    t = np.array([h[0] for s in run.steps for h in s["injection"]["history"]])
    assert np.all(np.isfinite(t)) and np.all(np.diff(t) >= 0) and t[-1] == 20.0
    from wingcrack.io.history import pumped as series

    curve_t, curve_p = series(run.summary)["curve"]
    # the curve follows the schedule: at rest (p0 = 0) until the pump starts, then rising
    assert 10.0 in curve_t and curve_p[list(curve_t).index(10.0)] == 0.0


def test_the_pump_grows_the_crack_after_breakdown_and_the_schedule_pauses():
    """A schedule with a pause after breakdown: the step after it waits for
    the fluid, so its time is past the pause."""
    run = wingcrack.run(pumped(times=[0.0, 1.2 * T_C, 2.0 * T_C], rates=[Q, 0.0, Q]), plots=False)
    assert run.status == "finished" and len(run.steps) == 3
    t = [s["time"] for s in run.steps]
    assert t[0] == pytest.approx(T_C, rel=PLATE_TOL) and t[1] > 2.0 * T_C


def test_sif_solves_a_pumped_case_at_its_initial_pressure():
    result = wingcrack.sif(pumped(rate=Q, initial_pressure=2e5))
    s = result.summary["steps"][0]
    assert s["load_factor"] == 1.0 and s["pressures"] == [2e5]
    assert result.tips[0].KI == pytest.approx(2e5 * np.sqrt(np.pi * A), rel=PLATE_TOL)


def test_check_prints_the_pump(capsys, tmp_path):
    from networks import to_toml

    path = tmp_path / "case.toml"
    d = {"title": "pumped crack", "material": {"E": E, "nu": NU, "KIc": KIC, "plane": "strain"},
         "domain": {"shape": "rectangle", "corner": [-20.0, -20.0], "size": [40.0, 40.0]},
         "fractures": [{"points": [[-A, 0.0], [A, 0.0]]}],
         "bc": [{"at": [-20.0, -20.0], "displacement": [0.0, 0.0]}, {"at": [20.0, -20.0], "displacement_y": 0.0}],
         "mesh": {"size": 4.0, "tip_size": 0.1}, "propagation": {"load": "injection"},
         "injection": {"fracture": 0, "times": [0.0, 60.0], "rates": [1e-4, 0.0], "end_time": 600.0}}
    path.write_text(to_toml(d))
    assert cli.main(["check", str(path)]) == 0
    out = capsys.readouterr().out
    assert "injection: into fracture 0 at (0, 0)" in out
    assert "schedule: 0.0001 m^3/s per m from 0 s to 60 s, shut-in from 60 s; the run ends at 600 s" in out


def test_no_tip_below_the_pressure_limit_stops_there_and_says_how_far():
    """The pump feeds a fracture that may not grow; the only growing tips are
    a dry fracture's, 5 m away, which the pressure loads only through the
    rock: below the limit 0.1 E no tip reaches KIc; the state at the limit is
    recorded and the status says how far from KIc it stayed."""
    W = 40.0
    case = Case.from_dict({
        "title": "out of reach", "material": {"E": E, "nu": NU, "KIc": KIC, "plane": "strain"},
        "domain": {"shape": "rectangle", "corner": [-W / 2, -W / 2], "size": [W, W]},
        "fractures": [{"points": [[-0.1, 0.0], [0.1, 0.0]], "grow": False},
                      {"points": [[5.0, -0.5], [5.0, 0.5]]}],
        "bc": [{"at": [-W / 2, -W / 2], "displacement": [0.0, 0.0]}, {"at": [W / 2, -W / 2], "displacement_y": 0.0}],
        "mesh": {"size": 4.0, "tip_size": 0.05},
        "propagation": {"steps": 2, "length": 0.1, "load": "injection"},
        "injection": {"fracture": 0, "rate": Q, "compressibility": 0.0}})
    run = wingcrack.run(case, plots=False)
    limit = 0.1 * E
    assert run.status.startswith(f"stopped: no tip reaches KIc below the pressure limit 0.1 E = {limit:.6g} Pa")
    s = run.steps[-1]
    ratio = max(t["K_eq"] for t in s["tips"] if t["fracture"] == 1) / KIC   # the tips that may grow
    assert s["injection"]["pressure"] == limit and 0 < ratio < 1
    assert f"(there the largest K_eq is {ratio:.3g} KIc)" in run.status
