"""Issue 5 test 2: the critical load factor, found directly."""
import numpy as np
import pytest

from builders import brazilian_disc
from wingcrack.step import Timer, discretise
from wingcrack.case import Case
from wingcrack.propagation.critical_load import critical_load_factor
from wingcrack.tip_sifs import correlation_sifs
import wingcrack_kernels as K


def test_secant_on_a_piecewise_linear_response():
    """A kinked response (as when the contact state changes with the load):
    the safeguarded secant finds the crossing to 1e-6 relative."""
    def keq(lam):
        return 0.4 * lam + 0.6 * max(0.0, lam - 3.0) + 0.2
    KIc = 2.0
    # exact: 0.4 l + 0.6 (l - 3) + 0.2 = 2  ->  l - 1.6 = 2  ->  l = 3.6
    res = critical_load_factor(keq, KIc, start=0.0, homogeneous=False, limit=100.0)
    assert abs(res.load_factor - 3.6) < 1e-6 * 3.6
    assert keq(res.load_factor) >= KIc
    assert res.solves < 30


def test_a_secant_that_lands_on_the_root_ends_there():
    """The first secant lands on the root (here exactly: K_eq = 2 lam - 1, the
    bracket [1, 2], all in binary fractions), and the search ends there,
    instead of halving the bracket's lower end up to it: the next secant
    from a root with f = 0 goes nowhere, and the bisection that follows
    took 12 more solves on a Coulomb disc step (1e-6 from a 3.5e-3 bracket)."""
    calls = []

    def keq(lam):
        calls.append(lam)
        return 2.0 * lam - 1.0

    res = critical_load_factor(keq, 2.0, start=1.0, homogeneous=False, limit=100.0)
    assert res.load_factor == 1.5 and calls == [1.0, 2.0, 1.5] and res.solves == 3


def test_limit_and_start():
    res = critical_load_factor(lambda l: 0.01 * l, 2.0, start=0.0, homogeneous=False, limit=100.0)
    assert res.load_factor is None                      # needs 200 > limit
    res = critical_load_factor(lambda l: 10.0, 2.0, start=5.0, homogeneous=False, limit=100.0)
    assert res.load_factor == 5.0                       # the load never goes down


@pytest.fixture(scope="module")
def disc():
    case = Case.from_dict(brazilian_disc(45, faces="open"))
    d = discretise(case, case.fractures, Timer())
    cm, problem, contact = d.cm, d.problem, d.contact
    m = case.material

    def keq(lam):
        contact.solve(lam)
        KI, KII = correlation_sifs(problem, cm, m.E, m.nu, m.plane)
        return float(np.max(K.equivalent_k(KI, KII, K.mts_angle(KI, KII))))
    return case, keq


def test_disc_critical_load_equals_independent_solve_and_bisection(disc):
    """45-degree disc, open faces: lambda_c = KIc / K_eq(f0 = 1 N/m) from a
    single solve at unit load, and equals a plain bisection on repeated
    solves, both within 1e-6 (the bisection's tolerance)."""
    case, keq = disc
    KIc = case.material.KIc
    f0 = 1.0e6                                    # the builder's load, N/m
    unit = keq(1.0 / f0)                          # K_eq at f0 = 1 N/m
    direct = critical_load_factor(keq, KIc, 0.0, homogeneous=True, limit=1e9)
    assert direct.solves == 1
    assert abs(direct.load_factor * f0 - KIc / unit) < 1e-6 * KIc / unit
    lo, hi = 0.0, 10.0
    while hi - lo > 1e-8 * hi:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if keq(mid) < KIc else (lo, mid)
    assert abs(direct.load_factor - hi) < 1e-6 * hi
    secant = critical_load_factor(keq, KIc, 0.0, homogeneous=False, limit=1e9)
    assert abs(secant.load_factor - hi) < 1e-6 * hi
