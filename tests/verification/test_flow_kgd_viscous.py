"""A hydraulic fracture in the viscosity-dominated regime: the M-vertex KGD
(Adachi & Detournay 2002; tests/references.py KGDViscosity) followed by the
run with the flow and the viscous tip asymptote
(wingcrack/propagation/viscous_tip.py).

The KGD plate of test_flow_kgd.py (a crack of half-length 1 m in a plate of
1000 m, tip_size 0.2 m, 1e-4 m^3/s per m, an incompressible fluid) with a
fluid of 1 Pa s and KIc = 0.01 MPa m^0.5: the dimensionless toughness
K' / (E'^3 mu' Q)^(1/4) = 0.005, deep in the viscosity regime (the M-vertex
holds for it below 1). Under 10 MPa of confinement, the fluid's initial
pressure, so that the viscous suction near the tips (a net pressure far
below zero) stays above the cavitation floor: the zero-lag solution.
Growth by 0.5 m steps; 27 steps reach l = 14 m at t = 621 s.

Tolerance (the issue's): 3 % on l(t), 5 % on the opening at the injection
point, from t = 60 s over a decade of time; the net pressure there within
5 % too. Measured: l 2.2 % at 60 s falling to 0.8 % at 621 s (the initial
crack's transient: 3.7 % at l = 1.5 m, decaying as the growth forgets the
start), the opening 0.6 % to 0.3 %, the pressure 1.0 % to 0.6 %; the
references' own error 5e-4 (the similarity solution's, tests/references.py).
tip_size 0.4 / 0.2 / 0.1 m and a step of 0.25 m: benchmarks/kgd_viscous_convergence.py.
"""
import numpy as np
import pytest

import wingcrack
from builders import flowing_kgd
from references import KGDViscosity
from wingcrack.case import Case

E, NU, Q, ETA, S0 = 10e9, 0.25, 1e-4, 1.0, 10e6
EP = E / (1 - NU ** 2)
T_FROM = 60.0


def viscous_kgd(steps=27, tip_size=0.2, length=0.5):
    """The case (module doc): `steps` growth steps of `length` (m)."""
    d = flowing_kgd(viscosity=ETA, steps=steps, end_time=2000.0, tip_size=tip_size)
    d["material"]["KIc"] = 1e4
    d["stress"] = {"sxx": -S0, "syy": -S0, "sxy": 0.0}
    d["injection"]["initial_pressure"] = S0
    d["propagation"]["length"] = length
    return d


def errors(run, ref):
    """(t, relative errors of l, w0, p0) at every step from T_FROM on."""
    steps = [s for s in run.steps if s["time"] >= T_FROM]
    t = np.array([s["time"] for s in steps])
    l = np.array([max(tip["x"] for tip in s["tips"]) for s in steps])
    w0 = np.array([s["injection"]["opening"] for s in steps])
    p0 = np.array([s["injection"]["pressure"] - S0 for s in steps])
    return t, l / ref.length(t) - 1, w0 / ref.opening(t) - 1, p0 / ref.net_pressure(t) - 1


@pytest.fixture(scope="module")
def run():
    return wingcrack.run(Case.from_dict(viscous_kgd()), plots=False)


def test_the_viscosity_dominated_kgd_is_followed_over_a_decade(run):
    ref = KGDViscosity(EP, ETA, Q)
    assert ref.gamma == pytest.approx(KGDViscosity.GAMMA, rel=1e-3)   # the similarity solution is the published one
    assert run.status == "finished" and len(run.steps) == 27
    t, el, ew, ep = errors(run, ref)
    assert t[-1] >= 10 * T_FROM
    assert np.abs(el).max() <= 0.03, (t, el)
    assert np.abs(ew).max() <= 0.05, (t, ew)
    assert np.abs(ep).max() <= 0.05, (t, ep)


def test_the_fluid_balance_holds_while_the_viscous_fracture_grows(run):
    for s in run.steps:
        inj = s["injection"]
        assert abs(inj["injected"] - inj["stored"] - inj["leaked"]) <= 1e-8 * (inj["held"] + inj["injected"])
        assert inj["injected"] == pytest.approx(Q * s["time"], rel=1e-12)
