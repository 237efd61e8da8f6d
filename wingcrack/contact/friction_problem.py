"""The records of the pair problem with Coulomb rows (contact.friction):
the rows' law, the rigid modes of pieces only contact holds, the result with
its states, one problem with its derived data, and the tolerances the
iterations share."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ComputationError
from .active_set import ActiveSetResult

OPEN, STICK, SLIP = 0, 1, 2
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
    elsewhere); friction (m,) the Coulomb coefficient; cohesion_force (m,) c times the pair's
    tributary length (N/m; the bound's cohesion part as a force)."""
    coulomb: np.ndarray
    partner: np.ndarray
    friction: np.ndarray
    cohesion_force: np.ndarray


@dataclass
class Rigid:
    """The rigid modes of the pieces only contact holds: G (m, r) their
    jumps per unit amplitude, e (r,) the other loads' generalised forces on
    them (equilibrium: G^T forces + e = 0); e_scale (r,) the sum of the
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
    loose: int = 0   # rigid motions of pieces no face holds and no load drives (placed: contact.loose_pieces.held)

    def bound(self) -> np.ndarray:
        """(m,) the friction bound F (forces) on Coulomb rows (0 elsewhere)."""
        law = self.law
        F = np.zeros(len(self.forces))
        i = np.flatnonzero(law.coulomb)
        F[i] = np.where(self.cohesive[i], law.cohesion_force[i], 0.0) + \
            law.friction[i] * np.maximum(self.forces[law.partner[i]], 0.0)
        return F

    def slip_increment(self) -> np.ndarray:
        """(m,) ds = s - s_ref on Coulomb rows (0 elsewhere)."""
        return np.where(self.law.coulomb, self.jump - self.reference, 0.0)

    def friction_residuals(self, weight) -> dict:
        """Largest violations of the friction law, relative: tractions to the
        largest row traction |forces| / weight, increments to the jump scale;
        "touch": the largest opening of a pair that holds cohesion beyond
        2 tol (relative to tol; 0 where the law holds)."""
        law = self.law
        w = np.maximum(np.asarray(weight, float), 1e-300)
        t = np.abs(self.forces) / w
        tscale = max(np.max(t, initial=0.0), 1e-300)
        ds = self.slip_increment()
        jscale = max(np.max(np.abs(self.jump0), initial=0.0), np.max(np.abs(self.jump), initial=0.0), 1e-300)
        c = law.coulomb
        F = self.bound()
        over = (np.abs(self.forces) - F) / w
        slip, stick = c & (self.state == SLIP), c & (self.state == STICK)
        i = np.flatnonzero(c & self.cohesive & (law.cohesion_force > 0))
        opening = (self.jump - self.reference)[law.partner[i]]
        return {
            "bound": float(max(0.0, np.max(over[c], initial=0.0)) / tscale),
            "at_bound": float(np.max(np.abs(over[slip]), initial=0.0) / tscale),
            "direction": float(max(0.0, np.max(self.forces[slip] / w[slip] * ds[slip], initial=0.0)) / (tscale * jscale)),
            "stick_increment": float(np.max(np.abs(ds[stick & (F > 0)]), initial=0.0) / jscale),
            "touch": float(max(0.0, np.max(opening, initial=0.0) - 2 * self.touch) / max(self.touch, 1e-300)),
        }


@dataclass
class PairProblem:
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
    #: the solve of one state set, where S is not at hand (fem.pair_saddle): (A, T, sign, C) -> (forces, jump)
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


def complementarity_parameters(P: PairProblem):
    """(c_n, c_t): turn a jump (m) into a force (N/m): the inverse mean compliance of the rows."""
    if P.S is None:
        return P.c0, P.c0
    diag = np.abs(np.diag(P.S))
    coulomb = np.asarray(P.law.coulomb, bool)
    cn = 1.0 / np.mean(diag[P.normal]) if P.normal.any() else 1.0 / np.mean(diag)
    ct = 1.0 / np.mean(diag[coulomb]) if coulomb.any() else cn
    return cn, ct


def result_of(P: PairProblem, forces, alpha, jump, A, T, C, history, fallback, iterations=None, broken=0) -> FrictionResult:
    """The FrictionResult of a solution; a pair that touches and holds its
    cohesion without a normal force counts as closed."""
    ci, pi = P.ci, P.pi
    active = np.array(A, bool)
    active[pi[T[ci] != OPEN]] = True
    res = FrictionResult(forces, jump, active & P.normal, len(history) if iterations is None else iterations, history,
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
    at = np.abs(res.forces[ci]) >= F * (1 - BOUND_RTOL)
    out[ci] = np.where(closed, np.where(at, SLIP, STICK), OPEN)
    return out
