"""Issue 15 verification 5: a pressurised fracture whose wing joins a dry
fracture floods it. From the step after the join the dry fracture carries
the pressure (summary.json's steps[].pressures and faces_XXXX.vtu's
pressure), and its faces open where the pressure exceeds the normal stress
on them.

The layout: in the plate of test_pressure_plate (side 100 a, far field as
the in-situ stress: principal compressions S1 = 3 MPa at 60 deg to the
x axis, S3 = 0.5 MPa across), fracture 0 is the crack 2a on the x axis
(coulomb, mu = 0.6, c = 0, injected: pressure P0, load = "pressure");
fractures 1 and 2 are dry (coulomb, mu = 1.0: in the in-situ field alone
they stick, mu sigma_n = 1.125 MPa > |tau| = 1.083 MPa), 0.6 a long at 30
deg to the x axis, where the wings of fracture 0 (kinked 70.5 deg) meet
them after two steps of length 0.1 a; 2 is 1's half-turn image. At p = 0
fracture 0 sticks (mu sigma_n = 1.425 MPa > |tau| = 1.083 MPa); it grows
at p = 1.71 MPa. The in-situ normal stress on 1 and 2 is 1.125 MPa, but the
wings move it: measured in the dry run, the part of 1 beyond the junction
carries 1.8-2.2 MPa, more than p, the rest 0.8 MPa or less (open near the
junction), so that the pressure opens only a part of them.

The reference for "the normal stress on them" is the same run with
propagation.connect_pressure = false: its steps are the same up to the
join (the pressures are), so its step after the join solves the same
geometry on the same mesh with the dry fractures dry; their contact
normal traction there is the normal stress they carry.
"""
import json

import meshio
import numpy as np
import pytest

import wingcrack
from builders import square_plate_with_cracks
from wingcrack.case import Case
from wingcrack.contact.friction import OPEN

A, L, TIP_SIZE = 1.0, 100.0, 0.05
S1, S3, BETA = 3.0e6, 0.5e6, 60.0
#: the injected pressure at load factor 1 (Pa)
P0 = 2.0e6
#: the dry fractures: centre on the wing's path from (a, 0), angle, half-length
DRY_CENTRE = np.array([A, 0.0]) + 0.3 * A * np.array([0.45, 0.89])
DRY_ANGLE, DRY_HALF = 30.0, 0.3 * A
STEPS = 3
#: "where p exceeds the normal stress" is a statement about the stress
#: before the faces open: opening a part of a fracture moves the normal
#: stress on the rest (measured: the closed part beyond the junction goes
#: from 1.79-2.16 MPa dry to 1.73-1.78 MPa total when flooded, p = 1.71
#: MPa). So a pair is asserted open where p exceeds the dry run's normal
#: stress by this fraction, closed where that stress exceeds p by it, and
#: nothing in between (measured on each dry fracture: 18 pairs open-asserted,
#: the highest dry stress among them 0.79 MPa; 9 closed-asserted, the lowest
#: 2.08 MPa; 2 in the band, 4 near the junction)
MARGIN = 0.2
#: and not within this distance of a junction (the ends of fracture 0's
#: wings), where the T's corner concentrates the stress: the dry run's
#: face node 0.02 a from it carries 1.37 MPa, 0.8 p, and stays closed
NEAR_JUNCTION = TIP_SIZE


def layout(connect):
    b = np.radians(BETA)
    m, m3 = np.array([np.cos(b), np.sin(b)]), np.array([-np.sin(b), np.cos(b)])
    s = -S1 * np.outer(m, m) - S3 * np.outer(m3, m3)
    g = np.radians(DRY_ANGLE)
    t = DRY_HALF * np.array([np.cos(g), np.sin(g)])
    dry1 = [DRY_CENTRE - t, DRY_CENTRE + t]
    dry2 = [-DRY_CENTRE + t, -DRY_CENTRE - t]   # the half-turn image of dry1
    d = square_plate_with_cracks(L, [[[-A, 0.0], [A, 0.0]], dry1, dry2], (s[0, 0], s[1, 1], s[0, 1]),
                                 size=10 * A, tip_size=TIP_SIZE)
    d["material"]["KIc"] = 1.5e6
    for i, f in enumerate(d["fractures"]):
        f.update(faces="coulomb", friction=0.6 if i == 0 else 1.0)
    d["fractures"][0]["pressure"] = P0
    d["propagation"].update(load="pressure", steps=STEPS, length=0.1 * A, connect_pressure=connect)
    return Case.from_dict(d)


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """{connect: (result, out folder)} of the layout run with
    connect_pressure true and false."""
    made = {}
    for connect in (True, False):
        out = tmp_path_factory.mktemp(f"connect_{connect}") / "out"
        made[connect] = wingcrack.run(layout(connect), out=out, plots=False), out
    return made


def joined_at(steps):
    """The step whose growth joined fracture 0's wings to the dry fractures."""
    for s in steps:
        if any(t["fracture"] == 0 and t["state"] == "joined" for t in s["tips"]):
            return s["step"]
    raise AssertionError("fracture 0's wings never joined")


