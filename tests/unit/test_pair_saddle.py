"""fem.pair_saddle (each state set as one sparse saddle-point system, for pair
systems above solver.DENSE_ROWS) against the dense route (the pair compliance
from MUMPS's Schur complement) on the same meshes: two direct solves of the
same discrete contact problem, so the multipliers, the jumps, the states and
the SIFs agree to round-off. The shipped cases with contact of both kinds:
frictionless and prescribed slip, Coulomb with and without cohesion, a fluid
pressure."""
from pathlib import Path

import numpy as np
import pytest

import wingcrack.solver as solver
import wingcrack.step as step
from wingcrack.case import Case

CASES = Path(__file__).resolve().parents[2] / "cases"


@pytest.mark.parametrize("name", ["brazilian_disc_45_friction", "parallel_fractures_cohesion", "three_fractures_slip",
                                  "multi_fractures_friction"])
def test_the_saddle_route_is_the_dense_one(name, monkeypatch):
    case = Case.from_toml(CASES / f"{name}.toml")
    dense = step.solve_initial(case)
    monkeypatch.setattr(solver, "DENSE_ROWS", 0)
    sparse = step.solve_initial(case)
    assert sparse.contact.saddle is not None and dense.contact.saddle is None
    a, b = dense.contact.result, sparse.contact.result
    # MUMPS's Cholesky and Schur complement against its LU of the saddle system: pair systems of condition
    # ~1e4 to 1e6, so ~1e-12 of the force and jump scales (measured 1e-14 to 1.3e-12)
    np.testing.assert_allclose(b.forces, a.forces, rtol=0, atol=1e-10 * np.abs(a.forces).max())
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
    monkeypatch.setattr(solver, "DENSE_ROWS", 0)
    sparse = wingcrack.run(case, out=None, plots=False)
    # the search ends at K_eq = KIc to 1e-12 from either route's round-off-equal SIFs
    np.testing.assert_allclose([s["load_factor"] for s in sparse.steps], [s["load_factor"] for s in dense.steps],
                               rtol=1e-9)
    for p, q in zip(sparse.polylines, dense.polylines):
        np.testing.assert_allclose(p, q, rtol=0, atol=1e-9)


def test_a_set_near_the_factorised_one_is_solved_by_an_update_as_by_a_new_factorisation(monkeypatch):
    """The cohesion case's active set changes hundreds of rows, then a few: the last sets are solved
    through the factorisation kept (a rank-r update, fem.pair_saddle._updated). Against every set
    factorised anew (REUSE_ROWS = 0): two direct solves of the same systems, the same states, forces to
    round-off (the update's residual is checked against a direct solve's, UPDATE_RESIDUAL)."""
    from wingcrack.fem import pair_saddle

    case = Case.from_toml(CASES / "parallel_fractures_cohesion.toml")
    monkeypatch.setattr(solver, "DENSE_ROWS", 0)
    kept = step.solve_initial(case)
    monkeypatch.setattr(pair_saddle, "REUSE_ROWS", 0)
    anew = step.solve_initial(case)
    s, t = kept.contact.saddle, anew.contact.saddle
    assert s.updates >= 1 and s.factorisations < t.factorisations and t.updates == 0
    a, b = anew.contact.result, kept.contact.result
    np.testing.assert_array_equal(b.state, a.state)
    np.testing.assert_allclose(b.forces, a.forces, rtol=0, atol=1e-10 * np.abs(a.forces).max())
    np.testing.assert_allclose(b.jump, a.jump, rtol=0, atol=1e-10 * np.abs(a.jump).max())


class _Factor:
    def __init__(self, infog):
        self.infog = infog

    def getMumpsInfog(self, i):
        return self.infog.get(i, 0)


class _Ksp:
    def __init__(self, infog):
        self.factor = _Factor(infog)

    def getPC(self):
        return self

    def getFactorMatrix(self):
        return self.factor


def test_a_factorisation_that_runs_out_of_memory_says_so():
    """MUMPS's INFOG(1) read for the user: memory (with the analysis's estimate), singular, other."""
    from types import SimpleNamespace

    from wingcrack.fem.pair_saddle import _factor_failure

    err = SimpleNamespace(ierr=76)
    text = _factor_failure(_Ksp({1: -13, 2: 123456, 17: 20480}), err)
    assert text.startswith("contact: out of memory") and "about 20.0 GB" in text and "PETSc" not in text
    assert "singular" in _factor_failure(_Ksp({1: -10}), err)
    assert "MUMPS error -5" in _factor_failure(_Ksp({1: -5}), err)


