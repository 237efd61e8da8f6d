"""Paper eq. (13) and section 3.2: how far each tip grows."""
import numpy as np

from wingcrack.propagation.growth_law import advances


def test_paris_type_law_shares_the_step():
    """L_i = Lmax (G_i / max G)^alpha, exactly (closed form, round-off)."""
    G = np.array([120.0, 30.0, 0.0, 75.0])
    L = advances(G, Lmax=1e-3, alpha=0.35, Lmin=0.0)
    expected = 1e-3 * (np.array([120.0, 30.0, 0.0, 75.0]) / 120.0) ** 0.35
    expected[2] = 0.0   # a tip below KIc (G = 0 given) does not grow
    assert np.allclose(L, expected, rtol=1e-14, atol=0)


def test_lmin_stops_short_kinked_advances_but_not_straight_ones():
    """L_min = 0.4 h: a kinked tip whose share is shorter does not grow; a
    tip growing straight on (theta = 0) still moves its node forward."""
    G = np.array([100.0, 1.0, 1.0])
    theta = np.array([0.3, -0.5, 0.0])
    Lmax, h = 1e-3, 1e-3
    L = advances(G, Lmax=Lmax, alpha=0.35, Lmin=0.4 * h, theta=theta)
    share = Lmax * (1.0 / 100.0) ** 0.35          # 0.2 mm < L_min = 0.4 mm
    assert share < 0.4 * h
    assert L[0] == Lmax and L[1] == 0.0 and np.isclose(L[2], share, rtol=1e-14)
