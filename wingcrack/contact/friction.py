"""Coulomb friction on the pair system: a primal-dual active set with three
states a pair (open, stick, slip), the semi-smooth Newton method of Hueber,
Stadler & Wohlmuth (2008) written for 2D, where the tangential space of a
pair is one line and the slip direction one sign.

With the elasticity factorised, jumps depend on the row multipliers mu
(nodal forces; + on the + node) through the dense pair compliance S, and,
where a piece of the body is held by contact alone, on the amplitudes alpha
of its rigid-body modes (their jumps G):

    jump(mu, alpha) = jump0 + S mu + G alpha,    G^T mu + e = 0,

the second the piece's equilibrium (e: its other loads as generalised forces
on the modes; FETI's coarse problem). Without such pieces G has no columns.

Rows: normal rows (w + g >= 0, mu_n >= 0, mu_n (w + g) = 0), prescribed
tangential rows ("slip" faces: jump = target) and Coulomb tangential rows
paired with their normal row p. On a Coulomb row the friction law acts on
the slip increment ds = s - s_ref from the last converged state s_ref:

    |mu_t| <= F = c w_p + mu_f mu_n                (bound; forces; c only while touching)
    |mu_t| <  F  ->  ds = 0                         (stick)
    |mu_t| =  F  ->  mu_t ds <= 0                   (slip, against the increment)

Cohesion is held by faces that touch. Whether faces carrying no normal force
touch is a question of a tolerance: under pure shear a straight crack on a
finite mesh slides with an opening of a few 1e-4 of its slip (measured:
2e-8 m against 8e-5 m), which must not decide whether its cohesion holds.
A pair touches while its opening w + g is below TOUCH_RTOL of the pair
system's jump scale (the largest jump without pair forces, or target); it
is open from twice that; between the two either holds. So a pair holds its
cohesion only if its opening stays below 2 tol, and must hold it if the
opening is below tol. Where the cohesion opens a pair beyond 2 tol that
closes without it, no state satisfies this law (the bound jumps from c w_p
to 0 as the faces part: the earlier fixed point alternated between the two
forever); there the pair's bond breaks: it keeps its friction and loses its
cohesion for the solve (FrictionResult.broken counts such pairs).

With lam = -mu_t the update of a closed pair's state is
    z = lam + c_t ds;  |z| > F: slip with sign(z), lam = F sign(z); else stick,
and F from the normal predictor mu_n - c_n (w + g) (Hueber et al.); a pair
holds its cohesion in the next set where it is predicted closed or its
opening is below 1.5 tol. For a state set the equations are linear (in 2D
the slip direction is a sign, not a unit vector to linearise), so every
iteration is one dense solve on the pair system; the method stops when the
set repeats. A pair changes between stick and slip
only where the law is violated by more than a band of round-off
(STATE_BAND) on either side of the bound: a pair at the bound with a zero
increment satisfies both. The method is not globally convergent: where the
state sets cycle, the fallback fixes which pairs hold cohesion (all at
first) and solves the law that is then continuous, by the same iteration
or else as a fixed point on the friction bound, each iterate a Tresca
problem (the bound of the last forces fixed: a convex quadratic program
with box bounds and the pieces' equilibrium as equalities, contact.box_qp),
damped where it oscillates; pairs that open beyond 2 tol lose their
cohesion and the law is solved again (at most once a pair: it ends).
With no Coulomb row and no floating piece this is the frictionless solver
itself (active_set.solve_active_set).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ComputationError
from .active_set import ActiveSetResult, solve_active_set
from .box_qp import Infeasible, solve_box_qp

OPEN, STICK, SLIP = 0, 1, 2
#: largest number of Tresca problems of the fallback's fixed point
FIXED_POINT_ITERATIONS = 200
#: the fixed point has converged when the bound changes by less than this (relative to the largest force)
FIXED_POINT_RTOL = 1e-13
#: the complementarity parameters are scaled by these in turn when the state sets cycle (the
#: semi-smooth Newton method is not globally convergent; another scaling changes its path)
SCALINGS = (1.0, 10.0, 0.1)
#: state sets one semi-smooth Newton attempt may visit (it ends in a few where it converges)
MAX_ITERATIONS = 40
#: a closed pair whose tangential force is within this (relative) of the bound is at it: it slips
BOUND_RTOL = 1e-9
#: the iteration's band round the bound (relative to the largest force): a sticking pair slips when its
#: force is above the bound by more, a slipping one sticks when its increment turns back by more (times
#: c_t). A pair at the bound with a zero increment (the last trials of a critical-load search, a hair above
#: the load of their reference) satisfies both states to round-off; a one-sided band made such pairs
#: alternate, each slip pushing a neighbour over the bound by ~1e-11 and its own increment staying below
#: the band, and the sets cycled under every scaling.
STATE_BAND = 1e-12
#: residual of the linear equations, relative to the load scale, a converged set must reach
RESIDUAL_RTOL = 1e-10
#: faces open by less than this times the jump scale touch (they hold their cohesion), beyond twice it not
TOUCH_RTOL = 1e-3

_SINGULAR = ("contact: the pair system is singular (a pair is held by a displacement condition on both "
             "faces?)")


class Mechanism(ComputationError):
    """A piece held by contact alone that the contact cannot hold: residual
    (r,) is the generalised force on its rigid modes that no admissible
    contact force balances, or (free_motion) a rigid motion that none of the
    holding rows resists (the caller names the motion)."""

    def __init__(self, residual, free_motion: bool = False, closed=None):
        self.residual = np.asarray(residual, float)
        self.free_motion = free_motion   # residual is a motion nothing resists, not an unbalanced force
        self.closed = closed             # (m,) the normal rows closed at the end, where known
        super().__init__("contact cannot hold a piece of the body that only contact holds")


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
class Rigid:
    """The rigid modes of the pieces only contact holds: G (m, r) their
    jumps per unit amplitude, e (r,) the other loads' generalised forces on
    them (equilibrium: G^T mu + e = 0); e_scale (r,) the sum of the
    magnitudes of the terms of e (its round-off is ~1e-16 of that)."""
    G: np.ndarray
    e: np.ndarray
    e_scale: np.ndarray = None


@dataclass
class FrictionResult(ActiveSetResult):
    """ActiveSetResult with the tangential states: state (m,) OPEN / STICK /
    SLIP on Coulomb rows (the pair's state on its normal row too; a closed
    normal row without friction is SLIP), the reference slip, the law,
    cohesive (m,) the Coulomb rows whose pair holds its cohesion, touch the
    touching tolerance (m), broken the pairs whose bond broke (see the
    module) and alpha (r,) the rigid modes' amplitudes."""
    state: np.ndarray = None
    reference: np.ndarray = None
    law: FrictionRows = None
    cohesive: np.ndarray = None
    touch: float = 0.0
    broken: int = 0
    alpha: np.ndarray = None
    loose: int = 0   # rigid motions of pieces no face holds and no load drives (placed, see _held)

    def bound(self) -> np.ndarray:
        """(m,) the friction bound F (forces) on Coulomb rows (0 elsewhere)."""
        law = self.law
        F = np.zeros(len(self.mu))
        i = np.flatnonzero(law.coulomb)
        F[i] = np.where(self.cohesive[i], law.cohesion_force[i], 0.0) + \
            law.friction[i] * np.maximum(self.mu[law.partner[i]], 0.0)
        return F

    def slip_increment(self) -> np.ndarray:
        """(m,) ds = s - s_ref on Coulomb rows (0 elsewhere)."""
        return np.where(self.law.coulomb, self.jump - self.reference, 0.0)

    def friction_residuals(self, weight) -> dict:
        """Largest violations of the friction law, relative: tractions to the
        largest row traction |mu| / weight, increments to the jump scale;
        "touch": the largest opening of a pair that holds cohesion beyond
        2 tol (relative to tol; 0 where the law holds)."""
        law = self.law
        w = np.maximum(np.asarray(weight, float), 1e-300)
        t = np.abs(self.mu) / w
        tscale = max(np.max(t, initial=0.0), 1e-300)
        ds = self.slip_increment()
        jscale = max(np.max(np.abs(self.jump0), initial=0.0), np.max(np.abs(self.jump), initial=0.0), 1e-300)
        c = law.coulomb
        F = self.bound()
        over = (np.abs(self.mu) - F) / w
        slip, stick = c & (self.state == SLIP), c & (self.state == STICK)
        i = np.flatnonzero(c & self.cohesive & (law.cohesion_force > 0))
        opening = (self.jump - self.reference)[law.partner[i]]
        return {
            "bound": float(max(0.0, np.max(over[c], initial=0.0)) / tscale),
            "at_bound": float(np.max(np.abs(over[slip]), initial=0.0) / tscale),
            "direction": float(max(0.0, np.max(self.mu[slip] / w[slip] * ds[slip], initial=0.0)) / (tscale * jscale)),
            "stick_increment": float(np.max(np.abs(ds[stick & (F > 0)]), initial=0.0) / jscale),
            "touch": float(max(0.0, np.max(opening, initial=0.0) - 2 * self.touch) / max(self.touch, 1e-300)),
        }


