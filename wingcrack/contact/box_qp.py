"""Convex quadratic programs on a box with linear equalities: the Tresca
and frictionless pair problems, with the equilibrium of pieces that only the
contact holds.

    min q(x) = 1/2 x^T H x - c^T x    lo <= x <= hi,    G^T x + e = 0

H (m, m) SPD, bounds possibly infinite, G (m, r) of full column rank (r may
be 0). In the pair problem x are the row multipliers (forces), H the pair
compliance, the gradient H x - c the jumps minus their targets, and the
equality's multipliers alpha the amplitudes of the rigid modes (jump = jump0
+ S forces + G alpha): at the solution the stationarity H x - c + G alpha = g
with g >= 0 where x is at its lower bound, <= 0 at its upper, 0 between.

The box: Bertsekas' projected Newton method (SIAM J. Control Optim. 20,
1982): a Newton step on the variables off the (epsilon-)active bounds, a
scaled gradient step on the others, projected on the box and cut back by
an Armijo rule along the projection arc. It decreases q at every step, so it
cannot cycle, and it identifies the active face in finitely many steps,
after which the Newton step on a quadratic is exact.
The equalities: the method of multipliers (Hestenes, Powell) with the
penalty raised while the equality residual falls too slowly; an
equality that no point of the box meets (a piece that contact cannot hold)
leaves a residual the penalty does not reduce: Infeasible, with that
residual (the generalised force that nothing balances).
The end is exact: once a face is identified, its KKT system (bordered by G)
is solved directly and the answer kept only if it meets every condition to
round-off.
"""
from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
from scipy import linalg

#: Armijo's sufficient-decrease fraction and step reduction
ARMIJO = 1e-4
BACKTRACK = 0.5
#: the optimality conditions hold when their violation is below this times the problem's scale
RTOL = 1e-12
#: most projected Newton steps of one box problem (each one Cholesky factorisation)
MAX_STEPS = 200
#: method of multipliers: the penalty starts at this times the ratio of H's to G G^T's diagonal
RHO0 = 1e3
#: ... is raised tenfold when the residual falls by less than this factor in an outer step
RHO_SLOW = 0.1
#: ... up to this ratio (beyond it H + rho G G^T loses H's digits in double precision)
RHO_MAX = 1e10
#: most outer steps
MAX_OUTER = 40
#: an equality residual the largest penalty leaves below this (relative) is its round-off, not a
#: residual no point meets: H + rho G G^T at rho = RHO_MAX keeps ~6 of H's digits, so the multipliers'
#: updates stall at ~1e-12..1e-10 of the scale; an unbalanced load is of the order of the scale itself
EQUALITY_FLOOR = 1e-8


class Infeasible(Exception):
    """The equalities cannot be met inside the box: residual (r,) is the
    least generalised force G^T x + e left over (unbalanced)."""

    def __init__(self, residual):
        self.residual = np.asarray(residual, float)
        super().__init__("the equalities cannot be met inside the bounds")


@dataclass
class BoxQPResult:
    x: np.ndarray          # (m,)
    alpha: np.ndarray      # (r,) multipliers of the equalities
    gradient: np.ndarray   # (m,) H x - c + G alpha
    steps: int             # projected Newton steps in all
    exact: bool            # ended on the face's KKT system solved directly


def solve_box_qp(H, c, lo, hi, G=None, e=None, x0=None, alpha0=None) -> BoxQPResult:
    """The minimiser of the program above (see the module); x0, alpha0: a
    start (the last answer of a sequence of nearby problems)."""
    H = np.asarray(H, float)
    c = np.asarray(c, float)
    m = len(c)
    lo = np.broadcast_to(np.asarray(lo, float), (m,)).copy()
    hi = np.broadcast_to(np.asarray(hi, float), (m,)).copy()
    r = 0 if G is None else int(np.shape(G)[1])
    G = np.zeros((m, 0)) if r == 0 else np.asarray(G, float)
    e = np.zeros(0) if r == 0 else np.asarray(e, float)
    x = np.zeros(m) if x0 is None else np.asarray(x0, float).copy()
    x = np.clip(x, lo, hi)
    d = np.abs(np.diag(H)).copy()
    d[d == 0] = 1.0
    if m == 0:
        return BoxQPResult(x, np.zeros(r), np.zeros(0), 0, True)
    if r == 0:
        x, steps = _projected_newton(H, c, lo, hi, x, d)
        res = _polish(H, c, lo, hi, G, e, x, np.zeros(0))
        if res is not None:
            res.steps += steps
            return res
        return BoxQPResult(x, np.zeros(0), H @ x - c, steps, False)

    alpha = np.zeros(r) if alpha0 is None else np.asarray(alpha0, float).copy()
    GG = np.einsum("ij,ij->j", G, G)
    rho = RHO0 * float(np.mean(d)) / max(float(np.mean(GG)), 1e-300)
    rho_cap = RHO_MAX * float(np.mean(d)) / max(float(np.mean(GG)), 1e-300)
    steps, last, stalled = 0, np.inf, 0
    escale = _equality_scale(G, e, x, lo, hi, float(np.max(np.abs(c) / d, initial=0.0)))
    for _ in range(MAX_OUTER):
        Hr = H + rho * (G @ G.T)
        cr = c - G @ (alpha + rho * e)
        x, k = _projected_newton(Hr, cr, lo, hi, x, np.abs(np.diag(Hr)))
        steps += k
        residual = G.T @ x + e
        res = _polish(H, c, lo, hi, G, e, x, alpha + rho * residual)
        if res is not None:
            res.steps += steps
            return res
        size = float(np.max(np.abs(residual), initial=0.0))
        alpha = alpha + rho * residual
        if size <= RTOL * escale:
            return BoxQPResult(x, alpha, H @ x - c + G @ alpha, steps, False)
        if size > RHO_SLOW * last:
            if rho >= rho_cap:
                stalled += 1
                if stalled >= 3:
                    if size <= EQUALITY_FLOOR * escale:   # round-off of H + rho G G^T: met
                        return BoxQPResult(x, alpha, H @ x - c + G @ alpha, steps, False)
                    raise Infeasible(residual)
            rho = min(10.0 * rho, rho_cap)
        last = size
    raise Infeasible(G.T @ x + e)


