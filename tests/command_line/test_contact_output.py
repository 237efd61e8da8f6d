"""Issue 14, the results of contact with friction: what faces_XXXX.vtu holds
(state open / stick / slip, tangential traction, slip increment), how a
result reads it back (also a face file written before friction), how
fractures.png draws the three states, and the summary's contact record
(stick, slip, friction residuals, fallback), also from a summary written
before friction (what `run --resume` loads).

The face files are written for a hand-made crack mesh (no gmsh, no
DOLFINx): one straight crack along +x from (-1, 0) to (1, 0) in two P2
edges, so that its normal n = (0, 1) and tangent t = (1, 0) give the
opening and slip of a jump by hand. The tractions that step.face_values
gives are checked on a solve: a glued crack under a uniform stress, whose
face tractions are that stress's.
"""
from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from wingcrack.io.faces import OPEN, SLIP, STICK, write_faces
from wingcrack.io.outdir import StoredResult, edge_states
from wingcrack.results import ContactRecord, StepRecord


def straight_crack():
    """+ face nodes 0..4 at x = -1, -0.5, 0, 0.5, 1 (0 and 4 the tips, not
    pairs); the - face copies 5, 6, 7 of nodes 1, 2, 3."""
    xs = np.array([-1.0, -0.5, 0.0, 0.5, 1.0])
    x = np.vstack([np.c_[xs, np.zeros(5)], np.c_[xs[1:4], np.zeros(3)]])
    return SimpleNamespace(x=x, pairs=np.array([[1, 5], [2, 6], [3, 7]]), pair_normal=np.tile([0.0, 1.0], (3, 1)),
                           crack_edges=np.array([[0, 2, 1], [2, 4, 3]]), crack_fracture=np.array([0, 0]))


# the three pairs at x = -0.5, 0, 0.5: open, sticking, slipping
VALUES = {"jump": np.array([[3e-4, 2e-4], [1e-5, 0.0], [-4e-5, 0.0]]),
          "normal_traction": np.array([0.0, -2e6, -1e6]),
          "tangential_traction": np.array([0.0, 3e5, 6e5]),
          "state": np.array([OPEN, STICK, SLIP], np.int8),
          "slip_increment": np.array([0.0, 0.0, -1e-5]),
          "closed": np.array([False, True, True])}


def stored(folder: Path, faces: Path) -> StoredResult:
    summary = {"title": "t", "version": "0", "status": "finished", "steps": [{"step": 0}],
               "fractures": [{"points": [[-1.0, 0.0], [1.0, 0.0]], "origin": "pre-existing", "fracture": 0}]}
    return StoredResult(folder, summary, [folder / "step_0000.vtu"], [faces])


def test_face_file_holds_state_tractions_and_slip_increment(tmp_path):
    """Every value at its + face node: opening = [u].n = [u]_y and slip =
    [u].t = [u]_x (n = (0, 1), t = (1, 0)); the tips (not pairs) OPEN with
    zeros; the state an integer code, the codes in the field data."""
    import meshio

    cm = straight_crack()
    path = write_faces(tmp_path / "faces_0000.vtu", cm, VALUES, field_data={"step": 0, "load_factor": 1.5})
    m = meshio.read(path)
    at = {round(float(p[0]), 12): i for i, p in enumerate(m.points)}
    node = [at[-0.5], at[0.0], at[0.5]]
    d = m.point_data
    assert np.array_equal(d["opening"][node], [2e-4, 0.0, 0.0])
    assert np.array_equal(d["slip"][node], [3e-4, 1e-5, -4e-5])
    for name in ("normal_traction", "tangential_traction", "slip_increment"):
        assert np.array_equal(d[name][node], VALUES[name])
    assert np.array_equal(d["closed"][node], [0.0, 1.0, 1.0])
    assert np.issubdtype(d["state"].dtype, np.integer) and np.array_equal(d["state"][node], [OPEN, STICK, SLIP])
    for tip in (at[-1.0], at[1.0]):
        assert d["state"][tip] == OPEN and all(d[k][tip] == 0 for k in d)
    f = {k: float(v[0]) for k, v in m.field_data.items()}
    assert f == {"step": 0.0, "load_factor": 1.5, "state_open": OPEN, "state_stick": STICK, "state_slip": SLIP}


def test_face_file_refuses_a_state_that_is_no_code(tmp_path):
    with pytest.raises(ValueError, match=r"not \[3\]"):
        write_faces(tmp_path / "f.vtu", straight_crack(), {**VALUES, "state": np.array([0, 3, 2])})


def test_state_codes_are_the_friction_solvers():
    friction = pytest.importorskip("wingcrack.contact.friction")
    assert (friction.OPEN, friction.STICK, friction.SLIP) == (OPEN, STICK, SLIP)


