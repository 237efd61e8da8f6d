"""The fluid balance's root (wingcrack/propagation/fluid.py) against the
closed forms of the volume laws a fracture network has:

- an open crack: V(p) = Vr + C (p - s) (Sneddon's compliance C = 2 pi a^2 / E',
  s the normal stress on it, Vr its residual volume);
- a closed crack: V = Vr (only the residual aperture) until p reaches s,
  then the open crack's law.

With the density law exp(c (p - p0)) the balance exp(c (p - p0)) V(p) = m
is, on the open branch, y exp(k y) = m exp(c p0 + k (Vr - C s)) ... for
y = V, k = c / C, so V = W(k M) / k with Lambert's W and
M = m exp(c (p0 - s) + k Vr): p = s + (V - Vr) / C; on the closed branch
p = p0 + ln(m / Vr) / c. The root is asked to BALANCE_RTOL (1e-10) of the
fluid; dp/p = (dm/m) (m / (p dm/dp)): on the open branch m / (p dm/dp) <=
V / (C p) < 10 here, so the pressures are compared at 1e-9; on the closed
one dm/m = c dp, so 1e-10 of the fluid is 1e-10 / c = 0.22 Pa (compared at
twice that).
"""
import math

import numpy as np
import pytest
from scipy.special import lambertw

from wingcrack.propagation.fluid import BALANCE_RTOL, balance_pressure, fluid_of

C, S, VR, CF, P0 = 2 * math.pi / 4e10, 20e6, 2e-4, 4.5e-10, 5e6
PRESSURE_RTOL = 1e-9


def volume(p):
    return VR + C * max(p - S, 0.0)


def open_root(m):
    k = CF / C
    M = m * math.exp(CF * (P0 - S) + k * VR)
    V = float(np.real(lambertw(k * M))) / k
    return S + (V - VR) / C


def closed_root(m):
    return P0 + math.log(m / VR) / CF


def test_the_open_branch_is_lambert_w():
    for p_true in (21e6, 25e6, 40e6, 200e6):
        m = fluid_of(volume(p_true), p_true, CF, P0)
        assert open_root(m) == pytest.approx(p_true, rel=1e-12)
        b = balance_pressure(volume, m, CF, P0, start=30e6, step=1e6)
        assert abs(b.fluid - m) <= BALANCE_RTOL * m
        assert b.pressure == pytest.approx(p_true, rel=PRESSURE_RTOL)
        assert b.solves <= 8, b.trials
        assert b.trials[-1][0] == b.pressure and b.volume == volume(b.pressure)


def test_the_closed_branch_holds_the_residual_volume_only():
    """Below the normal stress the faces are closed: only compressibility
    stores fluid, and the pressure is logarithmic in it."""
    for p_true in (6e6, 12e6, 19.9e6):
        m = fluid_of(VR, p_true, CF, P0)
        assert closed_root(m) == pytest.approx(p_true, rel=1e-12)
        b = balance_pressure(volume, m, CF, P0, start=30e6, step=1e6)
        assert abs(b.fluid - m) <= BALANCE_RTOL * m
        assert b.pressure == pytest.approx(p_true, abs=2 * BALANCE_RTOL / CF) and not b.partly_filled
        assert b.solves <= 12, b.trials


def test_too_little_fluid_leaves_the_network_partly_filled_at_zero():
    """A network whose volume at p = 0 exceeds the fluid (a dry fracture
    joined, its residual volume empty) holds p = 0, partly filled."""
    m = 0.5 * fluid_of(VR, 0.0, CF, P0)
    b = balance_pressure(volume, m, CF, P0, start=25e6, step=1e6)
    assert b.partly_filled and b.pressure == 0.0 and b.volume == VR
    assert b.fluid > m


def test_an_incompressible_fluid_and_no_residual_volume():
    """c = 0 and Vr = 0 (the KGD case): V(p) = m, p = s + m / C exactly;
    a linear law is solved by the first secant."""
    def v(p):
        return C * max(p - S, 0.0)

    m = C * 7e6
    b = balance_pressure(v, m, 0.0, 0.0, start=30e6, step=1e6)
    assert b.pressure == pytest.approx(S + 7e6, rel=1e-12)
    assert b.solves <= 3


def test_a_balance_at_the_start_costs_one_solve():
    m = fluid_of(volume(25e6), 25e6, CF, P0)
    b = balance_pressure(volume, m, CF, P0, start=25e6, step=1e6)
    assert b.solves == 1 and b.pressure == 25e6


def test_a_volume_that_jumps_is_said():
    """A volume law with a jump across the root (no pressure balances it)
    is an error that says where, not a wrong root."""
    def v(p):
        return 1.0 if p < 10e6 else 2.0

    with pytest.raises(ArithmeticError, match="jumps at 1"):
        balance_pressure(v, 1.5, 0.0, 0.0, start=5e6, step=1e6)
