"""The fracture records of a run (wingcrack/propagation/fracture_set.py):
what they take from the case and what their wings get (issue 14: friction
on every face, the wings included), and the joins that connect their fluid
pressures (issue 15)."""
from dataclasses import replace

import numpy as np
import pytest

from meshing import Domain
from wingcrack.case import Case
from wingcrack.face_law import FaceLaw
from wingcrack.propagation.fracture_set import FractureSet, GrowingFracture

# A 4 m x 2 m plate with one interior crack per kind of face, under
# compression; three scalar supports.
CASE = {
    "material": {"E": 1.0e10, "nu": 0.25, "KIc": 1.0e6},
    "domain": {"shape": "rectangle", "corner": [0.0, 0.0], "size": [4.0, 2.0]},
    "fractures": [
        {"points": [[0.5, 0.5], [1.0, 0.8]], "faces": "coulomb", "friction": 0.6, "cohesion": 2.0e5, "gap": 1e-6},
        {"points": [[1.5, 0.5], [2.0, 0.8]], "faces": "frictionless"},
        {"points": [[2.5, 0.5], [3.0, 0.8]], "faces": "slip", "slip": 1e-5},
        {"points": [[3.2, 1.2], [3.6, 1.5]]},
        {"points": [[0.5, 1.5], [1.0, 1.2]], "faces": "coulomb", "friction": 0.0},
    ],
    "bc": [
        {"on": "top", "traction": [0.0, -1.0e6]},
        {"on": "bottom", "traction": [0.0, 1.0e6]},
        {"at": [0.0, 1.0], "displacement": [0.0, 0.0]},
        {"at": [4.0, 1.0], "displacement_y": 0.0},
    ],
    "mesh": {"size": 0.2, "tip_size": 0.05},
}


@pytest.fixture(scope="module")
def fset():
    return FractureSet.from_case(Case.from_dict(CASE))


def test_from_case_carries_friction_and_cohesion(fset):
    got = [(f.law.faces, f.law.friction, f.law.cohesion, f.law.gap) for f in fset.fractures]
    assert got == [("coulomb", 0.6, 2.0e5, 1e-6), ("frictionless", 0.0, 0.0, 0.0), ("slip", 0.0, 0.0, 0.0),
                   ("open", 0.0, 0.0, 0.0), ("coulomb", 0.0, 0.0, 0.0)]


def test_wings_of_a_coulomb_fracture_are_coulomb_with_its_law(fset):
    """The wing's law is read from the same record (constraint_rows._parts
    gives a wing the fracture's law.wings(), with its own friction and
    cohesion), so a coulomb fracture's wings rub with its mu and c; the
    others keep the paper's rule: open stays open, contact becomes
    frictionless, a prescribed slip never reaches a wing."""
    assert [f.law.wings().faces for f in fset.fractures] == ["coulomb", "frictionless", "frictionless", "open", "coulomb"]


def test_a_grown_copy_keeps_the_law(fset):
    g = fset.copy()
    g.fractures[0].extend(1, [1.1, 0.9])
    assert g.fractures[0].pre == (0, 1) and len(g.fractures[0].points) == 3
    law = g.fractures[0].law
    assert (law.friction, law.cohesion, law.wings().faces) == (0.6, 2.0e5, "coulomb")
    assert len(fset.fractures[0].points) == 2   # the copy is its own


def test_a_record_built_without_a_law_is_frictionless():
    """A law given only its faces has no friction and no cohesion: mu = c = 0."""
    f = GrowingFracture(np.array([[0.0, 0.0], [1.0, 0.0]]), (0, 1), ["tip", "tip"], FaceLaw("frictionless"))
    assert (f.law.friction, f.law.cohesion, f.law.wings().faces) == (0.0, 0.0, "frictionless")


# ---------------------------------------------------------------- fluid pressure (issue 15)

