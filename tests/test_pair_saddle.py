"""fem.pair_saddle (each state set as one sparse saddle-point system, for pair
systems above step.DENSE_ROWS) against the dense route (the pair compliance
from MUMPS's Schur complement) on the same meshes: two direct solves of the
same discrete contact problem, so the multipliers, the jumps, the states and
the SIFs agree to round-off. The shipped cases with contact of both kinds:
frictionless and prescribed slip, Coulomb with and without cohesion, a fluid
pressure."""
from pathlib import Path

import numpy as np
import pytest

import wingcrack.step as step
from wingcrack.case import Case

CASES = Path(__file__).resolve().parents[1] / "cases"


@pytest.mark.parametrize("name", ["brazilian_disc_45_friction", "parallel_fractures_cohesion", "three_fractures_slip",
                                  "multi_fractures_friction"])
def test_the_saddle_route_is_the_dense_one(name, monkeypatch):
    case = Case.from_toml(CASES / f"{name}.toml")
    dense = step.solve_initial(case)
    monkeypatch.setattr(step, "DENSE_ROWS", 0)
    sparse = step.solve_initial(case)
    assert sparse.contact.saddle is not None and dense.contact.saddle is None
    a, b = dense.contact.result, sparse.contact.result
    # MUMPS's Cholesky and Schur complement against its LU of the saddle system: pair systems of condition
    # ~1e4 to 1e6, so ~1e-12 of the force and jump scales (measured 1e-14 to 1.3e-12)
    np.testing.assert_allclose(b.mu, a.mu, rtol=0, atol=1e-10 * np.abs(a.mu).max())
    jscale = max(np.abs(a.jump0).max(), np.abs(a.jump).max())
    np.testing.assert_allclose(b.jump, a.jump, rtol=0, atol=1e-10 * jscale)
    if getattr(a, "state", None) is not None:
        np.testing.assert_array_equal(b.state, a.state)
    np.testing.assert_array_equal(b.active, a.active)
    ka = np.array([[t.KI, t.KII, t.KI_M, t.KII_M] for t in dense.tips], float)
    kb = np.array([[t.KI, t.KII, t.KI_M, t.KII_M] for t in sparse.tips], float)
    np.testing.assert_allclose(kb, ka, rtol=0, atol=1e-10 * max(np.abs(ka).max(), 1.0))
    ua, ub = dense.problem.u.x.array, sparse.problem.u.x.array
    np.testing.assert_allclose(ub, ua, rtol=0, atol=1e-10 * np.abs(ua).max())


def test_a_run_through_the_saddle_route_grows_as_the_dense_one(monkeypatch, tmp_path):
    """Three steps of the frictionless five-fracture case (a critical-load search a step, remeshing):
    the same load factors and tip positions."""
    from dataclasses import replace

    import wingcrack

    case = Case.from_toml(CASES / "multi_fractures_shear.toml")
    case = replace(case, propagation=replace(case.propagation, steps=3))
    dense = wingcrack.run(case, out=None, plots=False)
    monkeypatch.setattr(step, "DENSE_ROWS", 0)
    sparse = wingcrack.run(case, out=None, plots=False)
    # the search ends at K_eq = KIc to 1e-12 from either route's round-off-equal SIFs
    np.testing.assert_allclose([s["load_factor"] for s in sparse.steps], [s["load_factor"] for s in dense.steps],
                               rtol=1e-9)
    for p, q in zip(sparse.polylines, dense.polylines):
        np.testing.assert_allclose(p, q, rtol=0, atol=1e-9)