@dataclass
class _Problem:
    """One pair problem with its derived data."""
    S: np.ndarray
    jump0: np.ndarray
    target: np.ndarray
    normal: np.ndarray
    prescribed: np.ndarray
    law: FrictionRows
    G: np.ndarray      # (m, r)
    e: np.ndarray      # (r,)
    touch: float
    e_scale: np.ndarray = None   # (r,)
    #: the solve of one state set, where S is not at hand (fem.pair_saddle): (A, T, sign, C) -> (mu, jump)
    solve: object = None
    c0: float = None   # the complementarity parameters' scale without S (N/m per m)
    last_states: tuple = None   # (A, T, sign) the last iteration reached (where it cycled)
    cycle_rows: np.ndarray = None   # (m,) bool: the rows whose states the last cycle changed
    last_C: np.ndarray = None       # (m,) the touching flags of the last converged set

    @classmethod
    def of(cls, S, jump0, target, normal, prescribed, law, rigid):
        m = len(jump0)
        r = 0 if rigid is None else int(np.shape(rigid.G)[1])
        jump0, target = np.asarray(jump0, float), np.asarray(target, float)
        scale = max(float(np.max(np.abs(jump0), initial=0.0)), float(np.max(np.abs(target), initial=0.0)), 1e-300)
        return cls(None if S is None else np.asarray(S, float), jump0, target, np.asarray(normal, bool), np.asarray(prescribed, bool), law,
                   np.zeros((m, 0)) if r == 0 else np.asarray(rigid.G, float),
                   np.zeros(0) if r == 0 else np.asarray(rigid.e, float), TOUCH_RTOL * scale,
                   None if r == 0 or rigid.e_scale is None else np.asarray(rigid.e_scale, float))

    @property
    def ci(self):
        return np.flatnonzero(self.law.coulomb)

    @property
    def pi(self):
        return np.asarray(self.law.partner, np.int64)[self.ci]


