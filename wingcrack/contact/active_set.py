"""Primal-dual active-set method (Hintermueller, Ito & Kunisch 2002; Hueber &
Wohlmuth 2005) on the small pair system.

With the elasticity factorised, the jumps depend on the multipliers through
the dense pair compliance S = B^T K^-1 B:

    jump(forces) = jump0 + S forces

Normal rows: gap function gamma = jump + g >= 0, forces >= 0, forces gamma = 0,
rewritten as forces = max(0, forces - c gamma). Tangential rows (prescribed slip):
jump = s, always. The active set A = {forces - c gamma > 0} is updated until it
repeats (converged); a set seen before that is not the last one is cycling.
The method is not globally convergent for every SPD S (random 7x7 compliances
cycle about once in a hundred); on cycling, or without convergence, the same
problem is solved as the convex quadratic program it is (min 1/2 forces^T S forces -
forces^T (target - jump0) with forces >= 0 on normal rows) by contact.box_qp, which
terminates.
"""
from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from ..errors import ComputationError
from .box_qp import solve_box_qp


@dataclass
class ActiveSetResult:
    forces: np.ndarray      # (m,) the row forces: the contact multipliers (nodal forces, N/m)
    jump: np.ndarray        # (m,) jumps (u+ - u-).v at the solution (m)
    active: np.ndarray      # (m,) bool: normal rows in contact
    iterations: int
    history: list           # number of active normal rows per iteration

    jump0: np.ndarray = None  # (m,) jumps without pair forces
    fallback: bool = False    # solved by bounded least squares after the active set cycled

    @property
    def mu(self) -> np.ndarray:
        """The former name of `forces` (deprecated)."""
        warnings.warn("the contact result's .mu is deprecated: read .forces (the row forces, the contact "
                      "multipliers)", DeprecationWarning, stacklevel=2)
        return self.forces

    def kkt_residuals(self, gap, normal) -> dict:
        """Largest KKT violations on the normal rows, relative to the load
        scale: the largest |force| for forces, the largest jump without
        contact (or with it) for gaps."""
        normal = np.asarray(normal, bool)
        g = self.jump[normal] + gap[normal]
        forces = self.forces[normal]
        mscale = max(np.max(np.abs(self.forces), initial=0.0), 1e-300)
        jscale = max(np.max(np.abs(self.jump0), initial=0.0), np.max(np.abs(self.jump), initial=0.0),
                     np.max(np.abs(gap), initial=0.0), 1e-300)
        return {
            "feasibility": float(max(0.0, -np.min(g, initial=0.0)) / jscale),
            "sign": float(max(0.0, -np.min(forces, initial=0.0)) / mscale),
            "complementarity": float(np.max(np.abs(forces * g), initial=0.0) / (mscale * jscale)),
        }


def solve_active_set(S, jump0, target, normal, c=None, active=None, max_iter=100) -> ActiveSetResult:
    """S (m, m) compliance; jump0 (m,) jumps without multipliers; target (m,)
    = -g on normal rows, the prescribed slip on tangential rows; normal (m,)
    bool. `active`: initial contact set (default: the rows penetrating
    without contact, i.e. jump0 < target)."""
    S = np.asarray(S, float)
    jump0 = np.asarray(jump0, float)
    target = np.asarray(target, float)
    normal = np.asarray(normal, bool)
    m = len(jump0)
    if m == 0:
        return ActiveSetResult(np.zeros(0), jump0.copy(), np.zeros(0, bool), 0, [], jump0.copy())
    if c is None:
        # c turns a gap (m) into a force (N/m): the inverse mean compliance
        c = 1.0 / np.mean(np.abs(np.diag(S)))
    gap = -np.where(normal, target, 0.0)
    A = (jump0 < target) & normal if active is None else (np.asarray(active, bool) & normal)
    seen = {A.tobytes()}
    history = []
    for it in range(1, max_iter + 1):
        rows = A | ~normal
        forces = np.zeros(m)
        if rows.any():
            idx = np.flatnonzero(rows)
            try:
                forces[idx] = np.linalg.solve(S[np.ix_(idx, idx)], target[idx] - jump0[idx])
            except np.linalg.LinAlgError:
                raise ComputationError("contact: the pair system is singular (a pair is held by a "
                                       "displacement condition on both faces?)") from None
        jump = jump0 + S @ forces
        if not np.all(np.isfinite(jump)):
            raise ComputationError("contact: NaN in the active-set iteration")
        gamma = jump + gap
        A_new = normal & (forces - c * gamma > 0)
        history.append(int(A.sum()))
        if np.array_equal(A_new, A):
            return ActiveSetResult(forces, jump, A, it, history, jump0)
        key = A_new.tobytes()
        if key in seen:
            break  # cycling
        seen.add(key)
        A = A_new
    return _bounded_least_squares(S, jump0, target, normal, history)


def _bounded_least_squares(S, jump0, target, normal, history) -> ActiveSetResult:
    """The contact problem as min 1/2 forces^T S forces - forces^T (target - jump0), forces >= 0
    on normal rows, free on tangential rows (its KKT conditions are the
    contact conditions), by contact.box_qp."""
    lower = np.where(normal, 0.0, -np.inf)
    try:
        qp = solve_box_qp(S, target - jump0, lower, np.full(len(jump0), np.inf))
    except np.linalg.LinAlgError:
        raise ComputationError("contact: the pair system is singular (a pair is held by a "
                               "displacement condition on both faces?)") from None
    forces = np.where(normal, np.maximum(qp.x, 0.0), qp.x)
    jump = jump0 + S @ forces
    if not np.all(np.isfinite(jump)):
        raise ComputationError("contact: NaN in the contact solve")
    active = normal & (forces > 0.0)
    history.append(int(active.sum()))
    return ActiveSetResult(forces, jump, active, len(history) + int(qp.steps), history, jump0, fallback=True)
