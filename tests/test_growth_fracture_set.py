"""The fracture records of a run (wingcrack/propagation/fracture_set.py):
what they take from the case and what their wings get (issue 14: friction
on every face, the wings included)."""
import numpy as np
import pytest

from wingcrack.case import Case
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
    got = [(f.faces, f.friction, f.cohesion, f.gap) for f in fset.fractures]
    assert got == [("coulomb", 0.6, 2.0e5, 1e-6), ("frictionless", 0.0, 0.0, 0.0), ("slip", 0.0, 0.0, 0.0),
                   ("open", 0.0, 0.0, 0.0), ("coulomb", 0.0, 0.0, 0.0)]


def test_wings_of_a_coulomb_fracture_are_coulomb_with_its_law(fset):
    """The wing's law is read from the same record (constraint_rows._part
    gives a wing fracture.wing_faces() and the fracture's own friction and
    cohesion), so a coulomb fracture's wings rub with its mu and c; the
    others keep the paper's rule: open stays open, contact becomes
    frictionless, a prescribed slip never reaches a wing."""
    assert [f.wing_faces() for f in fset.fractures] == ["coulomb", "frictionless", "frictionless", "open", "coulomb"]


def test_a_grown_copy_keeps_the_law(fset):
    g = fset.copy()
    g.fractures[0].extend(1, [1.1, 0.9])
    assert g.fractures[0].pre == (0, 1) and len(g.fractures[0].points) == 3
    assert (g.fractures[0].friction, g.fractures[0].cohesion, g.fractures[0].wing_faces()) == (0.6, 2.0e5, "coulomb")
    assert len(fset.fractures[0].points) == 2   # the copy is its own


def test_a_record_built_without_a_law_is_frictionless():
    """Callers that predate friction build records positionally: mu = c = 0."""
    f = GrowingFracture(np.array([[0.0, 0.0], [1.0, 0.0]]), (0, 1), ["tip", "tip"], "frictionless", 0.0, 0.0,
                        "uniform", True)
    assert (f.friction, f.cohesion, f.wing_faces()) == (0.0, 0.0, "frictionless")