def solve_friction(S, jump0, target, normal, law: FrictionRows, max_iter: int = MAX_ITERATIONS, active=None,
                   start: FrictionResult | None = None, rigid: Rigid | None = None):
    """The contact problem with Coulomb rows. target: -g on normal rows, the
    prescribed slip on prescribed tangential rows, the reference slip s_ref
    on Coulomb rows; active: the normal rows to start in contact (default:
    those penetrating without contact forces); start: a result on the same
    rows (the last solve) whose states the iteration starts from: the trials
    of a critical-load search differ by little and their state sets mostly
    repeat. The answer is that of the state set the iteration ends on, not
    of where it started; a start that does not settle is dropped. rigid:
    the rigid modes of pieces only contact holds (Mechanism where it cannot).
    Without Coulomb rows or such pieces, the frictionless active set."""
    normal = np.asarray(normal, bool)
    coulomb = np.asarray(law.coulomb, bool)
    r = 0 if rigid is None else int(np.shape(rigid.G)[1])
    if not coulomb.any() and r == 0:
        return solve_active_set(S, jump0, target, normal, active=active)
    P = _Problem.of(S, jump0, target, normal, ~normal & ~coulomb, law, rigid)
    if r:
        res = _loose_first(P, max_iter, active, start)
        if res is not None:
            return res
    cn, ct = _parameters(P)
    history = []
    if getattr(start, "state", None) is not None and len(start.mu) == len(P.jump0):
        res = _active_set(P, cn, ct, max_iter, history, states=_start_states(start, P))
        if res is not None:
            return _held(P, res)
    for k in SCALINGS:
        res = _active_set(P, cn * k, ct * k, max_iter, history, active)
        if res is not None:
            return _held(P, res)
    return _held(P, _fallback(P, history, max_iter))


#: the rigid modes' jumps on the rows that hold (closed normal, sticking, prescribed) determine the
#: amplitudes when their smallest singular value is above this times the largest
HELD_RTOL = 1e-8
#: a load on a rigid motion below this times the magnitude of the terms it sums is round-off: the
#: motion is unloaded (the in-situ stress's load on an inner piece sums to zero, to ~1e-16 of its terms)
UNLOADED_RTOL = 1e-9


def _held(P: _Problem, res: FrictionResult) -> FrictionResult:
    """res, where the rows that hold fix every rigid mode. A motion they
    leave free that a load drives: Mechanism. One that no load drives (a
    piece whose faces all opened around it, with nothing on it, or with a
    fluid pressure all round): the piece is loose, its place undetermined by
    the equations; it is put in the middle of its opening (_middle), and
    res.loose counts such motions."""
    r = P.G.shape[1]
    if r == 0:
        return res
    law = P.law
    holding = (P.normal & res.active) | P.prescribed | (np.asarray(law.coulomb, bool) & (res.state == STICK))
    closed = P.normal & res.active
    Gh = P.G[holding]
    if len(Gh):
        _, sv, vt = np.linalg.svd(Gh)
        sv = np.r_[sv, np.zeros(r - len(sv))]
        vt = np.vstack([vt, _complement(vt, r)]) if len(vt) < r else vt
        free = sv <= HELD_RTOL * max(float(np.max(np.linalg.norm(P.G, axis=0))), 1e-300)
    else:
        vt, free = np.eye(r), np.ones(r, bool)
    if not free.any():
        return res
    V = vt[free].T                                           # (r, k) the free motions
    scale = np.abs(V).T @ (P.e_scale if P.e_scale is not None else np.abs(P.e))
    if np.any(np.abs(V.T @ P.e) > UNLOADED_RTOL * np.maximum(scale, 1e-300)) or P.e_scale is None:
        k = int(np.argmax(np.abs(V.T @ P.e)))
        raise Mechanism(V[:, k], free_motion=True, closed=closed)
    GV = P.G[P.normal] @ V
    on = np.any(np.abs(GV) > 0, axis=1)
    GV, gamma = GV[on], (res.jump - P.target)[P.normal][on]
    z = _middle(GV, gamma)
    res.alpha = res.alpha + V @ z
    res.jump = res.jump + P.G @ (V @ z)
    res.loose = int(free.sum())
    return res