def test_the_result_reads_states_and_values_back(tmp_path):
    """faces_of: the lines a -> mid -> b with each node's values; edge 0
    (tip, open pair, stick pair) is OPEN, edge 1 (stick pair, slip pair, tip)
    too: a tip is never in contact, as `closed` had it."""
    faces = write_faces(tmp_path / "faces_0000.vtu", straight_crack(), VALUES)
    f = stored(tmp_path, faces).faces_of(0)
    assert np.array_equal(f.lines[:, :, 0], [[-1.0, -0.5, 0.0], [0.0, 0.5, 1.0]])
    assert np.array_equal(f.values["state"], [[OPEN, OPEN, STICK], [STICK, SLIP, OPEN]])
    assert np.array_equal(f.values["tangential_traction"], [[0.0, 0.0, 3e5], [3e5, 6e5, 0.0]])
    assert np.array_equal(f.values["slip_increment"], [[0.0, 0.0, 0.0], [0.0, -1e-5, 0.0]])
    assert np.array_equal(f.state, [OPEN, OPEN]) and not f.closed.any()


def test_an_edge_is_open_stick_or_slip_by_its_nodes():
    s = np.array([[STICK, STICK, STICK], [STICK, SLIP, STICK], [SLIP, OPEN, STICK], [SLIP, SLIP, SLIP],
                  [OPEN, SLIP, SLIP], [SLIP, SLIP, OPEN], [OPEN, OPEN, OPEN]])
    assert np.array_equal(edge_states(s), [STICK, SLIP, SLIP, SLIP, OPEN, OPEN, OPEN])


def test_a_face_file_from_before_friction_reads_as_frictionless(tmp_path):
    """A face file of an earlier version (opening, slip, normal_traction,
    closed only): its closed nodes SLIP, as frictionless and prescribed-slip
    pairs are, the others OPEN; no tangential traction or slip increment."""
    import meshio

    x = np.c_[np.linspace(-1.0, 1.0, 5), np.zeros((5, 2))]
    closed = np.array([0.0, 1.0, 1.0, 1.0, 0.0])
    data = {"opening": np.zeros(5), "slip": np.full(5, 1e-4), "normal_traction": -1e6 * closed, "closed": closed}
    path = tmp_path / "faces_0000.vtu"
    meshio.Mesh(x, [("line3", np.array([[0, 2, 1], [2, 4, 3]]))], point_data=data,
                cell_data={"fracture": [np.array([0, 0])]}).write(path)
    f = stored(tmp_path, path).faces_of(0)
    assert np.array_equal(f.values["state"], [[OPEN, SLIP, SLIP], [SLIP, SLIP, OPEN]])
    assert "tangential_traction" not in f.values and "slip_increment" not in f.values
    assert np.array_equal(f.values["normal_traction"], [[0.0, -1e6, -1e6], [-1e6, -1e6, 0.0]])
    assert np.array_equal(f.state, [OPEN, OPEN])


def test_a_face_file_with_a_state_that_is_no_code_is_refused(tmp_path):
    import meshio

    from wingcrack.errors import FolderError

    path = tmp_path / "faces_0000.vtu"
    meshio.Mesh(np.c_[np.linspace(-1.0, 1.0, 3), np.zeros((3, 2))], [("line3", np.array([[0, 2, 1]]))],
                point_data={"closed": np.zeros(3), "state": np.array([0.0, 7.0, 0.0])}).write(path)
    with pytest.raises(FolderError, match="a state that is not 0, 1 or 2"):
        stored(tmp_path, path).faces_of(0)


# ---------------------------------------------------------------- fractures.png


def test_the_picture_bands_each_state_present_and_names_it(tmp_path):
    """The bands drawn are exactly the face edges of each state, read back
    from the figure; a legend entry for each state present, none for the
    absent one (stick)."""
    from wingcrack.io.pictures import plot_fractures

    lines = np.array([[[0.0, 0.0], [0.5, 0.0], [1.0, 0.0]], [[1.0, 0.0], [1.5, 0.0], [2.0, 0.0]],
                      [[2.0, 0.0], [2.5, 0.0], [3.0, 0.0]]])
    fractures = [{"points": [[0.0, 0.0], [3.0, 0.0]], "origin": "pre-existing"}]
    drawn = plot_fractures(tmp_path / "a.png", fractures, face_lines=lines, face_states=[SLIP, OPEN, SLIP])
    assert set(drawn) == {"faces open", "faces slip", "legend", "colour bars"} and drawn["colour bars"] == []
    assert np.array_equal(drawn["faces open"], lines[[1]]) and np.array_equal(drawn["faces slip"], lines[[0, 2]])
    assert sorted(drawn["legend"]) == ["faces open", "faces slip", "pre-existing"]
    assert (tmp_path / "a.png").stat().st_size > 0
    drawn = plot_fractures(tmp_path / "b.png", fractures, face_lines=lines, face_states=[STICK, STICK, OPEN])
    assert np.array_equal(drawn["faces stick"], lines[:2]) and "faces slip" not in drawn["legend"]
    assert {"faces stick", "faces open"} <= set(drawn["legend"])


