"""Issue 7.6: a fracture that cuts off a piece nothing holds makes the
stiffness matrix singular; the solve must say so (ComputationError naming
the reason and the piece), not return garbage.

Reference: the same plate with the cut-off top piece held (pinned at one top
corner, held vertically at the other) solves with displacements of the size
elasticity gives: traction 1e5 Pa on a 1 m plate with E = 1e10 Pa strains it
by ~1e-5, and the top piece bends on its two supports: measured 5.0e-5 m
(open) and 5.6e-5 m (frictionless); the bound 1e-3 m is 20x that and still
twelve orders below a free mode's ~1e9 m (as a
top piece pinned at one corner only did before wingcrack.free_pieces: the
factorisation's null-pivot test missed its rotation). A piece held by its
faces' contact is solved through the contact problem (wingcrack.floating,
tests/verification/test_floating_pieces.py); here: frictionless faces under the top's
shear let the free top piece slide, which is reported as the mechanism it is,
and pinned at one corner it is held by the pin and the contact."""
from dataclasses import replace

import numpy as np
import pytest

from wingcrack.step import Timer, discretise
from wingcrack.case import Case
from wingcrack.errors import ComputationError

U_BOUND = 1e-3  # m: elastic response 5e-5 here (see above), a free mode ~1e9


def plate(faces, pins):
    bc = [{"on": "bottom", "displacement": [0.0, 0.0]}, {"on": "top", "traction": [1e5, -1e5]}]
    if pins >= 1:
        bc.append({"at": [0.0, 1.0], "displacement": [0.0, 0.0]})
    if pins >= 2:
        bc.append({"at": [1.0, 1.0], "displacement_y": 0.0})
    return Case.from_dict({
        "title": "cut plate",
        "material": {"E": 1e10, "nu": 0.25, "KIc": 1e6},
        "domain": {"shape": "rectangle", "corner": [0.0, 0.0], "size": [1.0, 1.0]},
        "fractures": [{"points": [[0.3, 0.5], [0.7, 0.5]], "faces": faces}],
        "bc": bc,
        "mesh": {"size": 0.1, "tip_size": 0.02},
    })


def solve_cut(case):
    cut = replace(case.fractures[0], points=np.array([[0.0, 0.5], [1.0, 0.5]]))  # side to side
    d = discretise(case, [cut], Timer())
    d.solver.solve(1.0)
    return d.problem.u.x.array


@pytest.mark.parametrize("faces", ["open", "frictionless"])
def test_a_held_piece_solves(faces):
    u = solve_cut(plate(faces, pins=2))
    assert np.all(np.isfinite(u)) and 0.0 < np.abs(u).max() < U_BOUND


@pytest.mark.parametrize("pins, motion", [(0, "is not held at all"), (1, "can rotate about the point")])
def test_a_free_piece_is_reported(pins, motion):
    with pytest.raises(ComputationError, match="singular") as err:
        solve_cut(plate("open", pins))
    assert motion in str(err.value) and "(0.5, 0.75)" in str(err.value)  # the top piece
    assert "no contact either" in str(err.value)


def test_a_free_piece_on_frictionless_faces_under_shear_slides():
    with pytest.raises(ComputationError, match=r"the piece around \(0.5, 0.75\) slides along fracture 0"):
        solve_cut(plate("frictionless", pins=0))


def test_a_piece_pinned_at_one_corner_is_held_by_its_contact():
    u = solve_cut(plate("frictionless", pins=1))
    assert np.all(np.isfinite(u)) and 0.0 < np.abs(u).max() < U_BOUND