def dry(points, pressure=0.0, joined_to=(None, None)):
    f = GrowingFracture(np.asarray(points, float), (0, len(points) - 1), ["tip", "tip"], FaceLaw(pressure=pressure))
    for e, g in enumerate(joined_to):
        if g is not None:
            f.ends[e], f.joined_to[e] = "joined", g
    return f


def test_from_case_carries_the_pressure_and_nothing_is_joined():
    d = {**CASE, "fractures": [dict(f) for f in CASE["fractures"]]}
    d["fractures"][1]["pressure"] = 4.0e6
    d["fractures"][3]["pressure"] = 1
    fs = FractureSet.from_case(Case.from_dict(d))
    assert [f.law.pressure for f in fs.fractures] == [0.0, 4.0e6, 0.0, 1.0, 0.0]
    assert all(f.joined_to == [None, None] for f in fs.fractures)
    assert not fs.connect_pressures() and [f.law.pressure for f in fs.fractures] == [0.0, 4.0e6, 0.0, 1.0, 0.0]


def test_a_copy_keeps_pressure_and_joins_as_its_own():
    fs = FractureSet([dry([[0, 0], [1, 0]], 2e6, (None, 1)), dry([[1, -1], [1, 1]])])
    g = fs.copy()
    assert [(f.law.pressure, f.joined_to) for f in g.fractures] == [(2e6, [None, 1]), (0.0, [None, None])]
    g.fractures[1].joined_to[0] = 0
    g.fractures[1].law = replace(g.fractures[1].law, pressure=5.0)
    assert fs.fractures[1].joined_to == [None, None] and fs.fractures[1].law.pressure == 0.0


def test_a_chain_of_joins_floods_with_its_highest_pressure():
    """0 ends on 1 (a T), 1 ends on 2: one group, though 0 and 2 never
    touch and the links run one way; 3 is joined to nothing and keeps its
    own. The group takes the highest of its pressures (5 MPa, not 2 + 5),
    whichever member holds it."""
    fs = FractureSet([dry([[0, 0], [1, 0]], 2e6, (None, 1)), dry([[1, -1], [1, 0.5]], 0.0, (None, 2)),
                      dry([[0.5, 0.5], [1.5, 0.5]], 5e6), dry([[-1, -1], [-0.5, -1]], 1e6)])
    assert fs.connected_groups() == [[0, 1, 2], [3]]
    assert fs.connect_pressures()
    assert [f.law.pressure for f in fs.fractures] == [5e6, 5e6, 5e6, 1e6]
    assert not fs.connect_pressures()            # connected already: nothing changes again


def test_a_tip_to_tip_pair_shares_its_pressure():
    """Tip to tip both ends record the other: either link alone connects."""
    for links in (((None, 1), (0, None)), ((None, 1), (None, None)), ((None, None), (0, None))):
        fs = FractureSet([dry([[0, 0], [1, 0]], 0.0, links[0]), dry([[1, 0], [2, 0.5]], 3e6, links[1]),
                          dry([[0, 1], [1, 1]], 0.0)])
        assert fs.connect_pressures()
        assert [f.law.pressure for f in fs.fractures] == [3e6, 3e6, 0.0]


def test_an_isolated_fracture_keeps_its_own_pressure():
    fs = FractureSet([dry([[0, 0], [1, 0]], 2e6), dry([[0, 1], [1, 1]], 0.0), dry([[0, 2], [1, 2]], 7.0)])
    assert not fs.connect_pressures()
    assert [f.law.pressure for f in fs.fractures] == [2e6, 0.0, 7.0]


# growth records what a joined end met (no solve: the candidate is given)
H = 0.1
DOMAIN = Domain("rectangle", corner=[-2.0, -2.0], size=[4.0, 4.0])