def _middle(GV, gamma) -> np.ndarray:
    """The motion z of a loose piece that makes the least opening of its faces
    (gamma + GV z, all >= 0 at z = 0: the solution found is admissible) the
    largest, no farther than the largest opening: the middle of its opening
    (a linear program). z = 0 where that fails."""
    from scipy.optimize import linprog

    k = GV.shape[1]
    reach = max(float(np.max(gamma, initial=0.0)), 1e-300)
    colmax = np.maximum(np.max(np.abs(GV), axis=0), 1e-300)
    # maximise t subject to gamma + GV z >= t, |GV z| <= reach per column scale
    cost = np.r_[np.zeros(k), -1.0]
    A = np.c_[-GV, np.ones(len(gamma))]
    bounds = [(-reach / c, reach / c) for c in colmax] + [(None, None)]
    out = linprog(cost, A_ub=A, b_ub=gamma, bounds=bounds, method="highs")
    if out.status != 0 or out.x[-1] < float(np.min(gamma, initial=0.0)):
        return np.zeros(k)
    return out.x[:k]


def _balanced(P: _Problem, mu) -> bool:
    """Whether the pieces' equilibrium G^T mu + e = 0 holds to round-off."""
    terms = np.abs(P.G).T @ np.abs(mu) + (np.abs(P.e) if P.e_scale is None else P.e_scale)
    return bool(np.all(np.abs(P.G.T @ mu + P.e) <= RESIDUAL_RTOL * np.maximum(terms, 1e-300)))


def _loose_first(P: _Problem, max_iter, active, start) -> FrictionResult | None:
    """The answer where the pieces that no load drives are loose: their
    faces' rows carry nothing, the rest is solved without them, and each is
    put in the middle of its opening; None where one would then penetrate a
    face (it touches: the whole problem is solved), or where there are no
    such pieces. (Left in the whole problem, a loose piece's place is free,
    and the semi-smooth Newton iteration wanders with it: the stimulation
    network's pressurised block, 22 state sets without settling.)"""
    G, e = P.G, P.e
    if P.e_scale is None:
        return None
    r = G.shape[1]
    touches = G != 0
    # the pieces: modes that share rows (a pair between two pieces couples them)
    group = np.arange(r)
    for i in range(r):
        for j in range(i + 1, r):
            if np.any(touches[:, i] & touches[:, j]):
                group[group == group[j]] = group[i]
    loose_cols = np.zeros(r, bool)
    for g in np.unique(group):
        cols = group == g
        if np.all(np.abs(e[cols]) <= UNLOADED_RTOL * np.maximum(P.e_scale[cols], 1e-300)):
            loose_cols |= cols
    if not loose_cols.any():
        return None
    law = P.law
    partner = np.asarray(law.partner, np.int64)
    gone = np.any(touches[:, loose_cols], axis=1)
    c = np.flatnonzero(law.coulomb)
    both = gone[c] | gone[partner[c]]
    gone[c[both]] = gone[partner[c[both]]] = True
    keep = np.flatnonzero(~gone)
    index = np.full(len(gone), -1, np.int64)
    index[keep] = np.arange(len(keep))
    sub_law = FrictionRows(law.coulomb[keep], np.where(partner[keep] >= 0, index[np.maximum(partner[keep], 0)], -1),
                           law.friction[keep], law.cohesion_force[keep])
    rest = np.flatnonzero(~loose_cols)
    rigid = Rigid(G[np.ix_(keep, rest)], e[rest], P.e_scale[rest]) if len(rest) else None
    sub_start = None
    if getattr(start, "state", None) is not None and len(start.mu) == len(gone):
        sub_start = FrictionResult(start.mu[keep], start.jump[keep], start.active[keep], 0, [], start.jump0[keep],
                                   state=start.state[keep], reference=start.reference[keep], law=sub_law,
                                   cohesive=None if start.cohesive is None else start.cohesive[keep])
    sub = solve_friction(P.S[np.ix_(keep, keep)], P.jump0[keep], P.target[keep], P.normal[keep], sub_law, max_iter,
                         None if active is None else np.asarray(active, bool)[keep], sub_start, rigid)
    m = len(gone)
    mu = np.zeros(m)
    mu[keep] = sub.mu
    alpha = np.zeros(r)
    if len(rest):
        alpha[rest] = getattr(sub, "alpha", np.zeros(len(rest)))
    jump = P.jump0 + P.S @ mu + G @ alpha
    rows = gone & P.normal
    GV = G[np.ix_(rows, loose_cols)]
    gamma = (jump - P.target)[rows]
    z = _middle(GV, gamma - float(np.min(gamma, initial=0.0)))   # the best place, from where they stand
    after = gamma + GV @ z
    if np.min(after, initial=0.0) < 0.0:
        return None   # it would penetrate: it touches somewhere
    alpha[loose_cols] += z
    jump = P.jump0 + P.S @ mu + G @ alpha
    A = np.zeros(m, bool)
    A[keep] = sub.active
    T = np.full(m, OPEN, np.int8)
    C = np.zeros(m, bool)
    if getattr(sub, "state", None) is not None:
        T[keep] = sub.state
        C[keep] = sub.cohesive
    res = _result(P, mu, alpha, jump, A & P.normal, T, C, list(sub.history), fallback=bool(sub.fallback),
                  iterations=int(sub.iterations), broken=int(getattr(sub, "broken", 0)))
    res.loose = int(loose_cols.sum()) + int(getattr(sub, "loose", 0))
    return res