def test_the_picture_refuses_states_that_do_not_match_the_edges(tmp_path):
    from wingcrack.io.pictures import plot_fractures

    with pytest.raises(ValueError, match="2 face edges but 1 states"):
        plot_fractures(tmp_path / "a.png", [], face_lines=np.zeros((2, 3, 2)), face_states=[OPEN])


# ---------------------------------------------------------------- the contact record


def test_contact_record_round_trips_with_friction():
    rec = ContactRecord(40, 80, closed=30, iterations=5, kkt={"feasibility": 0.0, "sign": 0.0, "complementarity": 0.0},
                        stick=12, slip=18, friction={"bound": 1e-12, "at_bound": 2e-12, "direction": 0.0,
                                                     "stick_increment": 0.0}, fallback=True)
    d = rec.to_dict()
    assert (d["stick"], d["slip"], d["fallback"]) == (12, 18, True) and d["friction"]["at_bound"] == 2e-12
    assert ContactRecord.from_dict(d) == rec
    plain = ContactRecord(40, 0).to_dict()
    assert "friction" not in plain and "kkt" not in plain and (plain["stick"], plain["slip"]) == (0, 0)


def test_a_step_from_before_friction_loads_for_resume():
    """A summary or checkpoint written before friction has no stick, slip,
    friction or fallback: --resume loads it (StepRecord.from_dict) with its
    closed pairs slipping (what the frictionless faces it had do) and writes
    it back with the new keys and its old values unchanged."""
    old = {"step": 3, "load_factor": 1.25, "dofs": 7000, "cells": 1500,
           "tips": [{"fracture": 0, "end": 1, "x": 0.1, "y": 0.2, "KI": 0.0, "KII": 1e6, "KI_M": None,
                     "KII_M": None, "G": 10.0, "theta": -1.23, "K_eq": 1.1e6, "advance": 0.0, "state": "arrested"}],
           "contact": {"pairs": 44, "rows": 44, "closed": 37, "iterations": 3,
                       "kkt": {"feasibility": 0.0, "sign": 0.0, "complementarity": 1e-17}},
           "seconds": {"total": 1.0}, "mesh": {}, "solves": 4}
    rec = StepRecord.from_dict(old)
    c = rec.contact
    assert (c.closed, c.stick, c.slip, c.friction, c.fallback) == (37, 0, 37, None, False)
    again = rec.to_dict()
    assert again["contact"] == {**old["contact"], "stick": 0, "slip": 37, "fallback": False}
    assert {k: v for k, v in again.items() if k != "contact"} == {k: v for k, v in old.items() if k != "contact"}
    assert StepRecord.from_dict(again) == rec


# ---------------------------------------------------------------- face values of a solve


def test_face_tractions_of_a_glued_crack_are_the_uniform_stress():
    """A crack whose faces are glued (prescribed slip 0, in contact) in a
    plate under the uniform stress sigma: the uniform field is the solution
    (it lies in the P2 space and has no jump), so the face tractions are
    t_n = n.sigma.n and t_t = t.sigma.n at every pair; every pair is closed
    and counted as slipping (a prescribed slip holds its tangential row).
    Tolerance 1e-10 of |sigma|: only the round-off of the factorisation and
    of the tributary lengths (uniform tractions make the nodal forces
    exactly t * weight)."""
    from builders import square_plate_with_cracks
    from wingcrack.case import Case
    from wingcrack.face_values import contact_record, face_values
    from wingcrack.step import solve_initial

    t = np.array([np.cos(0.3), np.sin(0.3)])
    n = np.array([-t[1], t[0]])   # left normal of the fracture direction
    sxx, syy, sxy = -1e6, -2e6, 0.5e6
    sigma = np.array([[sxx, sxy], [sxy, syy]])
    d = square_plate_with_cracks(20.0, [[-t, t]], (sxx, syy, sxy), size=2.0, tip_size=0.1)
    d["fractures"][0].update({"faces": "slip", "slip": 0.0})
    sol = solve_initial(Case.from_dict(d))
    v = face_values(sol)
    scale = np.abs(sigma).max()
    assert n @ sigma @ n < 0 and abs(t @ sigma @ n) > 0.05 * scale   # pressed shut and sheared
    assert np.abs(v["normal_traction"] - n @ sigma @ n).max() < 1e-10 * scale
    assert np.abs(v["tangential_traction"] - t @ sigma @ n).max() < 1e-10 * scale
    assert v["closed"].all() and np.all(v["state"] == SLIP) and not v["slip_increment"].any()
    rec = contact_record(sol)
    assert (rec.closed, rec.stick, rec.slip, rec.fallback) == (len(sol.cm.pairs), 0, len(sol.cm.pairs), False)
