"""Cohesion at zero normal stress: a horizontal crack (2a = 0.4 m, mu 0.5) under
pure shear tau of 1 MPa in a 2 m plate. Sliding on its whole length against a
uniform resisting traction c + mu sigma_n, the crack is the frictionless crack
under the shear tau - c - mu sigma_n (superposition: the uncut plate's stress is
uniform, which the P2 solution holds exactly), so KII = (tau - c - mu sigma_n)
sqrt(pi a) times the plate's own factor and the critical load factor is the
frictionless one plus (c + mu sigma_n) / tau. Before the touching tolerance the
faces, which the sliding opens by ~3e-4 of the slip on this mesh, were found
open: the run "finished" at the frictionless load (1.097 instead of 1.561), and
with c = 1e5 Pa and 1 kPa of compression the solve failed to converge."""
import meshio
import numpy as np
import pytest

import wingcrack
from wingcrack.case import Case

TAU = 1e6


def _case(cohesion, compression=0.0):
    d = {"title": "cohesion at zero normal stress",
         "material": {"E": 10e9, "nu": 0.25, "KIc": 1e6, "plane": "strain"},
         "domain": {"shape": "rectangle", "corner": [-1.0, -1.0], "size": [2.0, 2.0]},
         "fractures": [{"points": [[-0.2, 0.0], [0.2, 0.0]], "faces": "coulomb", "friction": 0.5,
                        "cohesion": cohesion}],
         "bc": [{"on": "top", "traction": [TAU, 0.0]}, {"on": "bottom", "traction": [-TAU, 0.0]},
                {"on": "right", "traction": [0.0, TAU]}, {"on": "left", "traction": [0.0, -TAU]},
                {"at": [-1.0, -1.0], "displacement": [0.0, 0.0]}, {"at": [1.0, -1.0], "displacement_y": 0.0}],
         "mesh": {"size": 0.2, "tip_size": 0.01}, "propagation": {"steps": 1, "length": 0.02}}
    if compression:
        d["stress"] = {"sxx": 0.0, "syy": -compression, "sxy": 0.0}
    return Case.from_dict(d)


def _critical(case, out):
    r = wingcrack.run(case, out=out, plots=False)
    faces = meshio.read(out / "faces_0000.vtu").point_data
    return r.steps[0]["load_factor"], faces["normal_traction"], faces["state"]


@pytest.fixture(scope="module")
def frictionless(tmp_path_factory):
    return _critical(_case(0.0), tmp_path_factory.mktemp("c0"))[0]


@pytest.mark.parametrize("cohesion", [1e4, 5e5])
def test_the_cohesion_shifts_the_critical_load_by_c_over_tau_at_zero_normal_stress(cohesion, frictionless, tmp_path):
    lam, tn, _ = _critical(_case(cohesion), tmp_path)
    # superposition is exact on this mesh; the critical-load search ends at K_eq = KIc to 1e-12
    assert lam == pytest.approx(frictionless + cohesion / TAU, rel=1e-9)


@pytest.mark.parametrize("compression", [1e3, 3e3])
def test_small_compressions_continue_it(compression, frictionless, tmp_path):
    cohesion = 1e5
    lam, tn, state = _critical(_case(cohesion, compression), tmp_path)
    # the friction part mu sigma_n uses the contact's own normal traction, which the sliding perturbs
    # (the plate's finite size): the shift is (c + mu sigma_n) / tau up to mu times that perturbation
    closed = tn < 0
    perturbation = np.max(np.abs(-tn[closed] - compression), initial=0.0)
    expected = frictionless + (cohesion + 0.5 * compression) / TAU
    assert abs(lam - expected) <= 0.5 * perturbation / TAU + 1e-9 * expected
    assert np.all(state[closed] != 0)
