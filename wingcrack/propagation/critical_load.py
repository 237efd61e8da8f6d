"""The load factor at which the first tip reaches the toughness.

Instead of the published code's creeping 1% load increase, the critical
load factor is found directly:
- positively homogeneous problems (no gap, no in-situ stress, no body force:
  the response, contact included, scales with the load factor) need one
  solve: lambda_c = lambda KIc / max K_eq(lambda);
- otherwise a safeguarded secant (Illinois) iteration on the piecewise
  linear f(lambda) = max K_eq(lambda) - KIc, bracketed by doubling, to a
  relative tolerance of 1e-6.
With friction the response depends on the load path: the search goes
forward from the last converged state, and every trial that becomes the
bracket's lower end is accepted (`accept`) as the state the next trials
start from; a trial above the critical load is never a starting state.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np


#: a trial whose K_eq exceeds KIc by at most this fraction of it has found the
#: root: K_eq is computed to ~1e-15 relative, and with a slope of K_eq in the load
#: factor above 1e-6 KIc per unit factor the root is then within the search's
#: 1e-6 relative tolerance (without this test a secant that hits the root to
#: round-off leaves the bracket's other end to reach it by a dozen halvings)
AT_ROOT = 1e-12


@dataclass
class CriticalLoad:
    load_factor: float | None   # None: no tip reaches KIc below the limit
    solves: int


def scales_with_load(case, fset, network=None) -> bool:
    """Does the whole response of the fracture set `fset` scale with the
    load factor (a scaled load, no in-situ stress, no body force, no gap;
    with load = "pressure" also no bc value or slip, which stay fixed; with
    "injection" nor a given pressure outside the injected `network`, (n,)
    bool)?"""
    m = case.material
    body = m.density * np.linalg.norm(case.body.gravity)
    load = case.propagation.load
    fixed = load in ("pressure", "injection") and (any(any(b.value) for b in case.bcs)
                                                   or any(f.law.slip for f in fset.fractures))
    if load == "injection":
        fixed = fixed or any(f.law.pressure for f, inside in zip(fset.fractures, network) if not inside)
    return (load in ("scale", "pressure", "injection") and not fixed and not np.any(case.stress.tensor())
            and body == 0 and all(f.law.gap == 0 for f in fset.fractures))


def critical_load_factor(keq: Callable[[float], float], KIc: float, start: float,
                         homogeneous: bool, limit: float, rtol: float = 1e-6,
                         accept: Callable[[], None] | None = None, first: float | None = None,
                         beyond: Callable[[float], bool] | None = None,
                         at_root: float = AT_ROOT, two_sided: bool = False,
                         secant_above: bool = False) -> CriticalLoad:
    """keq(lam) -> largest K_eq over the growing tips at load factor lam.
    accept(): the last keq solve becomes the state later solves start from
    (friction); called on each lower end of the bracket. first: the first
    trial above start (default 2 start, or start + 1); beyond(lam): after a
    trial at lam below KIc, is the load past what the run can reach (no
    answer then, as past `limit`)? at_root: a trial with KIc <= K_eq <=
    KIc (1 + at_root) is the answer; two_sided: also one with K_eq down to
    KIc (1 - at_root) (where the caller takes a root a hair below KIc: a
    response linear in the load puts the secant's trial on either side by
    round-off, and the far end would creep to it by halves). secant_above:
    once two trials lie above KIc, the next is their secant's root where it
    falls inside the bracket (K_eq is piecewise linear in the load: zero, or
    flat, until the faces open or slip, then linear; the regula falsi from a
    flat lower end creeps, the secant of two trials on the linear part is
    the root).

    The load only rises: the result is >= start. If K_eq(start) >= KIc, the
    answer is start."""
    accept = accept or (lambda: None)
    beyond = beyond or (lambda lam: False)
    solves = 0
    if homogeneous:
        k = keq(1.0)
        solves += 1
        if k <= 0:
            return CriticalLoad(None, solves)
        lam = max(start, KIc / k)
        return CriticalLoad(lam if lam <= limit else None, solves)
    lo = start
    f_lo = keq(lo) - KIc
    solves += 1
    if f_lo >= 0:
        return CriticalLoad(lo, solves)
    accept()
    hi = first if first is not None and first > lo else max(2.0 * lo, lo + 1.0) if lo > 0 else 1.0
    while True:
        f_hi = keq(hi) - KIc
        solves += 1
        if f_hi >= 0:
            break
        if hi >= limit or beyond(hi):
            return CriticalLoad(None, solves)
        accept()
        lo, f_lo = hi, f_hi
        hi = min(2.0 * hi, limit)
    # Illinois: secant with the retained end's value halved when it repeats
    side = 0
    above = [(hi, f_hi)]   # the trials above KIc, their values as computed
    for _ in range(200):
        lam = None
        if secant_above and len(above) > 1 and above[-1][1] != above[-2][1]:
            (x1, g1), (x2, g2) = above[-2:]
            lam = x2 - g2 * (x2 - x1) / (g2 - g1)
            lam = lam if lo < lam < hi else None
        if lam is None:
            lam = hi - f_hi * (hi - lo) / (f_hi - f_lo) if f_hi != f_lo else 0.5 * (lo + hi)
        if not (lo < lam < hi):
            lam = 0.5 * (lo + hi)
        f = keq(lam) - KIc
        solves += 1
        if (-at_root * KIc if two_sided else 0.0) <= f <= at_root * KIc:
            # K_eq(lam) is KIc to round-off: lam is the critical load (the bracket's
            # far end would only creep up to it, by halves from the other side)
            return CriticalLoad(lam, solves)
        if f >= 0:
            hi, f_hi = lam, f
            above.append((lam, f))
            if side == 1:
                f_lo *= 0.5
            side = 1
        else:
            accept()
            lo, f_lo = lam, f
            if side == -1:
                f_hi *= 0.5
            side = -1
        if hi - lo <= rtol * hi:
            return CriticalLoad(hi, solves)
    return CriticalLoad(hi, solves)
