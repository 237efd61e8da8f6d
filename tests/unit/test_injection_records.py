"""What a pumped run's steps record and how it is shown: the step record's
time, injection and networks through summary.json and back, the rows of
to_dataframe(), the PVD's time axis (strictly increasing where unstable
steps share a time), the progress line, and history.png's series and
picture (the breakdown curve: every kept state in time order, the drop
after each growth at one time)."""
import json

import numpy as np
import pytest

from wingcrack.io.history import plot_history, pumped
from wingcrack.io.pvd import increasing, read_pvd, write_pvd
from wingcrack.progress import progress_text
from wingcrack.results import ContactRecord, StepRecord, tip_rows
from wingcrack.schedule import Schedule


def tip(fracture, end, x):
    return {"fracture": fracture, "end": end, "x": x, "y": 0.0, "KI": 1e6, "KII": 0.0, "KI_M": 1e6, "KII_M": 0.0,
            "G": 1.0, "theta": 0.0, "K_eq": 1e6, "advance": 0.1, "state": "growing"}


def step(k, t, p, history, unstable=False):
    """A pumped step of two networks: [0] (injected, pressure p) and [1] (dry)."""
    return {"step": k, "load_factor": p, "dofs": 100, "cells": 50, "tips": [tip(0, 1, 1.0 + k), tip(1, 0, 5.0)],
            "contact": {"pairs": 0, "rows": 0, "closed": 0, "stick": 0, "slip": 0, "iterations": 0,
                        "fallback": False},
            "seconds": {"solve": 0.5, "total": 1.0}, "mesh": {}, "solves": 3, "time": t,
            "injection": {"injected": 1e-4 * t, "stored": 1e-4 * t, "leaked": 0.0, "pressure": p, "volume": 2e-4,
                          "held": 1e-4, "unstable": unstable, "partly_filled": False, "history": history},
            "networks": [{"fractures": [0], "pressure": p, "volume": 2e-4, "length": 2.0 + 0.2 * k},
                         {"fractures": [1], "pressure": 0.0, "volume": 1e-4, "length": 1.0}]}


STEPS = [step(0, 10.0, 5e6, [[0.0, 1e6, 1e-4], [4.0, 3e6, 1.4e-4], [10.0, 5e6, 2e-4]]),
         step(1, 10.0, 4.5e6, [[10.0, 4.5e6, 2e-4]], unstable=True),
         step(2, 14.0, 4.8e6, [[10.0, 4.2e6, 2e-4], [14.0, 4.8e6, 2.4e-4]])]


def test_a_pumped_step_record_round_trips_through_summary_json():
    for d in STEPS:
        rec = StepRecord.from_dict(json.loads(json.dumps(d)))
        assert rec.time == d["time"] and rec.injection == d["injection"] and rec.networks == d["networks"]
        out = rec.to_dict()
        assert {k: out[k] for k in ("time", "injection", "networks")} == \
            {k: d[k] for k in ("time", "injection", "networks")}
    plain = StepRecord(0, 1.0, 10, 5, [], ContactRecord(0, 0), {}, {})
    assert not {"time", "injection", "networks"} & set(plain.to_dict())


def test_the_dataframe_rows_carry_time_injected_and_the_tips_network():
    rows = tip_rows(STEPS)
    assert len(rows) == 6
    r = rows[4]   # step 2, the tip of fracture 0
    assert (r["step"], r["time"], r["injected"], r["network"], r["network_pressure"], r["network_volume"]) == \
        (2, 14.0, 1e-4 * 14.0, 0, 4.8e6, 2e-4)
    assert rows[5]["network"] == 1 and rows[5]["network_pressure"] == 0.0
    unpumped = {k: v for k, v in STEPS[0].items() if k not in ("time", "injection", "networks")}
    assert not {"time", "injected", "network"} & set(tip_rows([unpumped])[0])


def test_the_pvd_axis_is_the_times_strictly_increasing(tmp_path):
    times = increasing([0.0, 10.0, 10.0, 10.0, 14.0])
    assert times[0] == 0.0 and times[1] == 10.0 and times[4] == 14.0
    assert times[1] < times[2] < times[3] < 10.0 + 1e-13
    write_pvd(tmp_path / "a.pvd", ["s0", "s1", "s2", "s3", "s4"], times)
    assert [t for t, _ in read_pvd(tmp_path / "a.pvd")] == times