def _complement(vt, r) -> np.ndarray:
    """Rows completing the orthonormal rows vt to a basis of R^r."""
    q, _ = np.linalg.qr(np.vstack([vt, np.eye(r)]).T)
    return q[:, len(vt):r].T


def _parameters(P: _Problem):
    """(c_n, c_t): turn a jump (m) into a force (N/m): the inverse mean compliance of the rows."""
    if P.S is None:
        return P.c0, P.c0
    diag = np.abs(np.diag(P.S))
    coulomb = np.asarray(P.law.coulomb, bool)
    cn = 1.0 / np.mean(diag[P.normal]) if P.normal.any() else 1.0 / np.mean(diag)
    ct = 1.0 / np.mean(diag[coulomb]) if coulomb.any() else cn
    return cn, ct


def _start_states(start: FrictionResult, P: _Problem) -> tuple:
    """(A, T, sign) of the iteration from a result: its closed normal rows,
    its pairs' states, a slip against its tangential force (a pair at the
    bound without force, F = 0, starts sticking)."""
    A = P.normal & np.asarray(start.active, bool)
    ci = P.ci
    T = np.full(len(A), OPEN, np.int8)
    sign = np.zeros(len(A))
    s = np.sign(-start.mu[ci])
    closed = start.state[ci] != OPEN
    slip = (start.state[ci] == SLIP) & (s != 0)
    T[ci] = np.where(closed, np.where(slip, SLIP, STICK), OPEN)
    sign[ci] = np.where(T[ci] == SLIP, s, 0.0)
    return A, T, sign