def _equality_scale(G, e, x, lo, hi, force=0.0) -> float:
    """What the equality residual is measured against: the generalised force of
    the largest finite bound, of x or of `force` (the forces that close the
    jumps, |c| / diag(H)), or e."""
    finite = np.where(np.isfinite(hi), np.abs(hi), 0.0) + np.where(np.isfinite(lo), np.abs(lo), 0.0)
    f = max(float(np.max(finite, initial=0.0)), float(np.max(np.abs(x), initial=0.0)), float(force))
    return max(float(np.max(np.abs(e), initial=0.0)), f * float(np.max(np.abs(G), initial=0.0)), 1e-300)


def _projected_newton(H, c, lo, hi, x, d):
    """Bertsekas' projected Newton method on the box, from x (in it);
    d > 0 the scaling of the gradient steps (H's diagonal). Returns (x, steps)."""
    fscale = max(float(np.max(np.abs(c) / d, initial=0.0)), float(np.max(np.abs(x), initial=0.0)), 1e-300)
    tol = RTOL * fscale
    eps_bar = 1e-3 * fscale
    for k in range(1, MAX_STEPS + 1):
        g = H @ x - c
        w = float(np.max(np.abs(x - np.clip(x - g / d, lo, hi)), initial=0.0))
        if w <= tol:
            return x, k - 1
        eps = min(eps_bar, w)
        at = ((x <= lo + eps) & (g > 0)) | ((x >= hi - eps) & (g < 0))
        F = np.flatnonzero(~at)
        p = np.where(at, -g / d, 0.0)
        if len(F):
            try:
                cf = linalg.cho_factor(H[np.ix_(F, F)], lower=True, check_finite=False)
                p[F] = -linalg.cho_solve(cf, g[F], check_finite=False)
            except linalg.LinAlgError:
                p[F] = -g[F] / d[F]
        a = 1.0
        while True:
            xa = np.clip(x + a * p, lo, hi)
            s = xa - x
            # q(x) - q(xa) from the step itself: the difference of q's values would lose half the digits
            decrease = -float(g @ s) - 0.5 * float(s @ (H @ s))
            want = ARMIJO * (a * float(-(g[F] @ p[F])) + float(g[at] @ (x[at] - xa[at])))
            if decrease >= want:
                break
            a *= BACKTRACK
            if a < 1e-30:   # no decrease left at round-off
                return x, k
        x = xa
    return x, MAX_STEPS


def _polish(H, c, lo, hi, G, e, x, alpha) -> BoxQPResult | None:
    """The KKT system of the face x lies on (its variables at a bound stay
    there), bordered by the equalities, solved directly: the answer when it
    meets every condition to round-off, else None."""
    m = len(x)
    scale = max(float(np.max(np.abs(x), initial=0.0)), 1e-300)
    band = 1e-9 * scale
    at_lo = np.isfinite(lo) & (x <= lo + band)
    at_hi = np.isfinite(hi) & (x >= hi - band) & ~at_lo
    fixed = at_lo | at_hi
    F = np.flatnonzero(~fixed)
    r = G.shape[1]
    y = np.where(at_lo, lo, np.where(at_hi, hi, x))
    rhs_top = c[F] - H[np.ix_(F, np.flatnonzero(fixed))] @ y[fixed]
    if r:
        rhs_bottom = -e - G[fixed].T @ y[fixed]
        M = np.block([[H[np.ix_(F, F)], G[F]], [G[F].T, np.zeros((r, r))]])
        rhs = np.r_[rhs_top, rhs_bottom]
    else:
        M, rhs = H[np.ix_(F, F)], rhs_top
    if len(rhs):
        try:
            with warnings.catch_warnings():   # a singular face (a piece it cannot hold) is refused below
                warnings.simplefilter("ignore", linalg.LinAlgWarning)
                sol = linalg.solve(M, rhs, assume_a="sym" if r else "pos", check_finite=False)
        except (linalg.LinAlgError, ValueError):
            return None
        if not np.all(np.isfinite(sol)):
            return None
        y[F] = sol[:len(F)]
        alpha = sol[len(F):]
    g = H @ y - c + (G @ alpha if r else 0.0)
    yscale = max(float(np.max(np.abs(y), initial=0.0)), 1e-300)
    gscale = max(float(np.max(np.abs(c), initial=0.0)), float(np.max(np.abs(H @ y), initial=0.0)), 1e-300)
    tol_x, tol_g = 1e-10 * yscale, 1e-10 * gscale
    if np.any(y[F] < lo[F] - tol_x) or np.any(y[F] > hi[F] + tol_x):
        return None
    pinned = lo == hi   # a variable with no room: its gradient has no sign to meet
    if np.any(g[at_lo & ~pinned] < -tol_g) or np.any(g[at_hi] > tol_g) or np.any(np.abs(g[F]) > tol_g):
        return None
    force = float(np.max(np.abs(c) / np.maximum(np.abs(np.diag(H)), 1e-300), initial=0.0))
    if r and np.max(np.abs(G.T @ y + e), initial=0.0) > 1e-10 * _equality_scale(G, e, y, lo, hi, force):
        return None
    y = np.clip(y, lo, hi)
    return BoxQPResult(y, np.asarray(alpha, float), g, 0, True)
