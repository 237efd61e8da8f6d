"""Issue 4 test 3: the initial gap g (non-penetration w + g >= 0)."""
import numpy as np

from test_contact_closed_crack import A, SIGMA, plate
from wingcrack.step import solve_initial


def _case(gap, faces="frictionless"):
    # a horizontal crack squeezed by -sigma: the open-face solution closes
    # it by w_open(s) = -4 (1 - nu^2) sigma sqrt(a^2 - s^2) / E (max 1.5e-4 m)
    return plate([[[-A, 0.0], [A, 0.0]]], faces=faces, sigma0=(0.0, -SIGMA, 0.0), gap=gap)


def test_large_gap_is_the_open_solve():
    """A gap larger than any closure: nothing touches, the result is the
    open-face solve (1e-12 relative: round-off)."""
    ref = solve_initial(_case(0.0, faces="open"))
    sol = solve_initial(_case(1e-3))
    assert not sol.contact.result.active.any()
    u0, u1 = ref.problem.u.x.array, sol.problem.u.x.array
    assert np.abs(u1 - u0).max() < 1e-12 * np.abs(u0).max()


def test_small_gap_closes_where_the_faces_meet():
    """With gaps below the full closure, the faces touch where the open
    solve would overlap most (the middle): the jump equals -g on every
    closed pair (1e-10 relative to g), the closed length shrinks and the
    contact pressure falls as the gap grows, and w + g >= 0 everywhere."""
    closed, force = [], []
    for g in (0.0, 2e-5, 6e-5, 1.2e-4):
        sol = solve_initial(_case(g))
        res, rows = sol.contact.result, sol.contact.rows
        act = res.active
        assert act.any()
        if g > 0:
            assert np.abs(res.jump[act] + g).max() < 1e-10 * g
        assert np.min(res.jump[rows.normal] + rows.gap[rows.normal]) > -1e-12 * max(g, 1e-6)
        closed.append(int(act.sum()))
        force.append(float(res.forces.sum()))
        if g > 0:
            # the closed pairs are the middle ones
            s_closed = np.abs(rows.position[act, 0])
            s_open = np.abs(rows.position[~act, 0])
            assert s_closed.max() < s_open.min()
    assert closed == sorted(closed, reverse=True) and closed[0] > closed[-1]
    assert all(f1 > f2 for f1, f2 in zip(force, force[1:]))