def faces_of(out, k):
    """{fracture: (points (n, 2), pressure, state, closed, opening,
    normal traction)} of the face nodes of faces_XXXX.vtu, tip nodes (not
    pairs) left out."""
    f = meshio.read(out / f"faces_{k:04d}.vtu")
    cells, frac = f.cells_dict["line3"], f.cell_data_dict["fracture"]["line3"]
    ends = {}
    for c, fr in zip(cells, frac):
        for v in c[:2]:   # a vertex in one cell only of its fracture is an end (a tip or a mouth)
            ends.setdefault((int(fr), int(v)), 0)
            ends[(int(fr), int(v))] += 1
    out_ = {}
    for fr in np.unique(frac):
        nodes = np.array([v for v in np.unique(cells[frac == fr]) if ends.get((int(fr), int(v)), 2) != 1])
        out_[int(fr)] = {k: np.asarray(f.point_data[k])[nodes] for k in
                         ("pressure", "state", "closed", "opening", "normal_traction")}
        out_[int(fr)]["points"] = f.points[nodes, :2]
    return out_


def test_the_join_floods_the_dry_fractures(runs):
    """Up to the step that joins them the dry fractures carry no pressure;
    from the next step on (connect_pressure = true) they carry fracture 0's,
    in summary.json and in the face files; with connect_pressure = false
    they stay dry, and the steps up to the join are the same in both runs."""
    (wet, wet_out), (dry, dry_out) = runs[True], runs[False]
    assert len(wet.steps) == len(dry.steps) == STEPS, (wet.status, dry.status)
    j = joined_at(wet.steps)
    assert j == joined_at(dry.steps) and j + 1 < STEPS
    summary = json.loads((wet_out / "summary.json").read_text())
    assert [s["pressures"] for s in summary["steps"]] == [s["pressures"] for s in wet.steps]
    for k in range(STEPS):
        lam = wet.steps[k]["load_factor"]
        p = lam * P0
        flooded = k > j
        assert wet.steps[k]["pressures"] == pytest.approx([p, p if flooded else 0.0, p if flooded else 0.0],
                                                          rel=1e-12), (k, wet.steps[k]["pressures"])
        assert dry.steps[k]["pressures"] == pytest.approx([dry.steps[k]["load_factor"] * P0, 0.0, 0.0], rel=1e-12)
        if k <= j:
            assert dry.steps[k]["load_factor"] == pytest.approx(lam, rel=1e-12)
        wet_faces, dry_faces = faces_of(wet_out, k), faces_of(dry_out, k)
        assert np.allclose(wet_faces[0]["pressure"], p, rtol=1e-12)
        for fr in (1, 2):
            assert np.allclose(wet_faces[fr]["pressure"], p if flooded else 0.0, rtol=1e-12), (k, fr)
            assert np.all(dry_faces[fr]["pressure"] == 0.0)


def test_the_flooded_faces_open_where_the_pressure_exceeds_their_normal_stress(runs):
    """At the step after the join, on the dry fractures: where the pressure
    p exceeds the normal stress the dry run's faces carry there (its contact
    traction -t_n where closed, none where open) by MARGIN, the flooded
    faces are open (w > 0); where that stress exceeds p by MARGIN, they stay
    closed; both kinds occur (the layout is not trivially all open). Had the
    pressure only been recorded and not loaded the flooded faces, they
    would be the dry run's: closed where it holds them by 0.33-0.79 MPa."""
    (wet, wet_out), (dry, dry_out) = runs[True], runs[False]
    k = joined_at(wet.steps) + 1
    assert wet.steps[k]["load_factor"] == pytest.approx(dry.steps[k]["load_factor"], rel=1e-12)
    p = wet.steps[k]["load_factor"] * P0
    wet_faces, dry_faces = faces_of(wet_out, k), faces_of(dry_out, k)
    junctions = wet.fractures.fractures[0].points[[0, -1]]
    assert wet.fractures.fractures[0].ends == ["joined", "joined"]
    seen = {"open": 0, "closed": 0}
    for fr in (1, 2):
        w, d = wet_faces[fr], dry_faces[fr]
        assert np.array_equal(w["points"], d["points"]), "the two runs mesh the same geometry alike"
        sigma_n = np.where(d["closed"] > 0, -d["normal_traction"], 0.0)
        away = np.min(np.linalg.norm(w["points"][:, None, :] - junctions[None], axis=2), axis=1) > NEAR_JUNCTION
        exceeds = away & (p > (1 + MARGIN) * sigma_n)
        held = away & (sigma_n > (1 + MARGIN) * p)
        assert np.all(w["state"][exceeds] == OPEN) and np.all(w["opening"][exceeds] > 0), \
            (fr, w["points"][exceeds & (w["state"] != OPEN)])
        assert np.all(w["closed"][held] > 0), (fr, w["points"][held & (w["closed"] == 0)])
        seen["open"] += int(exceeds.sum())
        seen["closed"] += int(held.sum())
    assert seen["open"] >= 10 and seen["closed"] >= 2, seen
