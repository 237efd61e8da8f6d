"""Before breakdown: the pressure-volume curve of a static crack under a
pump (propagation/injection.py: Pump.volumes and Pump.balance on one
discretisation), against closed forms. A straight crack 2a in a plate of
side 100 a (tip_size 0.05 a, the plate of test_pressure_plate.py), plane
strain; fluid water-like (c = 4.5e-10 1/Pa), residual aperture w_r, p0.

1. An open crack: V(p) = 2 w_r a + C p, linear in p, with Sneddon's
   compliance C = 2 pi a^2 / E'. Three numbers, three references:
   - the FE volume is the pressure's work per unit pressure: with the
     pressure the only load, Clapeyron's U = p V / 2 (U the strain energy,
     assembled over the cells: another route) to 1e-12 (two assemblies'
     round-off: measured 1e-15);
   - C against Sneddon's (the discretisation and the plate's finite size:
     measured 2.9e-4 here, checked at 1e-3);
   - the balance's root p(m), exp(c (p - p0)) (V_r + C p) = m, against its
     closed form with the FE's own C (Lambert W, as in
     tests/unit/test_fluid_balance.py) to 1e-9 of p (the balance's 1e-10 of
     the fluid, times m / (p dm/dp) <= 10 on this curve).
2. A closed Coulomb crack under the in-situ normal stress sigma_n (and a
   shear it holds, |tau| < mu sigma_n at p = 0): its faces hold only the
   residual volume until the effective normal stress sigma_n - p reaches
   zero, V(p) = 2 w_r a exactly (the opening of closed faces is the
   contact's round-off: measured 1e-16 of the open crack's at the net
   pressure sigma_n, checked at 1e-12), where compressibility alone stores
   fluid:
       p(m) = p0 + ln(m / (2 w_r a)) / c;
   there dm / m = c dp, so the balance's 1e-10 of the fluid is 1e-10 / c
   = 0.22 Pa of pressure (checked at twice that);
   past sigma_n it opens as the open crack does under the net pressure
   p - sigma_n: V = 2 w_r a + C (p - sigma_n) with the same C (1e-5: the
   slip the shear drives does not open a straight crack in a symmetric
   body; the mesh is not symmetric about the crack, and its slip opens it
   by 3e-6 of the volume, measured).
"""
import math

import numpy as np
import pytest
from scipy.special import lambertw

from builders import square_plate_with_cracks
from wingcrack.case import Case
from wingcrack.propagation.fluid import fluid_of
from wingcrack.propagation.injection import Pump
from wingcrack.step import Timer, discretise

A, L, E, NU = 1.0, 100.0, 10e9, 0.25
EP = E / (1 - NU ** 2)
C_SNEDDON = 2 * math.pi * A * A / EP
CF, WR, P0 = 4.5e-10, 1e-4, 0.5e6
VR = 2 * WR * A
#: see the module doc
CLAPEYRON_TOL, SNEDDON_TOL, ROOT_TOL, CLOSED_TOL, COUPLING_TOL = 1e-12, 1e-3, 1e-9, 1e-12, 1e-5
#: the in-situ stress of the closed crack: sigma_n = 8 MPa, tau = 2 MPa (mu sigma_n = 4.8 MPa)
SIGMA_N, TAU, MU = 8e6, 2e6, 0.6


def plate(faces="open", stress=(0.0, 0.0, 0.0), **law):
    d = square_plate_with_cracks(L, [[[-A, 0.0], [A, 0.0]]], stress, size=10 * A, tip_size=0.05 * A, nu=NU)
    d["material"]["E"] = E
    d["fractures"][0].update(faces=faces, **law)
    d["propagation"]["load"] = "injection"
    d["injection"] = {"fracture": 0, "rate": 1e-5, "compressibility": CF, "residual_aperture": WR,
                      "initial_pressure": P0}
    case = Case.from_dict(d)
    disc = discretise(case, case.fractures, Timer())
    return case, disc, Pump.of(case)


@pytest.fixture(scope="module")
def open_crack():
    case, disc, pump = plate()
    yield case, disc, pump
    disc.release()


def volume(disc, pump, case, p):
    disc.solve(p)
    return pump.network_volume(disc, case.fractures)


def test_the_volume_is_the_pressures_work(open_crack):
    case, disc, pump = open_crack
    p = 2e6
    v = volume(disc, pump, case, p) - VR
    assert 0.5 * p * v == pytest.approx(disc.problem.strain_energy(), rel=CLAPEYRON_TOL)


def test_an_open_crack_is_linear_with_sneddons_compliance(open_crack):
    case, disc, pump = open_crack
    ps = np.array([0.0, 1e6, 3e6, 7e6])
    vs = np.array([volume(disc, pump, case, p) for p in ps])
    assert vs[0] == pytest.approx(VR, rel=1e-12)
    C = (vs[1:] - VR) / ps[1:]
    assert np.ptp(C) <= 1e-12 * C.max()
    assert C[0] == pytest.approx(C_SNEDDON, rel=SNEDDON_TOL)


def lambert_root(m, C, s=0.0):
    """p with exp(c (p - p0)) (VR + C (p - s)) = m (the open branch)."""
    k = CF / C
    M = m * math.exp(CF * (P0 - s) + k * VR)
    V = float(np.real(lambertw(k * M))) / k
    return s + (V - VR) / C


def test_the_pressure_volume_curve_of_the_open_crack(open_crack):
    """The pump's pressure at each fluid held, solved on the crack by the
    balance from a far start, against the closed form."""
    case, disc, pump = open_crack
    C = (volume(disc, pump, case, 1e6) - VR) / 1e6
    for p_true in (0.6e6, 2e6, 5e6, 20e6):
        m = fluid_of(VR + C * p_true, p_true, CF, P0)
        assert lambert_root(m, C) == pytest.approx(p_true, rel=1e-12)
        b = pump.balance(disc, case.fractures, m, start=10e6, scale=1e6)
        assert b.pressure == pytest.approx(p_true, rel=ROOT_TOL)
        assert abs(fluid_of(b.volume, b.pressure, CF, P0) - m) <= 1e-10 * m


@pytest.fixture(scope="module")
def closed_crack():
    case, disc, pump = plate("coulomb", (0.0, -SIGMA_N, TAU), friction=MU)
    yield case, disc, pump
    disc.release()


def test_a_closed_crack_holds_its_residual_volume_until_it_opens(closed_crack, open_crack):
    case, disc, pump = closed_crack
    oc, od, op = open_crack
    C = (volume(od, op, oc, 1e6) - VR) / 1e6
    for p in (0.0, 2e6, 5e6, 7.9e6):
        disc.accept()
        v = volume(disc, pump, case, p)
        assert abs(v - VR) <= CLOSED_TOL * C * SIGMA_N, (p, v - VR)
        # the balance: compressibility alone stores the fluid
        m = fluid_of(VR, p, CF, P0)
        if p > 0:
            b = pump.balance(disc, case.fractures, m, start=p + 3e6, scale=1e6)
            assert abs(fluid_of(b.volume, b.pressure, CF, P0) - m) <= 1e-10 * m
            assert b.pressure == pytest.approx(P0 + math.log(m / VR) / CF, abs=2e-10 / CF)
    for p in (9e6, 12e6):
        v = volume(disc, pump, case, p)
        assert v == pytest.approx(VR + C * (p - SIGMA_N), rel=COUPLING_TOL)
