"""Issue 15, the results of fluid pressure in fractures: the pressures of a
step in summary.json (StepRecord.pressures, also from a summary written
before them), the pressure in faces_XXXX.vtu and how a result reads it
back (0 in an older file), how fractures.png marks the pressurised
fractures (a blue rim, darker with pressure, a legend entry per pressure
or a colour bar), and the injection pressure and slipping length that
history.png draws.

The face files are written for a hand-made crack mesh (no gmsh, no
DOLFINx): one straight crack along +x from (-1, 0) to (1, 0) in four P2
edges of 0.5 m, so that lengths and which edges slip follow by hand. What
a real run writes is checked in tests/command_line/test_plot.py.
"""
from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from wingcrack.io.faces import OPEN, SLIP, STICK, write_faces
from wingcrack.io.outdir import StoredResult
from wingcrack.results import ContactRecord, StepRecord


def straight_crack():
    """+ face nodes 0..8 at x = -1, -0.75, ..., 1 (0 and 8 the tips, not
    pairs: the edges are [0, 2, 1], [2, 4, 3], [4, 6, 5], [6, 8, 7]); the
    - face copies 9..15 of nodes 1..7."""
    xs = np.linspace(-1.0, 1.0, 9)
    x = np.vstack([np.c_[xs, np.zeros(9)], np.c_[xs[1:8], np.zeros(7)]])
    return SimpleNamespace(x=x, pairs=np.c_[np.arange(1, 8), np.arange(9, 16)],
                           pair_normal=np.tile([0.0, 1.0], (7, 1)),
                           crack_edges=np.array([[0, 2, 1], [2, 4, 3], [4, 6, 5], [6, 8, 7]]),
                           crack_fracture=np.zeros(4, int))


def values(state, pressure=None) -> dict:
    """Face values of the 7 pairs (x = -0.75 ... 0.75) with these states."""
    state = np.asarray(state, np.int8)
    out = {"jump": np.zeros((7, 2)), "normal_traction": np.where(state != OPEN, -1e6, 0.0),
           "tangential_traction": np.zeros(7), "state": state, "slip_increment": np.zeros(7),
           "closed": state != OPEN}
    if pressure is not None:
        out["pressure"] = np.asarray(pressure, float)
    return out


def stored(folder: Path, faces: list, pressures=None) -> StoredResult:
    steps = [{"step": k, **({} if pressures is None else {"pressures": pressures[k]})} for k in range(len(faces))]
    summary = {"title": "t", "version": "0", "status": "finished", "steps": steps,
               "fractures": [{"points": [[-1.0, 0.0], [1.0, 0.0]], "origin": "pre-existing", "fracture": 0}]}
    return StoredResult(folder, summary, [folder / f"step_{k:04d}.vtu" for k in range(len(faces))], faces)


# ---------------------------------------------------------------- summary.json


OLD_STEP = {"step": 3, "load_factor": 1.25, "dofs": 7000, "cells": 1500,
            "tips": [{"fracture": 0, "end": 1, "x": 0.1, "y": 0.2, "KI": 0.0, "KII": 1e6, "KI_M": None,
                      "KII_M": None, "G": 10.0, "theta": -1.23, "K_eq": 1.1e6, "advance": 0.0, "state": "arrested"}],
            "contact": {"pairs": 44, "rows": 44, "closed": 37, "stick": 10, "slip": 27, "iterations": 3,
                        "fallback": False},
            "seconds": {"total": 1.0}, "mesh": {}, "solves": 4}


def test_a_step_records_every_fractures_pressure_and_reads_it_back():
    rec = StepRecord.from_dict({**OLD_STEP, "pressures": [0.0, 12.5e6, 0.0]})
    assert rec.pressures == [0.0, 12.5e6, 0.0]
    d = rec.to_dict()
    assert d["pressures"] == [0.0, 12.5e6, 0.0]
    assert StepRecord.from_dict(d) == rec


