"""Issue 4 tests 1, 2 and 7: closed frictionless cracks under compression
(paper sections 2.1, 3.1: KKT non-penetration by an active set)."""
import numpy as np
import pytest

from builders import square_plate_with_cracks
from wingcrack.step import solve_initial
from wingcrack.case import Case
from wingcrack.fem.nodal import nodal_displacements

A, L, SIGMA, E, NU = 1.0, 100.0, 1.0e6, 10e9, 0.25


def plate(cracks, faces="frictionless", sigma0=(0.0, 0.0, 0.0), extra_bc=(), gap=0.0, **kw):
    d = square_plate_with_cracks(L, cracks, sigma0, size=10 * A, tip_size=0.05 * A, **kw)
    for f in d["fractures"]:
        f["faces"] = faces
        if gap:
            f["gap"] = gap
    d["bc"] += list(extra_bc)
    return Case.from_dict(d)


def test_closed_crack_normal_compression_is_the_uncracked_solution():
    """Compression normal to a closed crack: the crack transmits it as if it
    were not there. Uncracked plane-strain solution under syy = -sigma is
    linear, so P2 reproduces it to round-off: 1e-8 relative is met with
    room (measured 1e-13). Pressure: uniform, = sigma (0.5%)."""
    case = plate([[[-A, 0.0], [A, 0.0]]],
                 extra_bc=[{"on": "top", "traction": [0.0, -SIGMA]}, {"on": "bottom", "traction": [0.0, SIGMA]}])
    sol = solve_initial(case)
    res = sol.contact.result
    assert res.active.all(), "every pair closed"
    x = np.asarray(sol.cm.x)
    u = nodal_displacements(sol.problem.fm, sol.problem.u, np.arange(len(x)))
    eyy, exx = -(1 - NU ** 2) / E * SIGMA, NU * (1 + NU) / E * SIGMA
    exact = np.c_[exx * (x[:, 0] + L / 2), eyy * (x[:, 1] + L / 2)]   # pinned at (-L/2, -L/2)
    assert np.abs(u - exact).max() < 1e-8 * np.abs(exact).max()
    k = SIGMA * np.sqrt(np.pi * A)
    for t in sol.tips:
        for v in (t.KI, t.KII, t.KI_M, t.KII_M):
            assert abs(v) < 1e-6 * k
    tn = sol.contact.normal_traction()
    assert np.allclose(tn, -SIGMA, rtol=5e-3)


@pytest.mark.parametrize("beta", [30, 45, 60])
def test_inclined_closed_crack(beta):
    """Remote uniaxial compression -sigma at beta to the crack, frictionless
    closed faces: no opening (KI = 0), the shear is not carried:
    |KII| = sigma sqrt(pi a) sin b cos b, and the faces carry the normal
    stress -sigma sin^2 b. Tolerances: 0.5% of sigma sqrt(pi a) for K (as
    for the open Griffith crack), 1% for the traction away from the tips
    (|s| < 0.8 a; P2 traction recovery near the tips is not meant)."""
    b = np.radians(beta)
    t = np.array([np.sin(b), np.cos(b)])
    case = plate([[-A * t, A * t]], sigma0=(0.0, -SIGMA, 0.0))
    sol = solve_initial(case)
    k = SIGMA * np.sqrt(np.pi * A)
    KII = -SIGMA * np.sqrt(np.pi * A) * np.sin(b) * np.cos(b)   # sign in the contract frame
    for tip in sol.tips:
        assert abs(tip.KI) < 5e-3 * k and abs(tip.KI_M) < 5e-3 * k
        assert abs(tip.KII - KII) < 5e-3 * k and abs(tip.KII_M - KII) < 5e-3 * k
        assert abs(np.degrees(tip.theta) - np.sign(-KII) * 70.5288) < 0.5
    rows = sol.contact.rows
    away = np.linalg.norm(rows.position, axis=1) < 0.8 * A
    tn = sol.contact.normal_traction()[away]
    assert np.allclose(tn, -SIGMA * np.sin(b) ** 2, rtol=1e-2)


def test_open_faces_give_the_foundation_result():
    """faces = "open" adds no constraint row: the contact layer returns the
    plain elastic solve. And frictionless faces that the load opens (tension)
    give that same open-face result: the active set is empty and the pair
    forces are zero (1e-12 relative: round-off of the Schur solve)."""
    t = np.array([np.sin(0.7), np.cos(0.7)])
    sol_open = solve_initial(plate([[-A * t, A * t]], faces="open", sigma0=(0.0, SIGMA, 0.0)))
    assert len(sol_open.contact.rows) == 0 and sol_open.contact.result is None
    u_open = sol_open.problem.u.x.array.copy()
    sol_open.problem.solve(1.0)   # the foundation's plain solve on the same mesh
    assert np.array_equal(sol_open.problem.u.x.array, u_open)

    sol_fr = solve_initial(plate([[-A * t, A * t]], faces="frictionless", sigma0=(0.0, SIGMA, 0.0)))
    assert not sol_fr.contact.result.active.any()
    u_fr = sol_fr.problem.u.x.array
    assert np.abs(u_fr - u_open).max() < 1e-12 * np.abs(u_open).max()
    for a, b in zip(sol_open.tips, sol_fr.tips):
        assert abs(a.KI - b.KI) < 1e-10 * abs(a.KI)

    comp = solve_initial(plate([[-A * t, A * t]], faces="open", sigma0=(0.0, -SIGMA, 0.0)))
    assert comp.tips[0].KI < 0, "open faces interpenetrate under compression"
