"""Issue 14 verification 4: friction remembers the load path.

A straight crack 2a on the x axis of a large plate, under a constant normal
compression sigma_n (the in-situ stress, which the load factor does not
scale) and a shear tau times the load factor (boundary tractions). Loaded
from zero to lam = 1 the faces slip forward under tau_eff = tau - c - mu
sigma_n, and carry the friction bound c + mu sigma_n. Unloading by d tau:
with the slip frozen (stick) the crack is welded for the increment, the
face traction falls by d tau uniformly, and the faces stick until it
reaches the bound the other way, d tau = 2 (c + mu sigma_n). Beyond that
they slip back, and superposing the two loadings (forward slip under
tau_eff, then back under d tau - 2 (c + mu sigma_n)):

    KII = (lam tau + c + mu sigma_n) sqrt(pi a),
    slip = 4 (lam tau + c + mu sigma_n) / E' sqrt(a^2 - x^2).

Each solve is one increment from the reference slip that accept() set
(Solver.solve / accept), the route the critical-load search takes.
"""
import numpy as np
import pytest

from builders import square_plate_with_cracks
from wingcrack.case import Case
from wingcrack import sifs
from wingcrack.contact.friction import SLIP, STICK
from wingcrack.face_values import face_values
from wingcrack.step import Timer, discretise

A, L, E, NU = 1.0, 100.0, 10e9, 0.25
SIGMA_N, TAU, MU, C = 1.0e6, 1.0e6, 0.5, 0.1e6
#: the load scale of the SIF tolerances
K_SCALE = TAU * np.sqrt(np.pi * A)
#: as in test_friction_plate: the issue's 0.5 % of the load scale, five times
#: the discretisation error of this mesh (plate side 100 a, tip_size 0.05 a)
K_TOL = 5e-3
SLIP_TOL = 1e-2


@pytest.fixture(scope="module")
def plate():
    d = square_plate_with_cracks(L, [[[-A, 0.0], [A, 0.0]]], (0.0, -SIGMA_N, 0.0), size=10 * A, tip_size=0.05 * A,
                                 nu=NU, plane="strain")
    d["material"]["E"] = E
    d["fractures"][0].update(faces="coulomb", friction=MU, cohesion=C)
    # shear tau on the four sides (traction sigma.n), scaled by the load factor
    d["bc"] += [{"on": "top", "traction": [TAU, 0.0]}, {"on": "bottom", "traction": [-TAU, 0.0]},
                {"on": "right", "traction": [0.0, TAU]}, {"on": "left", "traction": [0.0, -TAU]}]
    case = Case.from_dict(d)
    return case, discretise(case, case.fractures, Timer())


def _from_rest(disc):
    """The unloaded, unslipped state as the reference (the plate is shared)."""
    disc.contact.reference[:] = 0.0


def _state(case, disc, lam):
    disc.solver.solve(lam)
    tips = sifs.at_tips(case, disc, [f.points for f in case.fractures])
    fv = face_values(disc)
    pairs = np.asarray(disc.cm.pairs).reshape(-1, 2)
    x = np.asarray(disc.cm.x)[pairs[:, 0], 0]
    return tips, fv, x


def _e_prime():
    return E / (1 - NU ** 2)


def test_unloading_less_than_twice_the_bound_freezes_the_slip_and_more_slips_back(plate):
    case, disc = plate
    bound = C + MU * SIGMA_N
    _from_rest(disc)
    tips1, fv1, x = _state(case, disc, 1.0)
    slipping = fv1["state"] != 0
    assert np.all(fv1["state"][slipping] == SLIP) and slipping.sum() > 20
    KII1 = (TAU - bound) * np.sqrt(np.pi * A)
    for t in tips1:
        assert t.KI == pytest.approx(0.0, abs=K_TOL * K_SCALE)
        assert abs(t.KII) == pytest.approx(KII1, abs=K_TOL * K_SCALE)
    disc.solver.accept()
    s1 = fv1["jump"][:, 0].copy()   # [u].t along +x

    # unload by 0.9 of 2 (c + mu sigma_n): every pair sticks, the slip stays frozen
    lam2 = 1.0 - 0.9 * 2 * bound / TAU
    tips2, fv2, _ = _state(case, disc, lam2)
    closed = fv2["state"] != 0
    assert np.all(fv2["state"][closed] == STICK)
    # frozen to round-off: the increment is one dense solve on the pairs (1e-10 of the slip)
    np.testing.assert_allclose(fv2["jump"][:, 0], s1, atol=1e-10 * np.max(np.abs(s1)))
    for t1, t2 in zip(tips1, tips2):
        # correlation reads the frozen jump: the same KII; the interaction integral sees the welded
        # increment's uniform field, which has no singularity: the same KII within its accuracy
        assert t2.KII == pytest.approx(t1.KII, rel=1e-8)
        assert t2.KII_M == pytest.approx(t1.KII_M, abs=K_TOL * K_SCALE)

    # unload by 1.5 of 2 (c + mu sigma_n) (from the same converged state): the faces slip back
    lam3 = 1.0 - 1.5 * 2 * bound / TAU
    tips3, fv3, x = _state(case, disc, lam3)
    back = fv3["state"] == SLIP
    assert back.sum() == slipping.sum()
    assert np.all(fv3["slip_increment"][back] < 0)
    tau_eff = lam3 * TAU + bound   # signed as the first loading's shear (here < 0: the slip reversed)
    for t1, t in zip(tips1, tips3):
        assert t.KI == pytest.approx(0.0, abs=K_TOL * K_SCALE)
        assert t.KII * np.sign(t1.KII) == pytest.approx(tau_eff * np.sqrt(np.pi * A), abs=K_TOL * K_SCALE)
    middle = np.abs(x) <= A / 2
    ref = 4 * tau_eff / _e_prime() * np.sqrt(A ** 2 - x[middle] ** 2)
    np.testing.assert_allclose(fv3["jump"][middle, 0] * np.sign(s1[middle]), ref, rtol=SLIP_TOL)


def test_reverse_slip_starts_at_the_tips(plate):
    """Just past the threshold the faces next to the tips slip back first:
    there the stuck faces carry the most shear of the unloading."""
    case, disc = plate
    bound = C + MU * SIGMA_N
    _from_rest(disc)
    disc.solver.solve(1.0)
    disc.solver.accept()
    _, fv, x = _state(case, disc, 1.0 - 1.02 * 2 * bound / TAU)
    back = fv["state"] == SLIP
    closed = fv["state"] != 0
    assert back.any()
    outer = np.abs(x) >= np.sort(np.abs(x[closed]))[-2]   # the pairs nearest the two tips
    assert np.all(back[outer & closed])
