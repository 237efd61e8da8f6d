"""contact.box_qp against programs whose solution is known by construction:
a point x*, its active bounds, multipliers alpha* of the equalities and
gradient signs are drawn first and c, e made so that x* meets the KKT
conditions (a strictly convex program has no other minimiser)."""
import numpy as np
import pytest

from wingcrack.contact.box_qp import Infeasible, solve_box_qp


def _program(seed, m=30, r=0, degenerate=False):
    rng = np.random.default_rng(seed)
    Q = rng.normal(size=(m, m))
    H = Q @ Q.T / m + 0.1 * np.eye(m)
    x = rng.normal(size=m)
    lo, hi = np.full(m, -np.inf), np.full(m, np.inf)
    kind = rng.integers(0, 4, m)          # 0 free, 1 at lo, 2 at hi, 3 inside a finite box
    lo[kind == 1] = x[kind == 1]
    hi[kind == 2] = x[kind == 2]
    lo[kind == 2] = x[kind == 2] - 5.0
    lo[kind == 3], hi[kind == 3] = x[kind == 3] - 1.0, x[kind == 3] + 1.0
    g = np.zeros(m)
    g[kind == 1] = 0.0 if degenerate else rng.uniform(0.1, 1.0, np.sum(kind == 1))
    g[kind == 2] = 0.0 if degenerate else -rng.uniform(0.1, 1.0, np.sum(kind == 2))
    G = rng.normal(size=(m, r))
    alpha = rng.normal(size=r)
    c = H @ x + G @ alpha - g
    return H, c, lo, hi, (G if r else None), (-G.T @ x if r else None), x, alpha


@pytest.mark.parametrize("r", [0, 2, 3])
@pytest.mark.parametrize("degenerate", [False, True])
def test_the_constructed_minimiser_is_found_to_round_off(r, degenerate):
    for seed in range(40):
        H, c, lo, hi, G, e, x, alpha = _program(seed, r=r, degenerate=degenerate)
        res = solve_box_qp(H, c, lo, hi, G, e)
        # cond(H) <= ~1e3 and one direct solve of the face's KKT system at the end: round-off
        np.testing.assert_allclose(res.x, x, rtol=0, atol=1e-12 * np.max(np.abs(x)))
        if r:
            np.testing.assert_allclose(res.alpha, alpha, rtol=0, atol=1e-10 * max(1.0, np.max(np.abs(alpha))))
        assert res.exact


def test_a_start_changes_the_steps_not_the_answer():
    H, c, lo, hi, G, e, x, _ = _program(7, r=2)
    cold = solve_box_qp(H, c, lo, hi, G, e)
    warm = solve_box_qp(H, c, lo, hi, G, e, x0=cold.x, alpha0=cold.alpha)
    np.testing.assert_allclose(warm.x, cold.x, rtol=0, atol=1e-13 * np.max(np.abs(x)))
    assert warm.steps <= cold.steps


def test_an_equality_the_box_cannot_meet_is_infeasible_with_its_residual():
    """x >= 0 and sum(x) = -1: the least residual is 1 (x = 0)."""
    rng = np.random.default_rng(1)
    m = 20
    Q = rng.normal(size=(m, m))
    H = Q @ Q.T / m + 0.1 * np.eye(m)
    with pytest.raises(Infeasible) as err:
        solve_box_qp(H, rng.normal(size=m), np.zeros(m), np.full(m, np.inf), np.ones((m, 1)), np.array([1.0]))
    np.testing.assert_allclose(err.value.residual, [1.0], rtol=1e-6)
    # on the edge of the box it is feasible
    res = solve_box_qp(H, rng.normal(size=m), np.zeros(m), np.full(m, np.inf), np.ones((m, 1)), np.array([-1.0]))
    assert abs(res.x.sum() - 1.0) < 1e-12 and np.all(res.x >= 0)