def _active_set(P: _Problem, cn, ct, max_iter, history, active=None, states=None, cohesive=None, frozen=None,
                C_start=None):
    """The three-state iteration with complementarity parameters cn, ct,
    from `states` (A, T, sign) or else from the contact set `active`; None
    when the state sets cycle (or do not settle in max_iter). cohesive:
    (m,) the Coulomb rows that hold their cohesion, fixed (the fallback's
    law); None: decided by each iterate's opening (see the module). frozen:
    (m,) rows whose states (and C_start's touching flags) stay those of the
    start (_cycling_rows: solved on their own)."""
    S, jump0, target, normal, law = P.S, P.jump0, P.target, P.normal, P.law
    m = len(jump0)
    coulomb = np.asarray(law.coulomb, bool)
    f = np.asarray(law.friction, float)
    b0 = np.asarray(law.cohesion_force, float)
    ci, pi = P.ci, P.pi
    fixed = cohesive is not None
    if states is not None:
        A, T, sign = (np.array(x) for x in states)
    else:
        # with floating pieces jump0 carries their gauge's arbitrary rigid offset: start them closed
        start = (jump0 < target) if P.G.shape[1] == 0 else np.ones(m, bool)
        A = normal & (start if active is None else np.asarray(active, bool))
        T = np.full(m, OPEN, np.int8)
        sign = np.zeros(m)
    C = np.zeros(m, bool)
    # whether a pair touches matters only where it holds a cohesion: elsewhere (b0 = 0) C changes nothing,
    # and a face open by about 1.5 tol flipped it between sets that are otherwise the same, so that they
    # never repeated (a network of 1,000 cohesionless fractures cycled under every scaling on it)
    cohesion = b0[ci] > 0
    C[ci] = cohesive[ci] if fixed else (A[pi] | ((jump0 - target)[pi] <= 1.5 * P.touch)) & cohesion
    if states is None:
        T[ci] = np.where(A[pi] | (C[ci] & (b0[ci] > 0)), STICK, OPEN)
    if C_start is not None:
        C = np.where(frozen, C_start, C) if frozen is not None else np.array(C_start, bool)
    seen = {_key(A, T, sign, C): 0}
    visited = [_states(A, T, sign, C)]
    load = max(np.max(np.abs(target - jump0), initial=0.0), 1e-300)
    alpha_last = None
    for it in range(1, max_iter + 1):
        if P.solve is not None:
            mu, jump = P.solve(A, T, sign, C)
            alpha = np.zeros(0)
        else:
            sol = _solve_set(P, A, T, sign, C, alpha_last)
            if sol is None:
                return None
            mu, alpha = sol
            alpha_last = alpha
            jump = jump0 + S @ mu + P.G @ alpha
        if not np.all(np.isfinite(jump)):
            raise ComputationError("contact: NaN in the friction iteration")
        history.append(int(A.sum()))
        gamma = jump - target                     # on normal rows: w + g
        A_new = normal & (mu - cn * gamma > 0)
        C_new = C.copy()
        if not fixed:
            C_new[ci] = (A_new[pi] | (gamma[pi] <= 1.5 * P.touch)) & cohesion
        T_new = np.full(m, OPEN, np.int8)
        sign_new = np.zeros(m)
        F = np.where(C_new[ci], b0[ci], 0.0) + f[ci] * np.maximum(mu[pi] - cn * gamma[pi], 0.0)
        z = -mu[ci] + ct * (jump[ci] - target[ci])
        band = STATE_BAND * max(np.max(np.abs(mu), initial=0.0), 1e-300)
        slipping = np.abs(z) > F + band
        direction = np.sign(z)
        # a slipping pair sticks again only when its increment turns against its direction by more than the
        # band, as a sticking one slips only above the bound by more than it (see STATE_BAND); and it sticks
        # then, whatever its trial force: a slip that reverses goes through stick. Straight to the opposite
        # slip, a fracture's pairs alternated between the two directions, each with the increment against
        # it (a network of 1,000 fractures cycled so under every scaling; 74 of 720 random pair systems)
        was = T[ci] == SLIP
        keep = was & (sign[ci] * ct * (jump[ci] - target[ci]) >= -band)
        slipping = np.where(was, keep, slipping)
        direction = np.where(keep, sign[ci], direction)
        closed = A_new[pi] | (C_new[ci] & (b0[ci] > 0))
        T_new[ci] = np.where(closed, np.where(slipping, SLIP, STICK), OPEN)
        sign_new[ci] = np.where(T_new[ci] == SLIP, direction, 0.0)
        if frozen is not None:
            A_new, T_new = np.where(frozen, A, A_new), np.where(frozen, T, T_new)
            sign_new, C_new = np.where(frozen, sign, sign_new), np.where(frozen, C, C_new)
        if np.array_equal(A_new, A) and np.array_equal(T_new, T) and np.array_equal(sign_new, sign) and \
                np.array_equal(C_new, C):
            eq = A | P.prescribed | (coulomb & (T == STICK))
            res = np.max(np.abs((jump - target)[eq]), initial=0.0)
            if P.G.shape[1] and not _balanced(P, mu):
                return None   # a least-squares set (a piece its closed pairs leave free) that no force balances
            if res <= RESIDUAL_RTOL * max(load, np.max(np.abs(jump), initial=0.0)):
                P.last_states, P.last_C = (A, T, sign), C
                return _result(P, mu, alpha, jump, A, T, C, history, fallback=fixed)
            return None
        key = _key(A_new, T_new, sign_new, C_new)
        P.last_states = (A_new, T_new, sign_new)
        if key in seen:   # cycling: the rows whose states the cycle's sets change
            cycle = visited[seen[key]:]
            P.cycle_rows = np.any(np.stack([c != cycle[0] for c in cycle[1:]] or [np.zeros_like(cycle[0])]),
                                  axis=(0, 2))
            return None
        seen[key] = len(visited)
        visited.append(_states(A_new, T_new, sign_new, C_new))
        A, T, sign, C = A_new, T_new, sign_new, C_new
    return None


def _result(P: _Problem, mu, alpha, jump, A, T, C, history, fallback, iterations=None, broken=0) -> FrictionResult:
    """The FrictionResult of a solution; a pair that touches and holds its
    cohesion without a normal force counts as closed."""
    ci, pi = P.ci, P.pi
    active = np.array(A, bool)
    active[pi[T[ci] != OPEN]] = True
    res = FrictionResult(mu, jump, active & P.normal, len(history) if iterations is None else iterations, history,
                         P.jump0, fallback=fallback, state=T, reference=P.target.copy(), law=P.law,
                         cohesive=np.array(C, bool), touch=P.touch, broken=int(broken), alpha=np.asarray(alpha, float))
    res.state = _labels(res)
    return res