def test_the_saddle_routes_problem_of_some_rows_is_the_dense_one(monkeypatch):
    """PairSaddle.respond (the rows y free, every other row held in its state: their free jumps and
    compliance, for by_sets._cycling_rows) against the same from the dense pair compliance S
    (contact.friction's set solve with y open, a unit force on each row of y): two direct routes to
    one linear map, equal to round-off (the pair system's condition ~1e5: 1e-9 is far above it)."""
    import dataclasses

    from wingcrack.contact.friction import OPEN, SLIP, STICK
    from wingcrack.contact.friction_problem import PairProblem
    from wingcrack.contact.friction_sets import solve_state_set

    case = Case.from_toml(CASES / "multi_fractures_friction.toml")
    dense = step.solve_initial(case)
    monkeypatch.setattr(solver, "DENSE_ROWS", 0)
    sparse = step.solve_initial(case)
    res, rows = dense.contact.result, dense.contact.rows
    law, S, target = rows.friction_law(), dense.contact.op.S, res.reference
    A = rows.normal & res.active
    T = np.where(rows.coulomb, res.state, OPEN).astype(np.int8)
    sign = np.where(T == SLIP, np.sign(-res.forces), 0.0)
    C = np.asarray(res.cohesive, bool)
    closed = np.flatnonzero(A)[:3]                       # three closed pairs: their normal and Coulomb rows
    y = np.zeros(len(rows), bool)
    y[closed] = True
    y[np.isin(law.partner, closed) & rows.coulomb] = True
    assert y.sum() == 6 and np.any(T[~y] == SLIP) and np.any(T[~y] == STICK)
    P = PairProblem.of(S, res.jump0, target, rows.normal, ~rows.normal & ~rows.coulomb, law, None)
    A0, T0, s0 = A & ~y, np.where(y, OPEN, T).astype(np.int8), np.where(y, 0.0, sign)

    def jumps(j0):
        mu, _ = solve_state_set(dataclasses.replace(P, jump0=j0), A0, T0, s0, C)
        return (j0 + S @ mu)[y]

    base = jumps(res.jump0)
    S_y = np.stack([jumps(res.jump0 + S[:, k]) - base for k in np.flatnonzero(y)], axis=1)
    eq = (rows.normal & A) | (~rows.normal & ~rows.coulomb) | (T == STICK)
    j_s, S_s = sparse.contact.saddle.respond(eq, T == SLIP, sign, law.friction,
                                             np.where(C, law.cohesion_force, 0.0), target, sparse.problem.b, y)
    np.testing.assert_allclose(j_s, base, rtol=0, atol=1e-9 * np.abs(res.jump0).max())
    np.testing.assert_allclose(S_s, S_y, rtol=0, atol=1e-9 * np.abs(S_y).max())


def test_the_saddle_system_is_ordered_as_asked(monkeypatch):
    """MUMPS analyses the saddle system with the ordering pair_saddle.ORDERING names (approximate minimum
    fill, 2): PETSc 3.18 reads ICNTL(7) from the options database at the analysis, over what
    MatMumpsSetIcntl set, so a value given the other way is silently replaced by MUMPS's own choice.
    Asked for plain AMD (0) instead, MUMPS reports AMD (INFOG(7)): the setting reaches it; and the
    option is gone from the database afterwards."""
    from petsc4py import PETSc

    from wingcrack.fem import pair_saddle

    assert pair_saddle.ORDERING == 2
    monkeypatch.setattr(solver, "DENSE_ROWS", 0)
    case = Case.from_toml(CASES / "three_fractures_friction.toml")
    for ordering in (2, 0):
        monkeypatch.setattr(pair_saddle, "ORDERING", ordering)
        F = step.solve_initial(case).contact.saddle.ksp.getPC().getFactorMatrix()
        assert F.getMumpsInfog(7) == ordering
        assert not PETSc.Options().hasName(pair_saddle._PREFIX + "factor_mat_mumps_icntl_7")


def test_the_trial_start_ends_where_the_sticking_start_does_on_a_network(monkeypatch):
    """The saddle route's first set (contact.by_sets: the trial states of the jumps without pair forces)
    against its old start (every closed pair sticking) on a network of 30 Coulomb fractures under
    compression (benchmarks/grid_network.py's layout): the same forces and jumps to round-off (two direct
    solves of the same final set: measured 5e-12), the same states but at pairs on the bound, whose force
    the two solves give to ~1e-10 of the largest: there the label (contact.friction_problem._labels, at
    the bound to 1e-9 of the pair's own bound) is round-off's (measured: two slipping pairs 2e-9 below the
    bound after the old start, named sticking). The trial start's answer holds the law."""
    import sys

    sys.path.insert(0, str(CASES.parent / "benchmarks"))
    import grid_network

    import wingcrack.contact.by_sets as by_sets
    from wingcrack.contact import friction_sets
    from wingcrack.contact.friction import SLIP, STICK

    case = Case.from_dict(grid_network.coulomb(grid_network.case(30)))
    monkeypatch.setattr(solver, "DENSE_ROWS", 0)
    trial = step.solve_initial(case).contact.result
    iterate = friction_sets.iterate_states
    monkeypatch.setattr(by_sets, "iterate_states", lambda *a, **k: iterate(*a, **{**k, "trial": False}))
    sticking = step.solve_initial(case).contact.result
    assert np.sum(trial.state == SLIP) > 100 and np.sum(trial.state == STICK) > 100 and not trial.fallback
    np.testing.assert_allclose(trial.forces, sticking.forces, rtol=0, atol=1e-10 * np.abs(sticking.forces).max())
    jscale = max(np.abs(sticking.jump0).max(), np.abs(sticking.jump).max())
    np.testing.assert_allclose(trial.jump, sticking.jump, rtol=0, atol=1e-10 * jscale)
    np.testing.assert_array_equal(trial.active, sticking.active)
    differ = np.flatnonzero(trial.state != sticking.state)
    at_bound = np.abs(np.abs(sticking.forces) - sticking.bound()) <= 1e-8 * np.abs(sticking.forces).max()
    assert len(differ) <= 4 and np.all(at_bound[differ])
    # the law's residuals, relative to the largest traction and to the jump scale: round-off of the solves
    assert max(trial.friction_residuals(np.ones(len(trial.forces))).values()) < 1e-8
