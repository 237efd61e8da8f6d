"""The fluid in the injected network: its density law, the fluid a volume
holds, and the pressure at which the network holds a given fluid mass (the
root of the fluid balance).

Density: rho(p) = rho0 exp(c (p - p0)), the law of a constant
compressibility c = (1/rho) d rho/dp, p0 the initial pressure (rho0 its
density). Fluid is counted as its volume at rho0 (m^3 per metre): a
fracture volume V at pressure p holds exp(c (p - p0)) V of it. With
c (p - p0) ~ 1e-2 for water (4.5e-10 1/Pa, tens of MPa) it is the
linearised law 1 + c (p - p0) to 1e-4.

The balance: exp(c (p - p0)) V(p) = m, m the fluid the network holds.
V(p) is non-decreasing (the pressure pushes the faces apart; with
frictionless contact V = -dPi/dp of the concave minimum energy Pi(p)), so
the left side rises strictly in p wherever V > 0. It is solved by a
secant iteration from the previous pressure until the root is bracketed,
then by Illinois (regula falsi with the retained end halved), to a
residual of BALANCE_RTOL of the fluid; every trial is one solve of the
contact problem (V(p) by `volume_at`). The pressure cannot fall below
FLOOR: where the network holds more than m even there, it stays at FLOOR
partly filled (the fluid cavitates rather than pulls the faces together).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

#: the fluid balance's residual, relative to the fluid held: the volume is the integral of
#: the FE opening, accurate to round-off (~1e-14 of it), so the root is solved far below
#: any discretisation error and the balance can be checked to 1e-10 at every step
BALANCE_RTOL = 1e-10
#: the lowest pressure (Pa): an absolute pressure below 0 is a fluid under tension, which
#: cavitates; the network then holds FLOOR, partly filled
FLOOR = 0.0
#: the most trial solves of one balance (a secant from the last pressure needs 2-6)
MAX_TRIALS = 100


def density_ratio(p: float, c: float, p0: float) -> float:
    """rho(p) / rho0 = exp(c (p - p0))."""
    return math.exp(c * (p - p0))


def fluid_of(volume: float, p: float, c: float, p0: float) -> float:
    """The fluid (m^3/m at rho0) that a volume `volume` holds at pressure p."""
    return volume * density_ratio(p, c, p0)


def linear_root(trials, fluid: float, c: float, p0: float) -> float | None:
    """The pressure at which exp(c (p - p0)) V(p) = fluid with V linear
    through the two trials [(p, V), (p, V)] (V is linear in p while the
    contact states hold: then the root in one solve, compressibility
    included), or None where that line gives none (V falling, or flat and
    the fluid not at the density that fills it)."""
    from scipy.optimize import brentq   # lazy: start-up (scipy.optimize is 0.3 s, pumped runs' alone)

    (x1, v1), (x2, v2) = trials
    if x1 == x2 or fluid <= 0:
        return None
    s = (v2 - v1) / (x2 - x1)
    if s < 0 or (s == 0 and (c == 0 or v2 <= 0)):
        return None
    if c == 0:
        return x2 + (fluid - v2) / s

    def g(p):   # ln(fluid held at p) - ln(fluid): increasing where V > 0
        v = v2 + s * (p - x2)
        return c * (p - p0) + math.log(v) - math.log(fluid) if v > 0 else -math.inf

    # a bracket about x2, widened by doubling on the side of the root; where V vanishes on the
    # left (at x2 - v2 / s), just right of it g is far below 0
    width = abs(x2 - x1)
    if g(x2) < 0:
        lo, hi = x2, x2 + width
        while g(hi) < 0:
            hi, width = hi + width, 2 * width
    else:
        lo, hi = x2 - width, x2
        if s > 0:
            lo = max(lo, x2 - v2 / s * (1 - 1e-12))
        while g(lo) >= 0:
            lo, width = lo - width, 2 * width
    return float(brentq(g, lo, hi, xtol=1e-15 * max(abs(lo), abs(hi)), rtol=4 * np.finfo(float).eps))


@dataclass
class Balance:
    """The root of the balance: pressure p (Pa), the network's volume V(p)
    and the fluid it holds there, the trials [(p, V)] in order, and whether
    the network is only partly filled (p = FLOOR, its volume more than the
    fluid)."""
    pressure: float
    volume: float
    fluid: float
    trials: list = field(default_factory=list)
    partly_filled: bool = False

    @property
    def solves(self) -> int:
        return len(self.trials)


def balance_pressure(volume_at: Callable[[float], float], fluid: float, c: float, p0: float, start: float,
                     step: float, floor: float = FLOOR, rtol: float = BALANCE_RTOL,
                     closing: float | None = None, constant: float = 0.0) -> Balance:
    """The pressure p >= floor at which exp(c (p - p0)) volume_at(p) equals
    `fluid`, from the guess `start`; then secants. The first step: where
    `closing` is given (the pressure at which the faces' opening, the volume
    less its `constant` part, vanishes: the normal stress on the fractures),
    Newton's with the opening taken proportional to p - closing (exact for a
    crack under a uniform normal stress); else of about `step` (> 0, Pa).
    volume_at(p) solves at p; the solution left is the root's (the last
    trial is the returned one)."""
    trials = []

    def f(p):
        v = float(volume_at(p))
        trials.append((p, v))
        return fluid_of(v, p, c, p0) - fluid

    tol = rtol * abs(fluid)

    def done(p, fp, partly=False):
        if trials[-1][0] != p:   # the solution left must be the root's
            f(p)
        return Balance(p, trials[-1][1], fluid + fp, trials, partly)

    x0 = max(float(start), floor)
    f0 = f(x0)
    if abs(f0) <= tol:
        return done(x0, f0)
    direction = -1.0 if f0 > 0 else 1.0
    first = abs(step)
    opening = trials[-1][1] - constant
    if closing is not None and x0 > closing and opening > 0:
        slope = density_ratio(x0, c, p0) * (opening / (x0 - closing) + c * trials[-1][1])
        first = abs(f0) / slope
    x1 = max(x0 + direction * first, floor)
    # bracket: secant steps from the last two trials (exact where V is linear in p: open faces,
    # a set of contact states that holds), at most 100 times the last, doubled where the secant
    # points back
    while True:
        if x1 == x0:   # at the floor, with fluid to spare
            return done(x0, f0, partly=True)
        f1 = f(x1)
        if abs(f1) <= tol:
            return done(x1, f1)
        if (f1 > 0) != (f0 > 0):
            break
        if len(trials) >= MAX_TRIALS:
            raise ArithmeticError(f"the fluid balance found no pressure in {MAX_TRIALS} solves (the last at "
                                  f"{x1:.6g} Pa holds {f1 + fluid:.6g} m^3/m, {fluid:.6g} wanted)")
        last = x1 - x0
        secant = linear_root(trials[-2:], fluid, c, p0)
        s = secant - x1 if secant is not None and (secant - x1) * last > 0 else 2.0 * last
        s = math.copysign(min(abs(s), 100.0 * abs(last)), last)
        x0, f0, x1 = x1, f1, max(x1 + s, floor)
    lo, f_lo, hi, f_hi = (x0, f0, x1, f1) if f0 < 0 else (x1, f1, x0, f0)
    side = 0
    while len(trials) < MAX_TRIALS:
        x = linear_root(trials[-2:], fluid, c, p0)   # exact where the last two trials share their contact states
        if x is None or not lo < x < hi:
            x = hi - f_hi * (hi - lo) / (f_hi - f_lo)
        if not lo < x < hi:
            x = 0.5 * (lo + hi)
        fx = f(x)
        if abs(fx) <= tol:
            return done(x, fx)
        if fx > 0:
            hi, f_hi = x, fx
            if side == 1:
                f_lo *= 0.5
            side = 1
        else:
            lo, f_lo = x, fx
            if side == -1:
                f_hi *= 0.5
            side = -1
        if hi - lo <= 4.0 * math.ulp(max(abs(lo), abs(hi))):
            break
    # no pressure balances to the tolerance: V jumps across the bracket (a change of the contact
    # state that the solver resolves on one side only); the closer end, said by its residual
    p, fp = (lo, f_lo) if abs(f_lo) <= abs(f_hi) else (hi, f_hi)
    raise ArithmeticError(f"the fluid balance has no root to {rtol:g}: the network's volume jumps at "
                          f"{p:.9g} Pa (residual {abs(fp) / max(abs(fluid), 1e-300):.3g} of the fluid)")
