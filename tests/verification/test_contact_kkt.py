"""Issue 4 test 5: KKT conditions on every case in cases/ with contact, and
the active set does not depend on where the iteration starts."""
from pathlib import Path

import numpy as np
import pytest

from wingcrack.step import solve_initial
from wingcrack.case import Case
from wingcrack.contact.active_set import solve_active_set
from wingcrack.contact.friction import fixed_point_solve

CASES = sorted(p for p in (Path(__file__).parents[2] / "cases").glob("*.toml")
               if any(f.faces != "open" for f in Case.from_toml(p).fractures))


@pytest.mark.parametrize("path", CASES, ids=lambda p: p.stem)
def test_kkt_and_initial_guess(path):
    sol = solve_initial(Case.from_toml(path))
    res, rows, op = sol.contact.result, sol.contact.rows, sol.contact.op
    # feasibility (w + g >= 0), sign (mu >= 0) and complementarity (mu (w+g)
    # = 0) to 1e-8 of the load scale: the active set is exact, so only the
    # round-off of the small dense solve remains
    for name, value in res.kkt_residuals(rows.gap, rows.normal).items():
        assert value < 1e-8, (name, value)
    if rows.coulomb.any():
        # the friction law to the same 1e-8, and the second method (the fixed point of Tresca
        # problems; without cohesion there is one solution) gives the same forces
        for name, value in res.friction_residuals(rows.weight).items():
            assert value < 1e-8, (name, value)
        if rows.cohesion.any():
            return   # cohesion: a pair may touch and hold c or be open, both lawful (tests/verification/test_friction_solver.py)
        other = fixed_point_solve(op.S, res.jump0, res.reference, rows.normal, ~rows.normal & ~rows.coulomb,
                             rows.friction_law(), [])
        np.testing.assert_array_equal(other.state, res.state)
        assert np.allclose(other.forces, res.forces, rtol=1e-9, atol=1e-10 * np.abs(res.forces).max())
        return
    target = np.where(rows.normal, -rows.gap, rows.slip)
    for start in (np.ones(len(rows), bool), np.zeros(len(rows), bool)):
        other = solve_active_set(op.S, res.jump0, target, rows.normal, active=start)
        assert np.array_equal(other.active, res.active)
        assert np.allclose(other.forces, res.forces, rtol=1e-9, atol=1e-12 * np.abs(res.forces).max())


def lcp_by_enumeration(S, q):
    """The unique mu >= 0 with w = S mu + q >= 0 and mu w = 0 (S SPD), found
    by trying every active set (the independent reference): the set whose
    solution violates the sign conditions least (by round-off only)."""
    m = len(q)
    best = (np.inf, None)
    for bits in range(2 ** m):
        act = np.array([(bits >> i) & 1 for i in range(m)], bool)
        mu = np.zeros(m)
        if act.any():
            mu[act] = np.linalg.solve(S[np.ix_(act, act)], -q[act])
        w = S @ mu + q
        worst = max(-mu.min() / max(np.abs(mu).max(), 1e-300), -w.min() / np.abs(q).max())
        best = min(best, (worst, mu), key=lambda b: b[0])
    assert best[0] < 1e-8, best[0]
    return best[1]


def test_cycling_active_set_falls_back_to_an_exact_solve():
    """Random SPD 3x3..7x7 compliances (rows of scales spread over e^+-1.5)
    make the plain primal-dual active set cycle in 8 of these 2000 draws;
    those are solved by bounded least squares. Reference: all 2^m active
    sets tried. Tolerance: 1e-9 of max |mu| (round-off of dense solves with
    condition numbers below 1e4 is ~1e-12)."""
    rng = np.random.default_rng(1)
    fell_back = 0
    for _ in range(2000):
        m = int(rng.integers(3, 8))
        a = rng.normal(size=(m, m)) * rng.lognormal(0, 1.5, size=m)
        S = a @ a.T + 1e-3 * np.trace(a @ a.T) / m * np.eye(m)   # condition number < 1e4
        jump0 = rng.normal(size=m)
        res = solve_active_set(S, jump0, np.zeros(m), np.ones(m, bool))
        ref = lcp_by_enumeration(S, jump0)
        assert np.allclose(res.forces, ref, rtol=0, atol=1e-9 * max(np.abs(ref).max(), 1e-300))
        fell_back += res.fallback
    assert fell_back >= 5  # the draws do exercise the fallback
