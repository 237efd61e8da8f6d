"""Contact at a T-junction (a wing that joined another fracture): the
junction node has three copies and three pairs (two on the host, one on the
wing), and the rows must stay consistent.

Reference: under hydrostatic in-situ compression -S every plane carries the
normal stress -S and no shear, so with frictionless closed faces the cracked
body behaves as the uncracked one: the perturbation displacement is zero,
every pair is closed, the contact pressure is S on every face of both
fractures, and KI = KII = 0 at the free tips.
"""
from dataclasses import replace

import numpy as np
import pytest

from builders import square_plate_with_cracks
from wingcrack.step import Timer, discretise
from wingcrack.case import Case
from wingcrack.fem.nodal import nodal_displacements

L, S = 10.0, 1.0e6


@pytest.mark.parametrize("angle", [90.0, 60.0])
def test_closed_t_junction_under_hydrostatic_compression(angle):
    host = np.array([[-1.0, 0.0], [1.0, 0.0]])
    a = np.radians(angle)
    wing = np.array([[0.2 + 0.8 * np.cos(a), 0.8 * np.sin(a)], [0.2, 0.0]])
    d = square_plate_with_cracks(L, [host], (-S, -S, 0.0), size=1.0, tip_size=0.05)
    d["fractures"][0]["faces"] = "frictionless"
    case = Case.from_dict(d)
    fractures = [case.fractures[0], replace(case.fractures[0], points=wing)]
    disc = discretise(case, fractures, Timer())
    cm, problem, contact = disc.cm, disc.problem, disc.contact
    junction = np.flatnonzero(np.linalg.norm(cm.x - wing[-1], axis=1) < 1e-14)
    assert len(junction) == 3
    contact.solve(1.0)
    res = contact.result
    assert res.active.all(), "every face closed"
    # the junction's three pairs all carry a normal row
    at = np.isin(contact.rows.plus, junction) & np.isin(contact.rows.minus, junction)
    assert at.sum() == 3
    x = np.asarray(cm.x)
    u = nodal_displacements(problem.fm, problem.u, np.arange(len(x)))
    # zero up to round-off of a solve whose loads are ~S L / E ~ 1e-3 m:
    # 1e-12 of that scale (measured ~1e-16)
    assert np.abs(u).max() < 1e-12 * S * L / case.material.E
    # pressure S within 1e-8 everywhere, the junction included (the exact
    # solution is in the discrete space: uniform stress, zero displacement)
    np.testing.assert_allclose(contact.normal_traction(), -S, rtol=1e-8)
    for t in disc.sifs(case, [f.points for f in fractures]):
        assert abs(t.KI) < 1e-8 * S and abs(t.KII) < 1e-8 * S


def test_closed_fractures_met_end_to_end_under_hydrostatic_compression():
    """Two fractures linked end to end (a wing that reached another's tip):
    the meeting node has two copies shared by both fractures' faces: one
    pair, with a normal row for each fracture (the copies must not overlap
    across either face; parallel normals would repeat each other and give
    one row); the hydrostatic reference holds as for the T."""
    a = np.array([[-1.0, 0.0], [0.2, 0.0]])
    b = np.array([[0.2, 0.0], [0.9, 0.5]])
    d = square_plate_with_cracks(L, [a], (-S, -S, 0.0), size=1.0, tip_size=0.05)
    d["fractures"][0]["faces"] = "frictionless"
    case = Case.from_dict(d)
    disc = discretise(case, [case.fractures[0], replace(case.fractures[0], points=b)], Timer())
    cm, problem, contact = disc.cm, disc.problem, disc.contact
    meet = np.flatnonzero(np.linalg.norm(cm.x - a[-1], axis=1) < 1e-14)
    assert len(meet) == 2 and len(cm.tips) == 2
    rows_here = np.isin(contact.rows.plus, meet) & np.isin(contact.rows.minus, meet)
    assert rows_here.sum() == 2
    contact.solve(1.0)
    assert contact.result.active.all()
    u = nodal_displacements(problem.fm, problem.u, np.arange(len(cm.x)))
    assert np.abs(u).max() < 1e-12 * S * L / case.material.E
    np.testing.assert_allclose(contact.normal_traction(), -S, rtol=1e-8)


def test_a_join_next_to_a_growing_tip_links_the_two():
    """The loop's rule: a join point within reach of another fracture's tip
    moves onto that tip, and both ends stop ('joined')."""
    from wingcrack.face_law import FaceLaw
    from wingcrack.propagation.fracture_set import FractureSet, GrowingFracture
    from wingcrack.propagation.growth import meet_tip_to_tip

    def frac(p):
        return GrowingFracture(np.array(p, float), (0, 1), ["tip", "tip"], FaceLaw("open"))

    fset = FractureSet([frac([[0, 0], [1, 0]]), frac([[1.05, 0.5], [1.02, 0.04]])])
    p, met = meet_tip_to_tip(fset, 0, np.array([1.0, 0.03]), reach=0.075)
    np.testing.assert_array_equal(p, [1.02, 0.04])
    assert met == 1
    assert fset.fractures[1].ends == ["tip", "joined"] and fset.fractures[1].joined_to == [None, 0]
    q, met = meet_tip_to_tip(fset, 0, np.array([0.5, 0.3]), reach=0.075)   # far from any tip: unchanged
    np.testing.assert_array_equal(q, [0.5, 0.3])
    assert met is None