def test_a_step_from_before_fluid_pressure_loads_and_writes_back_unchanged():
    """A summary or checkpoint written before fluid pressure: --resume loads
    its steps with no pressures and writes them back as they were."""
    rec = StepRecord.from_dict(OLD_STEP)
    assert rec.pressures == []
    assert rec.to_dict() == OLD_STEP


def test_finish_records_what_the_discretisation_says_the_pressures_are():
    """step.finish takes the pressures at the step's own load factor from
    the discretisation's FractureFluid.pressures (actual pressures: lam * p
    in the pressure and scale modes)."""
    from wingcrack.step import Timer, finish

    cm = SimpleNamespace(pairs=np.zeros((0, 2)), stats={"min_quality": 0.5, "min_jacobian": 1.0, "nodes": 9,
                                                        "tips": 2, "gmsh_retried": False, "symmetric": False,
                                                        "far_field": None})
    asked = []

    class Disc:
        dofs, cells = 18, 4

        def __init__(self):
            self.cm = cm
            self.contact = SimpleNamespace(rows=(), result=None)   # no rows: the record's ContactRecord(0, 0)

    class Fluid:
        def pressures(self, lam):
            asked.append(lam)
            return lam * np.array([0.0, 4e6])

    class Wet(Disc):
        fluid = Fluid()

    rec = finish(None, 2, 1.75, Wet(), [], Timer())
    assert asked == [1.75] and rec.pressures == [0.0, 7e6] and rec.contact == ContactRecord(0, 0)
    assert all(type(p) is float for p in rec.pressures)   # json writes numpy floats only by accident


# ---------------------------------------------------------------- faces_XXXX.vtu


def test_face_file_holds_the_pressure_at_every_pair(tmp_path):
    """pressure at each + face node of a pair; 0 at the tips, which are no pairs."""
    import meshio

    p = np.linspace(1e6, 7e6, 7)
    path = write_faces(tmp_path / "faces_0000.vtu", straight_crack(), values([OPEN] * 7, p))
    m = meshio.read(path)
    order = np.argsort(m.points[:, 0])
    assert np.array_equal(m.point_data["pressure"][order], np.r_[0.0, p, 0.0])


def test_face_values_without_pressure_are_written_dry(tmp_path):
    import meshio

    path = write_faces(tmp_path / "faces_0000.vtu", straight_crack(), values([OPEN] * 7))
    assert not meshio.read(path).point_data["pressure"].any()


def test_the_result_reads_the_pressure_back_per_node_and_per_edge(tmp_path):
    """StepFaces.values["pressure"] at the lines' nodes, and per edge the
    largest at its nodes: a tip (0) does not make its edge dry."""
    p = np.full(7, 3e6)
    faces = write_faces(tmp_path / "faces_0000.vtu", straight_crack(), values([OPEN] * 7, p))
    f = stored(tmp_path, [faces]).faces_of(0)
    assert np.array_equal(f.values["pressure"], [[0.0, 3e6, 3e6], [3e6, 3e6, 3e6], [3e6, 3e6, 3e6],
                                                 [3e6, 3e6, 0.0]])
    assert np.array_equal(f.pressure, np.full(4, 3e6))


def test_a_face_file_from_before_fluid_pressure_reads_dry(tmp_path):
    """A face file without pressure (written before issue 15) reads with
    pressure 0 everywhere, its other values as they are."""
    import meshio

    path = write_faces(tmp_path / "faces_0000.vtu", straight_crack(), values([SLIP] * 7, np.full(7, 1e6)))
    m = meshio.read(path)
    del m.point_data["pressure"]
    m.write(path)
    f = stored(tmp_path, [path]).faces_of(0)
    assert np.array_equal(f.values["pressure"], np.zeros((4, 3)))
    assert np.array_equal(f.pressure, np.zeros(4)) and np.array_equal(f.state, [OPEN, SLIP, SLIP, OPEN])