def test_the_progress_line_says_time_and_pressure():
    assert progress_text(STEPS[2]).startswith("t 14 s, p 4.8 MPa, 100 DOFs")


def test_the_breakdown_curve_is_every_kept_state_in_time_order(tmp_path):
    pm = pumped({"steps": STEPS})
    t, p = pm["curve"]
    assert list(t) == [0.0, 4.0, 10.0, 10.0, 10.0, 14.0] and list(p) == [1e6, 3e6, 5e6, 4.5e6, 4.2e6, 4.8e6]
    assert list(pm["unstable"]) == [False, True, False]
    tl, ml = pm["length"]
    assert list(tl) == [0.0, 10.0, 10.0, 10.0, 10.0, 14.0] and list(ml) == [3.0, 3.0, 3.2, 3.2, 3.4, 3.4]
    drawn = plot_history(tmp_path / "history.png", {"title": "pumped", "status": "finished", "steps": STEPS,
                                                   "KIc": 1e6})
    assert (tmp_path / "history.png").stat().st_size > 0
    np.testing.assert_array_equal(drawn["injection pressure"][1], p / 1e6)
    assert list(drawn["unstable growth (no time passes)"][0]) == [10.0]
    assert list(drawn["critical pressure of the step"][0]) == [10.0, 14.0]
    assert drawn["fracture length"][1].max() == pytest.approx(3.4)


def test_between_two_states_the_curve_follows_the_pumped_fluid_through_a_pause():
    """States (0 s, 0 Pa) and (30 s, 3 MPa) on one geometry, the pump at
    1 (0-10 s), shut in (10-20 s), at 1 again: Q = 0, 10, 10, 20 at 0, 10,
    20, 30 s, so the pressure, interpolated in the fluid pumped, is 1.5 MPa
    at 10 s and stays there until 20 s (not the straight line in time,
    1 and 2 MPa). Without the schedule (an older summary) the states alone."""
    schedule = Schedule(np.array([0.0, 10.0, 20.0]), np.array([1.0, 0.0, 1.0]), 100.0)
    assert Schedule.from_dict(json.loads(json.dumps(schedule.to_dict()))).to_dict() == schedule.to_dict()
    s = step(0, 30.0, 3e6, [[0.0, 0.0, 0.0], [30.0, 3e6, 2e-4]])
    t, p = pumped({"steps": [s], "propagation": {"steps": 1, "length": 0.1, "schedule": schedule.to_dict()}})["curve"]
    assert list(t) == [0.0, 10.0, 20.0, 30.0] and list(p) == [0.0, 1.5e6, 1.5e6, 3e6]
    t, p = pumped({"steps": [s]})["curve"]
    assert list(t) == [0.0, 30.0] and list(p) == [0.0, 3e6]


def test_the_checkpoint_keeps_the_pumps_state_and_refuses_a_damaged_one(tmp_path):
    """The pump's state goes through checkpoint.npz as written; a state that
    is not one of the case (a network without the injected fracture, a NaN
    time) is a damaged checkpoint (a FolderError, exit 2, for --resume)."""
    from test_case_injection import PUMPED
    from wingcrack.case import Case
    from wingcrack.propagation import checkpoint
    from wingcrack.propagation.fracture_set import FractureSet

    case = Case.from_dict(PUMPED)
    fset = FractureSet.from_case(case)
    steps = [dict(STEPS[0], load_factor=5e6)]
    state = {"network": [1], "held": 1e-4, "time": 10.0, "pressure": 5e6, "closing": 4e6}
    checkpoint.save(tmp_path, case, 0, fset, 5e6, steps, None, pump=state)
    assert checkpoint.load(tmp_path, case)["pump"] == state
    # "open" faces under compression overlap at p0: the fluid held is below 0, and a run that went on with it
    # resumes (it was refused as damaged)
    overlap = {**state, "held": -6e-6}
    checkpoint.save(tmp_path, case, 0, fset, 5e6, steps, None, pump=overlap)
    assert checkpoint.load(tmp_path, case)["pump"] == overlap
    for bad in ({**state, "network": [0]}, {**state, "time": float("nan")}, {**state, "closing": "x"},
                {**state, "held": float("inf")}, {**state, "held": None}, None):
        checkpoint.save(tmp_path, case, 0, fset, 5e6, steps, None, pump=bad)
        with pytest.raises(ValueError, match="damaged"):
            checkpoint.load(tmp_path, case)
