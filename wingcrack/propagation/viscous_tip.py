"""The growth criterion of a tip that a viscous fluid drives: the tip
asymptote of a fluid-driven fracture, implicit in the tip's arrival time.

Near the tip of a hydraulic fracture moving at the velocity V the opening
at a distance s behind it follows the universal asymptote, between the
toughness one (LEFM) and the viscosity one (the fluid flowing to the tip of
a crack in a solid of no toughness; Desroches et al. 1994, Garagash &
Detournay 2000, Detournay 2016):

    w_k(s) = K' s^(1/2) / E',                        K' = sqrt(32/pi) KIc,
    w_m(s) = beta_m (mu' V / E')^(1/3) s^(2/3),      beta_m = 2^(1/3) 3^(5/6), mu' = 12 eta,

here blended as w^3 = w_k^3 + w_m^3: monotone in V, exact in both limits.
On a practical mesh the viscous field (w ~ s^(2/3), the pressure singular
as s^(-1/3)) is not resolved at the rosette, and the K that displacement
correlation reads there exceeds a small KIc at once: LEFM at the tips then
runs away. What the rosette reads is compared instead with what it would
read on the asymptote of a tip moving at V: its apparent toughness

    K_app(V) = E' (4 w(h/4) - w(h)) / (sqrt(32/pi) sqrt(h)),   w the asymptote,

the correlation's own combination of the openings at the quarter-point and
corner nodes (h the rosette's radius). K_app(0) = KIc exactly, and K_app
does not depend on V where the viscosity is 0: the criterion K_eq = K_app(V)
is LEFM's where nothing moves or nothing is viscous.

V is implicit (PyFrac's way, Peirce & Detournay 2008, in time instead of
in the front's position): a tip that advanced dl at the growth event of
time t_n sits, on the grown geometry, where it arrived at the time t at
which K_eq = K_app(dl / (t - t_n)): the step's mean velocity. K_app falls
from infinity as t grows while the fluid pumped in raises K_eq, so the
arrival is one root in time, found as a growth event is (flow_march.py).
A tip that did not move at the last event, or has never grown, has V = 0.
"""
from __future__ import annotations

import math

import numpy as np

#: the viscosity asymptote's prefactor (Desroches et al. 1994: w = beta_m (mu' V / E')^(1/3) s^(2/3))
BETA_M = 2.0 ** (1.0 / 3.0) * 3.0 ** (5.0 / 6.0)
#: K' / KIc
K_PRIME = math.sqrt(32.0 / math.pi)


def asymptote(s, V: float, KIc: float, Ep: float, mup: float):
    """The opening (m) at the distance s (m) behind a tip moving at V (m/s):
    w^3 = w_k^3 + w_m^3 (module doc); mup = 12 eta."""
    s = np.asarray(s, float)
    wk = K_PRIME * KIc * np.sqrt(s) / Ep
    wm = BETA_M * np.cbrt(mup * max(V, 0.0) / Ep) * s ** (2.0 / 3.0)
    return np.cbrt(wk ** 3 + wm ** 3)


def apparent_toughness(h: float, V: float, KIc: float, Ep: float, mup: float) -> float:
    """K_app(V) (Pa m^0.5): what displacement correlation on a rosette of
    radius h reads on the asymptote of a tip moving at V (module doc)."""
    w = asymptote(np.array([0.25 * h, h]), V, KIc, Ep, mup)
    return float(Ep * (4.0 * w[0] - w[1]) / (K_PRIME * math.sqrt(h)))


class TipMotion:
    """Each tip's last advance: {(fracture, end): (dl, t_n)}, the advance
    (m) at the growth event of time t_n (s). velocity(): the mean velocity of
    a tip that arrives where it is at the time t."""

    def __init__(self, moves=None):
        self.moves = dict(moves or {})

    def velocity(self, fracture: int, end: int, t: float) -> float:
        dl, t_n = self.moves.get((int(fracture), int(end)), (0.0, t))
        if dl <= 0.0:
            return 0.0
        return dl / max(t - t_n, 1e-300)

    @classmethod
    def after_growth(cls, before, fset, t: float) -> "TipMotion":
        """The advances from the tips `before` (the mesh's tips: fracture,
        end, x) to the grown fractures' tips, at the event of time t."""
        moves = {}
        for tip in before:
            f = fset.fractures[int(tip.fracture)]
            if f.ends[int(tip.end)] != "tip":
                continue
            dl = float(np.linalg.norm(np.asarray(f.tip(int(tip.end)), float) - np.asarray(tip.x, float)))
            moves[(int(tip.fracture), int(tip.end))] = (dl, float(t))
        return cls(moves)

    def to_list(self) -> list:
        return [[f, e, dl, t] for (f, e), (dl, t) in sorted(self.moves.items())]

    @classmethod
    def from_list(cls, rows) -> "TipMotion":
        return cls({(int(f), int(e)): (float(dl), float(t)) for f, e, dl, t in rows or []})


def driving_ratio(keq, tips, grow, motion: TipMotion, t: float, KIc: float, Ep: float, mup: float) -> float:
    """The largest K_eq / K_app(V) of the growing tips `grow` (indices into
    the mesh's `tips`) at the time t: 1 where the first of them arrives."""
    out = -np.inf
    for i in grow:
        tip = tips[i]
        V = motion.velocity(tip.fracture, tip.end, t)
        out = max(out, float(keq[i]) / apparent_toughness(float(tip.h), V, KIc, Ep, mup))
    return out

