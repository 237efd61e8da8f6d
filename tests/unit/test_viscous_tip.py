"""The viscous tip's criterion (wingcrack/propagation/viscous_tip.py)
against its definitions: LEFM where nothing moves or nothing is viscous,
the viscosity asymptote's own reading where the toughness vanishes, and the
tip's mean velocity from its last advance."""
import math

import numpy as np
import pytest

from wingcrack.propagation.viscous_tip import (BETA_M, K_PRIME, TipMotion, apparent_toughness, asymptote,
                                               driving_ratio)

EP, KIC, MUP, H = 1e10, 1e6, 12.0, 0.2


def test_the_constants_are_the_asymptotes_of_the_literature():
    # Desroches et al. 1994: beta_m = 2^(1/3) 3^(5/6); LEFM's opening 8 KI sqrt(s / 2 pi) / E'
    assert BETA_M == pytest.approx(3.1473, abs=1e-4)
    assert K_PRIME * math.sqrt(0.3) == pytest.approx(8 * math.sqrt(0.3 / (2 * math.pi)), rel=1e-15)


def test_a_tip_that_does_not_move_or_a_fluid_without_viscosity_grows_at_kic():
    assert apparent_toughness(H, 0.0, KIC, EP, MUP) == pytest.approx(KIC, rel=1e-14)
    for V in (1e-6, 1.0, 1e3):
        assert apparent_toughness(H, V, KIC, EP, 0.0) == pytest.approx(KIC, rel=1e-14)


def test_without_toughness_the_rosette_reads_the_viscosity_asymptote():
    """w = A s^(2/3): 4 w(h/4) - w(h) = (4^(1/3) - 1) A h^(2/3)."""
    V = 0.05
    A = BETA_M * (MUP * V / EP) ** (1 / 3)
    expected = EP * (4 ** (1 / 3) - 1) * A * H ** (2 / 3) / (K_PRIME * math.sqrt(H))
    assert apparent_toughness(H, V, 0.0, EP, MUP) == pytest.approx(expected, rel=1e-14)


def test_the_blend_is_monotone_in_the_velocity_and_exact_in_both_limits():
    s = np.array([0.01, 0.1, 1.0])
    V = np.logspace(-8, 2, 30)
    w = np.array([asymptote(s, v, KIC, EP, MUP) for v in V])
    assert np.all(np.diff(w, axis=0) > 0)
    wk = K_PRIME * KIC * np.sqrt(s) / EP
    wm = BETA_M * (MUP * V[-1] / EP) ** (1 / 3) * s ** (2 / 3)
    assert np.allclose(asymptote(s, 0.0, KIC, EP, MUP), wk, rtol=1e-15)
    assert np.allclose(asymptote(s, V[-1], 0.0, EP, MUP), wm, rtol=1e-14)
    K_app = np.array([apparent_toughness(H, v, KIC, EP, MUP) for v in V])
    assert np.all(K_app > KIC) and np.all(np.diff(K_app) > 0)


class _Tip:
    def __init__(self, fracture, end, h=H):
        self.fracture, self.end, self.h = fracture, end, h


def test_a_tip_moves_at_its_last_advance_over_the_time_since():
    motion = TipMotion({(0, 1): (0.5, 10.0)})
    assert motion.velocity(0, 1, 15.0) == pytest.approx(0.1, rel=1e-15)
    assert motion.velocity(0, 0, 15.0) == 0.0   # it did not move
    again = TipMotion.from_list(motion.to_list())
    assert again.moves == motion.moves
    tips = [_Tip(0, 0), _Tip(0, 1)]
    keq = np.array([2 * KIC, 2 * KIC])
    ratio = driving_ratio(keq, tips, [0, 1], motion, 15.0, KIC, EP, MUP)
    # the tip that did not move decides: K_eq / KIc; the moving one's K_app is above KIc
    assert ratio == pytest.approx(2.0, rel=1e-14)
    assert driving_ratio(keq, tips, [1], motion, 15.0, KIC, EP, MUP) == \
        pytest.approx(2 * KIC / apparent_toughness(H, 0.1, KIC, EP, MUP), rel=1e-14)