def _labels(res: FrictionResult) -> np.ndarray:
    """The states as the law names them, by the traction: a closed pair at
    the bound slips, below it sticks. The iteration's own labels differ
    where both hold, at the bound with a zero increment (frictionless faces,
    or the last solve of a critical-load search, a hair above the load its
    reference was accepted at): there the pair is sliding, not held."""
    out = res.state.copy()
    ci = np.flatnonzero(res.law.coulomb)
    closed = out[ci] != OPEN
    F = res.bound()[ci]
    at = np.abs(res.mu[ci]) >= F * (1 - BOUND_RTOL)
    out[ci] = np.where(closed, np.where(at, SLIP, STICK), OPEN)
    return out


def _states(A, T, sign, C) -> np.ndarray:
    """(m, 4) a set's states, row by row."""
    return np.stack([A.astype(np.int8), T.astype(np.int8), np.sign(sign).astype(np.int8), C.astype(np.int8)], axis=1)


def _key(A, T, sign, C) -> bytes:
    return A.tobytes() + T.tobytes() + np.sign(sign).astype(np.int8).tobytes() + C.tobytes()


def _solve_set(P: _Problem, A, T, sign, C, alpha_last=None):
    """(mu, alpha) of one state set: jump = target on contact normal,
    prescribed and sticking rows; mu_t = -sign (b0 [cohesive] + f mu_n) on
    slipping rows; mu = 0 on open ones; the pieces' equilibrium G^T mu + e
    = 0. The slipping rows' forces follow from their normal rows', so they
    are eliminated: one dense solve on the equality rows (and the pieces'
    amplitudes) only. Where that system is singular with floating pieces
    (this set's closed pairs leave a piece free), the amplitudes nearest the
    last iterate's."""
    S, normal, law = P.S, P.normal, P.law
    partner, f, b0 = law.partner, law.friction, law.cohesion_force
    m = len(P.jump0)
    r = P.G.shape[1]
    mu = np.zeros(m)
    eq = np.flatnonzero((normal & A) | P.prescribed | (T == STICK))
    sl = np.flatnonzero(T == SLIP)
    if len(eq) + len(sl) == 0 and r == 0:
        return mu, np.zeros(0)
    n = len(eq)
    # mu_sl = c_sl + D mu_eq: D has -sign f at the column of the slipping row's normal row (if it is an
    # equality row; else the pair touches without a normal force, mu_n = 0)
    col = np.full(m, -1, np.int64)
    col[eq] = np.arange(n)
    c_sl = -sign[sl] * np.where(C[sl], b0[sl], 0.0)
    pcol = col[partner[sl]] if len(sl) else np.zeros(0, np.int64)
    coef = np.where(pcol >= 0, -sign[sl] * f[sl], 0.0)
    M = np.zeros((n + r, n + r))
    rhs = np.zeros(n + r)
    M[:n, :n] = S[np.ix_(eq, eq)]
    if len(sl):
        S_es = S[np.ix_(eq, sl)]
        with_p = pcol >= 0
        np.add.at(M[:n, :n].T, pcol[with_p], (S_es[:, with_p] * coef[with_p]).T)
        rhs[:n] = P.target[eq] - P.jump0[eq] - S_es @ c_sl
    else:
        rhs[:n] = P.target[eq] - P.jump0[eq]
    if r:
        M[:n, n:] = P.G[eq]
        M[n:, :n] = P.G[eq].T
        if len(sl):
            Gs = P.G[sl]
            with_p = pcol >= 0
            np.add.at(M[n:, :n].T, pcol[with_p], Gs[with_p] * coef[with_p, None])
            rhs[n:] = -P.e - Gs.T @ c_sl
        else:
            rhs[n:] = -P.e
    sol = np.zeros(0)
    if n + r:
        try:
            sol = np.linalg.solve(M, rhs)
        except np.linalg.LinAlgError:
            if not r:
                raise ComputationError(_SINGULAR) from None
            # this set's closed pairs leave a piece's motion free: the amplitudes nearest the last
            # iterate's, and the iteration goes on (a set it settles on must fix them or the motion be
            # unloaded: _held)
            last = np.r_[np.zeros(n), np.zeros(r) if alpha_last is None else alpha_last]
            sol = last + np.linalg.lstsq(M, rhs - M @ last, rcond=None)[0]
    if r and not np.all(np.isfinite(sol)):
        return None
    mu[eq] = sol[:n]
    if len(sl):
        mu[sl] = c_sl + coef * (sol[np.maximum(pcol, 0)] if n else 0.0)
    return mu, sol[n:]