def test_edge_lengths_and_the_slipping_length(tmp_path):
    """Four edges of 0.5 m; all pairs slipping: the two inner edges slip
    (an edge at a tip never is in contact), 1.0 m; pairs at x = -0.75 ...
    0 sticking and the rest slipping: edge 1 sticks, edge 2 slips, 0.5 m."""
    from wingcrack.io.history import slipping_lengths

    a = write_faces(tmp_path / "faces_0000.vtu", straight_crack(), values([SLIP] * 7))
    b = write_faces(tmp_path / "faces_0001.vtu", straight_crack(), values([STICK] * 4 + [SLIP] * 3))
    result = stored(tmp_path, [a, b])
    assert np.allclose(result.faces_of(0).lengths, 0.5, rtol=0, atol=1e-15)
    assert np.array_equal(result.faces_of(1).state, [OPEN, STICK, SLIP, OPEN])
    assert np.allclose(slipping_lengths(result), [1.0, 0.5], rtol=0, atol=1e-15)


# ---------------------------------------------------------------- fractures.png


def three_fractures():
    """Summary pieces of three fractures: 0 with a wing at each end (a kink
    at each), 1 straight and 2 with a wing at end 1."""
    return [{"points": [[-3.2, 0.2], [-3.0, 0.0]], "origin": "wing", "fracture": 0},
            {"points": [[-3.0, 0.0], [-2.0, 0.0]], "origin": "pre-existing", "fracture": 0},
            {"points": [[-2.0, 0.0], [-1.8, -0.2]], "origin": "wing", "fracture": 0},
            {"points": [[-0.5, 0.0], [0.5, 0.0]], "origin": "pre-existing", "fracture": 1},
            {"points": [[2.0, 0.0], [3.0, 0.0]], "origin": "pre-existing", "fracture": 2},
            {"points": [[3.0, 0.0], [3.1, 0.1], [3.2, 0.1]], "origin": "wing", "fracture": 2}]


def luminance(rgba) -> float:
    return float(np.dot(rgba[:3], [0.2126, 0.7152, 0.0722]))


def test_the_picture_rims_the_pressurised_fractures_with_their_wings(tmp_path):
    """Fractures 0 (5 MPa) and 2 (2 MPa) hold fluid, 1 is dry: a rim along
    each wet fracture and its wings, chained through the kinks, none along
    1; a legend entry per pressure, highest first, after the face states;
    the higher pressure the darker blue; the state bands as without fluid."""
    from wingcrack.io.pictures import PRESSURE_BLUES, plot_fractures, pressure_colours

    fr = three_fractures()
    lines = np.array([[[-0.5, 0.0], [0.0, 0.0], [0.5, 0.0]], [[2.0, 0.0], [2.5, 0.0], [3.0, 0.0]]])
    dry = plot_fractures(tmp_path / "dry.png", fr, face_lines=lines, face_states=[SLIP, OPEN])
    wet = plot_fractures(tmp_path / "wet.png", fr, face_lines=lines, face_states=[SLIP, OPEN],
                         pressures={0: 5e6, 2: 2e6})
    assert "pressurised" not in dry
    got = wet["pressurised"]
    assert len(got["lines"]) == 2 and np.array_equal(got["pressure"], [5e6, 2e6])
    assert np.array_equal(got["lines"][0], [[-3.2, 0.2], [-3.0, 0.0], [-2.0, 0.0], [-1.8, -0.2]])
    assert np.array_equal(got["lines"][1], [[2.0, 0.0], [3.0, 0.0], [3.1, 0.1], [3.2, 0.1]])
    assert wet["legend"] == dry["legend"] + ["pressurised: p = 5 MPa", "pressurised: p = 2 MPa"]
    for label in ("faces open", "faces slip"):
        assert np.array_equal(wet[label], dry[label])
    assert wet["colour bars"] == dry["colour bars"] == []
    cmap, norm = pressure_colours(5e6)
    assert norm.vmin == 0.0 and norm.vmax == 5e6
    assert luminance(cmap(norm(5e6))) < luminance(cmap(norm(2e6))) < luminance(cmap(0.0))
    # the lightest shade is Blues at PRESSURE_BLUES[0], darker than the open band's light blue
    from matplotlib.colors import to_rgba

    from wingcrack.io.pictures import FACE_BANDS

    assert luminance(cmap(0.0)) < luminance(to_rgba(FACE_BANDS[OPEN][0])) and PRESSURE_BLUES[0] >= 0.5