def grow_end_1_of_fracture_1(fs, L=H):
    """Fracture 1 runs along +x to its end 1 at (0, 0); it reaches KIc and
    grows straight on by L."""
    from wingcrack.propagation import growth

    c = growth.Candidate(0, 1, 1, 1.0, 0.0, np.array([1.0, 0.0]), np.array([0.0, 1.0]))
    rule = growth.Rule(KIc=1.0, Eprime=1.0, length=L, alpha=0.35, tip_size=H)
    return growth.grow(fs, [c], 1, rule, DOMAIN)


FAR = [[-1.5, 1.5], [-1.0, 1.5]]   # fracture 0, out of reach: the index found is not the first or the grower's


def test_a_wing_ending_on_a_fracture_records_it():
    """The tip's segment (0, 0) -> (0.1, 0) stretched by the reach crosses
    fracture 2 at x = 0.15: a T on fracture 2, whose tips are far and stay
    free."""
    fs = FractureSet([dry(FAR), dry([[-1, 0], [0, 0]], 1e6), dry([[0.15, -0.5], [0.15, 0.5]])])
    g = grow_end_1_of_fracture_1(fs)
    assert g.tips[0].state == "joined"
    np.testing.assert_allclose(fs.fractures[1].points[-1], [0.15, 0.0], atol=1e-12)
    assert [f.joined_to for f in fs.fractures] == [[None, None], [None, 2], [None, None]]
    assert [f.ends for f in fs.fractures] == [["tip", "tip"], ["tip", "joined"], ["tip", "tip"]]
    assert fs.connect_pressures() and [f.law.pressure for f in fs.fractures] == [0.0, 1e6, 1e6]


def test_a_wing_meeting_a_tip_records_both():
    """The step's end (0.1, 0) is 0.06 from fracture 2's free tip (0.1, 0.06),
    within the join distance 1.5 h: the two meet tip to tip, both ends
    stop, and each records the other."""
    fs = FractureSet([dry(FAR), dry([[-1, 0], [0, 0]]), dry([[0.1, 0.8], [0.1, 0.06]], 2e6)])
    g = grow_end_1_of_fracture_1(fs)
    assert g.tips[0].state == "joined"
    np.testing.assert_allclose(fs.fractures[1].points[-1], [0.1, 0.06], atol=1e-12)
    assert [f.joined_to for f in fs.fractures] == [[None, None], [None, 2], [None, 1]]
    assert [f.ends for f in fs.fractures] == [["tip", "tip"], ["tip", "joined"], ["tip", "joined"]]
    assert fs.connect_pressures() and [f.law.pressure for f in fs.fractures] == [0.0, 2e6, 2e6]


def test_a_join_moved_onto_a_nearer_tip_records_that_tip():
    """The crossing is on fracture 2 at (0.15, 0), but fracture 3's free tip
    (0.08, 0.1) lies within the join distance of it: the wing meets that tip
    instead, so it is linked to 3, not to 2, which it no longer touches."""
    fs = FractureSet([dry(FAR), dry([[-1, 0], [0, 0]]), dry([[0.15, -0.5], [0.15, 0.5]], 4e6),
                      dry([[0.05, 0.8], [0.08, 0.1]], 1e6)])
    g = grow_end_1_of_fracture_1(fs)
    assert g.tips[0].state == "joined"
    np.testing.assert_allclose(fs.fractures[1].points[-1], [0.08, 0.1], atol=1e-12)
    assert [f.joined_to for f in fs.fractures] == [[None, None], [None, 3], [None, None], [None, 1]]
    assert fs.connect_pressures() and [f.law.pressure for f in fs.fractures] == [0.0, 1e6, 4e6, 1e6]


def test_a_free_step_records_no_join():
    fs = FractureSet([dry(FAR), dry([[-1, 0], [0, 0]], 1e6), dry([[1.0, -0.5], [1.0, 0.5]])])
    g = grow_end_1_of_fracture_1(fs)
    assert g.tips[0].state == "growing" and [f.joined_to for f in fs.fractures] == [[None, None]] * 3
    assert not fs.connect_pressures()