def _fallback(P: _Problem, history, max_iter) -> FrictionResult:
    """The law with the cohesive pairs fixed, all at first; those whose
    opening then exceeds 2 tol lose their cohesion and it is solved again
    (each pair at most once, so it ends). Each law is continuous: the
    three-state iteration, or where that cycles the fixed point."""
    m = len(P.jump0)
    ci, pi = P.ci, P.pi
    C = np.zeros(m, bool)
    C[ci] = True
    cn, ct = _parameters(P)
    while True:
        res = None
        for k in SCALINGS[:1]:
            res = _active_set(P, cn * k, ct * k, max_iter, history, cohesive=C)
        if res is None:
            res = _fixed_point(P, history, C)
        opening = (res.jump - P.target)[pi]
        drop = C[ci] & (opening > 2 * P.touch) & (np.asarray(P.law.cohesion_force)[ci] > 0)
        if not drop.any():
            res.broken = int(np.sum(~C[ci] & (opening < P.touch) & (np.asarray(P.law.cohesion_force)[ci] > 0)))
            res.fallback = True
            return res
        C[ci[drop]] = False


def fixed_point_solve(S, jump0, target, normal, prescribed, law, history, rigid: Rigid | None = None):
    """The fallback on its own (see the module): cohesion as the fallback
    decides it, each law solved as a fixed point on the bound (a second
    method beside the three-state iteration)."""
    P = _Problem.of(S, jump0, target, normal, prescribed, law, rigid)
    m = len(P.jump0)
    ci, pi = P.ci, P.pi
    C = np.zeros(m, bool)
    C[ci] = True
    b0 = np.asarray(law.cohesion_force, float)[ci]
    while True:
        res = _fixed_point(P, history, C)
        opening = (res.jump - P.target)[pi]
        drop = C[ci] & (opening > 2 * P.touch) & (b0 > 0)
        if not drop.any():
            res.broken = int(np.sum(~C[ci] & (opening < P.touch) & (b0 > 0)))
            return res
        C[ci[drop]] = False


def _fixed_point(P: _Problem, history, C) -> FrictionResult:
    """Coulomb friction as a fixed point on the friction bound F = c w_p
    [cohesive] + mu_f mu_n: each iterate is Tresca friction with the bound
    of the last forces, the convex problem min 1/2 mu^T S mu - mu^T (target
    - jump0) with mu_n >= 0, -F <= mu_t <= F and the pieces' equilibrium (its
    KKT conditions: contact, stick inside the box, slip against the
    increment on its faces), by contact.box_qp; the update of the bound is
    relaxed (damped) where successive iterates oscillate."""
    S, jump0, target, normal, law = P.S, P.jump0, P.target, P.normal, P.law
    m = len(jump0)
    ci, pi = P.ci, P.pi
    f = np.asarray(law.friction, float)[ci]
    b0 = np.where(C[ci], np.asarray(law.cohesion_force, float)[ci], 0.0)
    lo = np.where(normal, 0.0, -np.inf)
    hi = np.full(m, np.inf)
    F = b0.copy()
    mu, alpha = np.zeros(m), np.zeros(P.G.shape[1])
    theta, last = 1.0, np.inf
    steps = 0
    for _ in range(FIXED_POINT_ITERATIONS):
        lo[ci], hi[ci] = -F, F
        try:
            qp = solve_box_qp(S, target - jump0, lo, hi, P.G if P.G.shape[1] else None, P.e, x0=mu, alpha0=alpha)
        except Infeasible as err:
            raise Mechanism(err.residual) from None
        mu, alpha = qp.x, qp.alpha
        steps += qp.steps
        jump = jump0 + S @ mu + P.G @ alpha
        if not np.all(np.isfinite(jump)):
            raise ComputationError("contact: NaN in the friction solve")
        history.append(int(np.sum(normal & (mu > 0))))
        F_new = b0 + f * np.maximum(mu[pi], 0.0)
        change = float(np.max(np.abs(F_new - F), initial=0.0))
        fscale = max(float(np.max(np.abs(mu), initial=0.0)), 1e-300)
        if change <= FIXED_POINT_RTOL * fscale:
            break
        if change >= last:   # oscillating: relax the update
            theta = max(theta / 2, 1.0 / 64)
        last = change
        F = F + theta * (F_new - F)
    else:
        raise ComputationError(f"contact: friction: the fixed point on the friction bound did not converge in "
                               f"{FIXED_POINT_ITERATIONS} iterations")
    A = normal & (mu > 0.0)
    T = np.full(m, OPEN, np.int8)
    T[ci] = np.where(A[pi] | (C[ci] & (b0 > 0)), STICK, OPEN)
    return _result(P, mu, alpha, jump, A, T, C, history, fallback=True, iterations=len(history) + steps)