def test_many_pressures_get_a_colour_bar(tmp_path):
    """More distinct pressures than PRESSURE_LEGEND_MAX: one legend entry
    and a colour bar in MPa instead of an entry each."""
    from wingcrack.io.pictures import PRESSURE_BAR, PRESSURE_LEGEND_MAX, plot_fractures

    n = PRESSURE_LEGEND_MAX + 1
    fr = [{"points": [[2.0 * i, 0.0], [2.0 * i + 1.0, 0.0]], "origin": "pre-existing", "fracture": i} for i in range(n)]
    pressures = {i: 1e6 * (i + 1) for i in range(n)}
    drawn = plot_fractures(tmp_path / "a.png", fr, pressures=pressures)
    assert np.array_equal(drawn["pressurised"]["pressure"], [pressures[i] for i in range(n)])
    assert drawn["legend"] == ["pre-existing", "pressurised (colour: p)"]
    assert drawn["colour bars"] == [PRESSURE_BAR]
    # as many fractures at the same pressures as the legend can name: an entry each
    drawn = plot_fractures(tmp_path / "b.png", fr, pressures={i: 1e6 * (1 + i % 2) for i in range(n)})
    assert drawn["legend"] == ["pre-existing", "pressurised: p = 2 MPa", "pressurised: p = 1 MPa"]


def test_the_pressures_of_a_summary_are_its_last_steps():
    from wingcrack.io.pictures import fracture_pressures

    steps = [{"pressures": [1e6, 0.0, 0.0]}, {"pressures": [2e6, 2e6, 0.0]}]
    assert fracture_pressures({"steps": steps}) == {0: 2e6, 1: 2e6}
    assert fracture_pressures({"steps": [{"step": 0}]}) == {}   # before fluid pressure
    assert fracture_pressures({"steps": []}) == {}


# ---------------------------------------------------------------- history.png


def test_history_draws_the_injection_pressure_and_the_slipping_length(tmp_path):
    """The injection pressure of a step is its highest fracture pressure
    (MPa in the picture); the slipping length comes from the face files."""
    from wingcrack.io.history import history, plot_history

    a = write_faces(tmp_path / "faces_0000.vtu", straight_crack(), values([STICK] * 7, np.full(7, 1e6)))
    b = write_faces(tmp_path / "faces_0001.vtu", straight_crack(), values([SLIP] * 7, np.full(7, 6e6)))
    result = stored(tmp_path, [a, b], pressures=[[1e6, 0.0], [6e6, 6e6]])
    for st in result.summary["steps"]:
        st.update(load_factor=1.0, dofs=100, tips=[])
    assert np.array_equal(history(result.summary)["injection"], [1e6, 6e6])
    drawn = plot_history(tmp_path / "history.png", result.summary, result)
    assert np.array_equal(drawn["injection pressure"][1], [1.0, 6.0])
    assert np.allclose(drawn["slipping length"][1], [0.0, 1.0], rtol=0, atol=1e-15)
    # without the face files: the pressure alone
    drawn = plot_history(tmp_path / "history.png", result.summary)
    assert "injection pressure" in drawn and "slipping length" not in drawn


def test_history_without_fluid_has_no_pressure_panel(tmp_path):
    """A dry run (pressures all 0) and a summary from before fluid pressure:
    history.png as it was, load factor, K_eq and DOFs only."""
    from wingcrack.io.history import history, plot_history

    base = {"title": "t", "version": "0", "status": "finished", "fractures": []}
    for steps in ([{"step": 0, "load_factor": 1.0, "dofs": 10, "tips": [], "pressures": [0.0, 0.0]}],
                  [{"step": 0, "load_factor": 1.0, "dofs": 10, "tips": []}]):
        summary = {**base, "steps": steps}
        assert np.array_equal(history(summary)["injection"], [0.0])
        assert set(plot_history(tmp_path / "h.png", summary)) == {"load factor", "DOFs"}
