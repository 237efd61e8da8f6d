"""Issue 7.6: a fracture that cuts off a piece nothing holds makes the
stiffness matrix singular; the solve must say so (ComputationError naming
the reason), not return garbage. Reference: the same case with the cut
piece held too solves, with finite displacements."""
from dataclasses import replace

import numpy as np
import pytest

from wingcrack.api import _Timer, build
from wingcrack.case import Case
from wingcrack.errors import ComputationError


def plate(faces, hold_top):
    bc = [{"on": "bottom", "displacement": [0.0, 0.0]}, {"on": "top", "traction": [1e5, -1e5]}]
    if hold_top:
        bc.append({"at": [0.0, 1.0], "displacement": [0.0, 0.0]})
    return Case.from_dict({
        "title": "cut plate",
        "material": {"E": 1e10, "nu": 0.25, "KIc": 1e6},
        "domain": {"shape": "rectangle", "corner": [0.0, 0.0], "size": [1.0, 1.0]},
        "fractures": [{"points": [[0.3, 0.5], [0.7, 0.5]], "faces": faces}],
        "bc": bc,
        "mesh": {"size": 0.1, "tip_size": 0.02},
    })


@pytest.mark.parametrize("faces", ["open", "frictionless"])
def test_a_free_piece_is_reported(faces):
    for hold, ok in ((True, True), (False, False)):
        case = plate(faces, hold)
        cut = replace(case.fractures[0], points=np.array([[0.0, 0.5], [1.0, 0.5]]))  # side to side
        try:
            cm, problem, contact = build(case, [cut], _Timer())
            contact.solve(1.0)
            u = problem.u.x.array
            assert ok, "a free piece must not solve"
            assert np.all(np.isfinite(u))
        except ComputationError as err:
            assert not ok, err
            assert "singular" in str(err)