def test_a_kink_folding_back_onto_its_own_crack_is_not_a_join():
    """A wing that turns back onto its own crack would enclose a piece of the
    body that nothing holds (soak seed 72 failed 'singular' so): such a join
    point is recognised, and the loop leaves the tip where it is."""
    from wingcrack.face_law import FaceLaw
    from wingcrack.propagation.fracture_set import GrowingFracture
    from wingcrack.propagation.growth import on_own_fracture

    f = GrowingFracture(np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 0.1], [0.9, 0.1]]), (0, 1), ["tip", "tip"],
                        FaceLaw("open"))
    assert on_own_fracture(f, 1, np.array([0.95, 0.0]))        # back on its own first segment
    assert not on_own_fracture(f, 1, np.array([0.85, 0.3]))    # free space


@pytest.mark.parametrize("angle", [90.0, 60.0])
def test_closed_coulomb_t_junction_is_not_singular(angle):
    """The same T with Coulomb faces (wing included): the junction's three
    pairs have two independent jumps (the wing's is the difference of the
    host's two), so they keep their normal rows only (with tangential rows
    too the pair system was singular once all were closed: the network case
    failed so; with the wing's pair dropped instead its faces interpenetrated
    at the junction, 3.6e-6 m here, while the host's pairs slipped).
    Hydrostatic compression: every pair closed, no displacement, the contact
    pressure S, no shear."""
    host = np.array([[-1.0, 0.0], [1.0, 0.0]])
    a = np.radians(angle)
    wing = np.array([[0.2 + 0.8 * np.cos(a), 0.8 * np.sin(a)], [0.2, 0.0]])
    d = square_plate_with_cracks(L, [host], (-S, -S, 0.0), size=1.0, tip_size=0.05)
    d["fractures"][0].update(faces="coulomb", friction=0.6)
    case = Case.from_dict(d)
    fractures = [case.fractures[0], replace(case.fractures[0], points=wing)]
    disc = discretise(case, fractures, Timer())
    cm, problem, contact = disc.cm, disc.problem, disc.contact
    junction = np.flatnonzero(np.linalg.norm(cm.x - wing[-1], axis=1) < 1e-14)
    rows = contact.rows
    at = np.isin(rows.plus, junction) & np.isin(rows.minus, junction)
    assert at.sum() == 3 and rows.normal[at].all()   # the three pairs' normal rows, no tangential
    np.linalg.cholesky(contact.op.S)   # SPD: no dependent rows
    res = contact.solve(1.0)
    assert res.active[rows.normal].all() and not res.fallback
    x = np.asarray(cm.x)
    u = nodal_displacements(problem.fm, problem.u, np.arange(len(x)))
    assert np.abs(u).max() < 1e-12 * S * L / case.material.E
    t = contact.tractions()
    np.testing.assert_allclose(t[rows.normal], -S, rtol=1e-8)
    assert np.abs(t[~rows.normal]).max() < 1e-8 * S


@pytest.mark.parametrize("faces", ["frictionless", "coulomb"])
def test_closed_x_of_pre_existing_fractures_under_hydrostatic_compression(faces):
    """Two pre-existing fractures crossing (an X, as the case gives them):
    the crossing node has four copies and four pairs (one per half-edge),
    whose jumps have three independent components per direction (they sum
    to zero around the node); the rows there are the four normal rows only
    (junction pairs: Coulomb keeps no tangential row) and independent: the
    rows' direction matrix on the copies has rank 4 and the pair system is
    SPD. Hydrostatic compression: every pair closed, no displacement, the
    contact pressure S, no shear (the uncracked plate's solution)."""
    a = np.array([[-1.0, 0.1], [1.0, 0.1]])
    b = np.array([[-0.3, -0.8], [0.4, 1.0]])
    d = square_plate_with_cracks(L, [a, b], (-S, -S, 0.0), size=1.0, tip_size=0.05)
    for f in d["fractures"]:
        f.update(faces=faces, **({"friction": 0.6} if faces == "coulomb" else {}))
    case = Case.from_dict(d)
    assert len(case.tips()) == 4
    disc = discretise(case, case.fractures, Timer())
    cm, problem, contact = disc.cm, disc.problem, disc.contact
    from meshing import admissibility

    (x,) = admissibility.joined(case.domain, case.fracture_points()).node_points()
    node = np.flatnonzero(np.all(cm.x == x, axis=1))
    assert len(node) == 4
    rows = contact.rows
    at = np.isin(rows.plus, node) & np.isin(rows.minus, node)
    assert at.sum() == 4 and rows.normal[at].all()
    # the rows' directions on the 8 dofs of the four copies: rank 4 (independent)
    M = np.zeros((at.sum(), 8))
    for r, k in enumerate(np.flatnonzero(at)):
        i, j = list(node).index(rows.plus[k]), list(node).index(rows.minus[k])
        M[r, 2 * i:2 * i + 2] += rows.direction[k]
        M[r, 2 * j:2 * j + 2] -= rows.direction[k]
    assert np.linalg.matrix_rank(M) == 4
    np.linalg.cholesky(contact.op.S)   # SPD: no dependent rows anywhere
    res = contact.solve(1.0)
    assert res.active[rows.normal].all() and not res.fallback
    u = nodal_displacements(problem.fm, problem.u, np.arange(len(cm.x)))
    # the exact solution (uniform stress, zero displacement) is in the discrete
    # space: zero to round-off, 1e-12 of the load's scale S L / E (measured ~1e-16)
    assert np.abs(u).max() < 1e-12 * S * L / case.material.E
    t = contact.tractions()
    np.testing.assert_allclose(t[rows.normal], -S, rtol=1e-8)
    assert np.abs(t[~rows.normal]).max(initial=0.0) < 1e-8 * S
    for tip in disc.sifs(case, case.fracture_points()):
        assert abs(tip.KI) < 1e-8 * S and abs(tip.KII) < 1e-8 * S
