"""Coulomb friction on the pair system: a primal-dual active set with three
states a pair (open, stick, slip), the semi-smooth Newton method of Hueber,
Stadler & Wohlmuth (2008) written for 2D, where the tangential space of a
pair is one line and the slip direction one sign.

With the elasticity factorised, jumps depend on the row multipliers mu
(nodal forces; + on the + node) through the dense pair compliance S:

    jump(mu) = jump0 + S mu.

Rows: normal rows (w + g >= 0, mu_n >= 0, mu_n (w + g) = 0), prescribed
tangential rows ("slip" faces: jump = target) and Coulomb tangential rows
paired with their normal row p. On a Coulomb row the friction law acts on
the slip increment ds = s - s_ref from the last converged state s_ref:

    |mu_t| <= F = c w_p + mu_f mu_n            (bound; forces)
    |mu_t| <  F  ->  ds = 0                    (stick)
    |mu_t| =  F  ->  mu_t ds <= 0              (slip, against the increment)
    open pair    ->  mu_t = 0.

With lam = -mu_t the update of a contact pair's state is
    z = lam + c_t ds;  |z| > F: slip with sign(z), lam = F sign(z); else stick,
and F from the normal predictor mu_n - c_n (w + g) (Hueber et al.). For a
state set the equations are linear (in 2D the slip direction is a sign, not
a unit vector to linearise), so every iteration is one dense solve on the
pair system; the method stops when the set repeats. A pair changes between
stick and slip only where the law is violated by more than a band of
round-off (STATE_BAND) on either side of the bound: a pair at the bound
with a zero increment satisfies both. A set seen before that is not the
last one is cycling: then the same problem is solved as a fixed point on
the friction bound, each a bounded least-squares problem (Tresca
friction with the bound of the last normal forces is a convex quadratic
program with box bounds), which is how the frictionless solver falls back
too. With no Coulomb row this is the frictionless solver itself
(active_set.solve_active_set).

Cohesion makes the law discontinuous where a pair touches with no normal
force (it holds c w closed and nothing open): the discrete problem may then
have two solutions or none. On random 12-pair compliances with c = 5 % of
the force scale, 191 of 200 solve and 9 end in the ComputationError of the
fallback (tests/test_friction_solver.py); without cohesion all do.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ComputationError
from .active_set import ActiveSetResult, solve_active_set

OPEN, STICK, SLIP = 0, 1, 2
#: largest number of fixed-point solves on the friction bound (fallback)
FIXED_POINT_ITERATIONS = 200
#: the fallback's fixed point has converged when the normal forces change by less than this (relative)
FIXED_POINT_RTOL = 1e-13
#: the complementarity parameters are scaled by these in turn when the state sets cycle (the
#: semi-smooth Newton method is not globally convergent; another scaling changes its path)
SCALINGS = (1.0, 10.0, 0.1, 100.0, 0.01)
#: a closed pair whose tangential force is within this (relative) of the bound is at it: it slips
BOUND_RTOL = 1e-9
#: the iteration's band round the bound (relative to the largest force): a sticking pair slips when its
#: force is above the bound by more, a slipping one sticks when its increment turns back by more (times
#: c_t). A pair at the bound with a zero increment (the last trials of a critical-load search, a hair above
#: the load of their reference) satisfies both states to round-off; a one-sided band made such pairs
#: alternate, each slip pushing a neighbour over the bound by ~1e-11 and its own increment staying below
#: the band, and the sets cycled under every scaling (the stimulation network, 406 pairs).
STATE_BAND = 1e-12
#: residual of the linear equations, relative to the load scale, a converged set must reach
RESIDUAL_RTOL = 1e-10

_SINGULAR = ("contact: the pair system is singular (a pair is held by a displacement condition on both "
             "faces?)")


@dataclass
class FrictionRows:
    """What the friction law needs of the rows (m = rows): coulomb (m,) bool,
    the Coulomb tangential rows; partner (m,) their pair's normal row (-1
    elsewhere); friction (m,) mu_f; cohesion_force (m,) c times the pair's
    tributary length (N/m; the bound's cohesion part as a force)."""
    coulomb: np.ndarray
    partner: np.ndarray
    friction: np.ndarray
    cohesion_force: np.ndarray


@dataclass
class FrictionResult(ActiveSetResult):
    """ActiveSetResult with the tangential states: state (m,) OPEN / STICK /
    SLIP on Coulomb rows (the pair's state on its normal row too; a closed
    normal row without friction is SLIP), the reference slip and the law."""
    state: np.ndarray = None
    reference: np.ndarray = None
    law: FrictionRows = None

    def bound(self) -> np.ndarray:
        """(m,) the friction bound F (forces) on Coulomb rows (0 elsewhere)."""
        law = self.law
        F = np.zeros(len(self.mu))
        i = np.flatnonzero(law.coulomb)
        closed = self.state[i] != OPEN
        F[i] = np.where(closed, law.cohesion_force[i] + law.friction[i] * np.maximum(self.mu[law.partner[i]], 0.0),
                        0.0)
        return F

    def slip_increment(self) -> np.ndarray:
        """(m,) ds = s - s_ref on Coulomb rows (0 elsewhere)."""
        return np.where(self.law.coulomb, self.jump - self.reference, 0.0)

    def friction_residuals(self, weight) -> dict:
        """Largest violations of the friction law, relative: tractions to the
        largest row traction |mu| / weight, increments to the jump scale."""
        law = self.law
        w = np.maximum(np.asarray(weight, float), 1e-300)
        t = np.abs(self.mu) / w
        tscale = max(np.max(t, initial=0.0), 1e-300)
        ds = self.slip_increment()
        jscale = max(np.max(np.abs(self.jump0), initial=0.0), np.max(np.abs(self.jump), initial=0.0), 1e-300)
        c = law.coulomb
        over = (np.abs(self.mu) - self.bound()) / w
        slip, stick = c & (self.state == SLIP), c & (self.state == STICK)
        return {
            "bound": float(max(0.0, np.max(over[c], initial=0.0)) / tscale),
            "at_bound": float(np.max(np.abs(over[slip]), initial=0.0) / tscale),
            "direction": float(max(0.0, np.max(self.mu[slip] / w[slip] * ds[slip], initial=0.0)) / (tscale * jscale)),
            "stick_increment": float(np.max(np.abs(ds[stick]), initial=0.0) / jscale),
        }


def solve_friction(S, jump0, target, normal, law: FrictionRows, max_iter: int = 100, active=None,
                   start: FrictionResult | None = None):
    """The contact problem with Coulomb rows. target: -g on normal rows, the
    prescribed slip on prescribed tangential rows, the reference slip s_ref
    on Coulomb rows; active: the normal rows to start in contact (default:
    those penetrating without contact forces); start: a result on the same
    rows (the last solve) whose states the iteration starts from: the trials
    of a critical-load search differ by little and their state sets mostly
    repeat. The answer is that of the state set the iteration ends on, not
    of where it started; a start that does not settle is dropped. Without
    Coulomb rows, the frictionless active set."""
    S = np.asarray(S, float)
    jump0 = np.asarray(jump0, float)
    target = np.asarray(target, float)
    normal = np.asarray(normal, bool)
    coulomb = np.asarray(law.coulomb, bool)
    if not coulomb.any():
        return solve_active_set(S, jump0, target, normal, active=active)
    prescribed = ~normal & ~coulomb
    # c turns a jump (m) into a force (N/m): the inverse mean compliance of the rows
    cn = 1.0 / np.mean(np.abs(np.diag(S)[normal]))
    ct = 1.0 / np.mean(np.abs(np.diag(S)[coulomb]))

    history = []
    if getattr(start, "state", None) is not None and len(start.mu) == len(jump0):
        res = _active_set(S, jump0, target, normal, prescribed, law, cn, ct, max_iter, history,
                          states=_start_states(start, normal, law))
        if res is not None:
            return res
    for scale in SCALINGS:
        res = _active_set(S, jump0, target, normal, prescribed, law, cn * scale, ct * scale, max_iter, history,
                          active)
        if res is not None:
            return res
    return fixed_point_solve(S, jump0, target, normal, prescribed, law, history)


def _start_states(start: FrictionResult, normal, law) -> tuple:
    """(A, T, sign) of the iteration from a result: its closed normal rows,
    its pairs' states, a slip against its tangential force (a pair at the
    bound without force, F = 0, starts sticking)."""
    A = normal & np.asarray(start.active, bool)
    ci = np.flatnonzero(law.coulomb)
    T = np.full(len(A), OPEN, np.int8)
    sign = np.zeros(len(A))
    s = np.sign(-start.mu[ci])
    slip = (start.state[ci] == SLIP) & (s != 0)
    T[ci] = np.where(A[law.partner[ci]], np.where(slip, SLIP, STICK), OPEN)
    sign[ci] = np.where(T[ci] == SLIP, s, 0.0)
    return A, T, sign


def _active_set(S, jump0, target, normal, prescribed, law, cn, ct, max_iter, history, active=None, states=None):
    """The three-state iteration with complementarity parameters cn, ct,
    from `states` (A, T, sign) or else from the contact set `active`; None
    when the state sets cycle (or do not settle in max_iter)."""
    m = len(jump0)
    coulomb = np.asarray(law.coulomb, bool)
    partner = np.asarray(law.partner, np.int64)
    f = np.asarray(law.friction, float)
    b0 = np.asarray(law.cohesion_force, float)
    ci = np.flatnonzero(coulomb)
    pi = partner[ci]
    if states is not None:
        A, T, sign = (np.array(x) for x in states)
    else:
        A = normal & ((jump0 < target) if active is None else np.asarray(active, bool))
        T = np.full(m, OPEN, np.int8)
        T[ci] = np.where(A[pi], STICK, OPEN)
        sign = np.zeros(m)
    seen = {_key(A, T, sign)}
    load = max(np.max(np.abs(target - jump0), initial=0.0), 1e-300)
    for it in range(1, max_iter + 1):
        mu = _solve_set(S, jump0, target, normal, prescribed, A, T, sign, partner, f, b0)
        jump = jump0 + S @ mu
        if not np.all(np.isfinite(jump)):
            raise ComputationError("contact: NaN in the friction iteration")
        history.append(int(A.sum()))
        gamma = jump - target                     # on normal rows: w + g
        A_new = normal & (mu - cn * gamma > 0)
        T_new = np.full(m, OPEN, np.int8)
        sign_new = np.zeros(m)
        F = b0[ci] + f[ci] * np.maximum(mu[pi] - cn * gamma[pi], 0.0)
        z = -mu[ci] + ct * (jump[ci] - target[ci])
        band = STATE_BAND * max(np.max(np.abs(mu), initial=0.0), 1e-300)
        slipping = np.abs(z) > F + band
        direction = np.sign(z)
        # a slipping pair sticks again only when its increment turns against its direction by more than the
        # band, as a sticking one slips only above the bound by more than it (see STATE_BAND)
        was = T[ci] == SLIP
        keep = was & (sign[ci] * ct * (jump[ci] - target[ci]) >= -band)
        slipping = np.where(was, keep | slipping, slipping)
        direction = np.where(keep, sign[ci], direction)
        T_new[ci] = np.where(A_new[pi], np.where(slipping, SLIP, STICK), OPEN)
        sign_new[ci] = np.where(T_new[ci] == SLIP, direction, 0.0)
        if np.array_equal(A_new, A) and np.array_equal(T_new, T) and np.array_equal(sign_new, sign):
            eq = A | prescribed | (coulomb & (T == STICK))
            res = np.max(np.abs((jump - target)[eq]), initial=0.0)
            if res <= RESIDUAL_RTOL * max(load, np.max(np.abs(jump), initial=0.0)):
                return FrictionResult(mu, jump, A, len(history), history, jump0, state=_labels(T, mu, law),
                                      reference=target.copy(), law=law)
            return None
        key = _key(A_new, T_new, sign_new)
        if key in seen:
            return None   # cycling
        seen.add(key)
        A, T, sign = A_new, T_new, sign_new
    return None


def _labels(T, mu, law) -> np.ndarray:
    """The states as the law names them, by the traction: a closed pair at
    the bound slips, below it sticks. The iteration's own labels differ
    where both hold, at the bound with a zero increment (frictionless faces,
    or the last solve of a critical-load search, a hair above the load its
    reference was accepted at): there the pair is sliding, not held."""
    out = T.copy()
    ci = np.flatnonzero(law.coulomb)
    closed = T[ci] != OPEN
    F = law.cohesion_force[ci] + law.friction[ci] * np.maximum(mu[law.partner[ci]], 0.0)
    at = np.abs(mu[ci]) >= F * (1 - BOUND_RTOL)
    out[ci] = np.where(closed, np.where(at, SLIP, STICK), OPEN)
    return out


def _key(A, T, sign) -> bytes:
    return A.tobytes() + T.tobytes() + np.sign(sign).astype(np.int8).tobytes()


def _solve_set(S, jump0, target, normal, prescribed, A, T, sign, partner, f, b0) -> np.ndarray:
    """The multipliers of one state set: jump = target on contact normal,
    prescribed and sticking rows; mu_t = -sign (b0 + f mu_n) on slipping
    rows; mu = 0 on open ones."""
    m = len(jump0)
    mu = np.zeros(m)
    slip = T == SLIP
    eq = np.flatnonzero((normal & A) | prescribed | (T == STICK))
    sl = np.flatnonzero(slip)
    unknown = np.r_[eq, sl]
    if len(unknown) == 0:
        return mu
    col = {int(j): k for k, j in enumerate(unknown)}
    n = len(unknown)
    M = np.zeros((n, n))
    r = np.zeros(n)
    M[:len(eq)] = S[np.ix_(eq, unknown)]
    r[:len(eq)] = target[eq] - jump0[eq]
    for k, j in enumerate(sl, start=len(eq)):
        M[k, k] = 1.0
        M[k, col[int(partner[j])]] = sign[j] * f[j]
        r[k] = -sign[j] * b0[j]
    try:
        mu[unknown] = np.linalg.solve(M, r)
    except np.linalg.LinAlgError:
        raise ComputationError(_SINGULAR) from None
    return mu


def fixed_point_solve(S, jump0, target, normal, prescribed, law, history):
    """Coulomb friction as a fixed point on the bound F = c w + mu_f mu_n:
    each iterate is Tresca friction with the last normal forces, the convex
    problem min 1/2 mu^T S mu - mu^T (target - jump0) with mu_n >= 0 and
    -F <= mu_t <= F (its KKT conditions: contact, stick inside the box,
    slip against the increment on its faces), by bounded-variable least
    squares."""
    from scipy.linalg import solve_triangular
    from scipy.optimize import lsq_linear

    m = len(jump0)
    coulomb = np.asarray(law.coulomb, bool)
    ci = np.flatnonzero(coulomb)
    pi = law.partner[ci]
    mu = np.zeros(m)
    iterations = 0
    for _ in range(FIXED_POINT_ITERATIONS):
        jump = jump0 + S @ mu
        closed = (mu[pi] > 0) | ((jump - target)[pi] <= 0)
        F = np.where(closed, law.cohesion_force[ci] + law.friction[ci] * np.maximum(mu[pi], 0.0), 0.0)
        lo = np.where(normal, 0.0, -np.inf)
        hi = np.full(m, np.inf)
        lo[ci], hi[ci] = -F, F
        free = hi > lo
        idx = np.flatnonzero(free)
        new = np.zeros(m)
        if len(idx):
            try:
                L = np.linalg.cholesky(S[np.ix_(idx, idx)])
            except np.linalg.LinAlgError:
                raise ComputationError(_SINGULAR) from None
            b = solve_triangular(L, (target - jump0)[idx], lower=True)
            res = lsq_linear(L.T, b, bounds=(lo[idx], hi[idx]), method="bvls", tol=1e-15, lsmr_tol=None,
                             max_iter=max(100, 10 * len(idx)))
            if res.status < 1:
                raise ComputationError(f"contact: friction: the active set cycles and bounded least squares "
                                       f"failed ({res.message})")
            iterations += int(res.nit)
            new[idx] = np.clip(res.x, lo[idx], hi[idx])
        change = np.max(np.abs(new - mu)[normal], initial=0.0)
        scale = max(np.max(np.abs(new), initial=0.0), 1e-300)
        mu = new
        history.append(int(np.sum(normal & (mu > 0))))
        if change <= FIXED_POINT_RTOL * scale:
            break
    else:
        raise ComputationError(f"contact: friction: the active set cycles and the fixed point on the friction "
                               f"bound did not converge in {FIXED_POINT_ITERATIONS} iterations")
    jump = jump0 + S @ mu
    if not np.all(np.isfinite(jump)):
        raise ComputationError("contact: NaN in the friction solve")
    active = normal & (mu > 0.0)
    state = np.full(m, OPEN, np.int8)
    state[ci] = np.where(active[pi] | ((jump - target)[pi] <= 0), STICK, OPEN)
    state = _labels(state, mu, law)
    return FrictionResult(mu, jump, active, len(history) + iterations, history, jump0, fallback=True,
                          state=state, reference=target.copy(), law=law)
