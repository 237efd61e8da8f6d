"""The fallback of the friction solve where the three-state iteration cycles:
the pairs that hold cohesion fixed (all at first), each law solved by the
iteration or as a fixed point on the friction bound (each iterate a Tresca
problem, contact.box_qp), pairs that open beyond twice the touching
tolerance losing their cohesion (at most once a pair: it ends)."""
from __future__ import annotations

import numpy as np

from ..errors import ComputationError
from .box_qp import Infeasible, solve_box_qp
from .friction_problem import (OPEN, SCALINGS, STICK, FrictionResult, Mechanism, PairProblem, Rigid,
                               complementarity_parameters, result_of)
from .friction_sets import iterate_states

#: largest number of Tresca problems of the fallback's fixed point
FIXED_POINT_ITERATIONS = 200
#: the fixed point has converged when the bound changes by less than this (relative to the largest force)
FIXED_POINT_RTOL = 1e-13


def fallback(P: PairProblem, history, max_iter) -> FrictionResult:
    """The law with the cohesive pairs fixed, all at first; those whose
    opening then exceeds 2 tol lose their cohesion and it is solved again
    (each pair at most once, so it ends). Each law is continuous: the
    three-state iteration, or where that cycles the fixed point."""
    m = len(P.jump0)
    ci, pi = P.ci, P.pi
    C = np.zeros(m, bool)
    C[ci] = True
    cn, ct = complementarity_parameters(P)
    while True:
        res = None
        for k in SCALINGS[:1]:
            res = iterate_states(P, cn * k, ct * k, max_iter, history, cohesive=C)
        if res is None:
            res = fixed_point(P, history, C)
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
    P = PairProblem.of(S, jump0, target, normal, prescribed, law, rigid)
    m = len(P.jump0)
    ci, pi = P.ci, P.pi
    C = np.zeros(m, bool)
    C[ci] = True
    b0 = np.asarray(law.cohesion_force, float)[ci]
    while True:
        res = fixed_point(P, history, C)
        opening = (res.jump - P.target)[pi]
        drop = C[ci] & (opening > 2 * P.touch) & (b0 > 0)
        if not drop.any():
            res.broken = int(np.sum(~C[ci] & (opening < P.touch) & (b0 > 0)))
            return res
        C[ci[drop]] = False


def fixed_point(P: PairProblem, history, C) -> FrictionResult:
    """Coulomb friction as a fixed point on the friction bound F = c w_p
    [cohesive] + friction forces_n: each iterate is Tresca friction with the bound
    of the last forces, the convex problem min 1/2 forces^T S forces - forces^T (target
    - jump0) with forces_n >= 0, -F <= forces_t <= F and the pieces' equilibrium (its
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
    forces, alpha = np.zeros(m), np.zeros(P.G.shape[1])
    theta, last = 1.0, np.inf
    steps = 0
    for _ in range(FIXED_POINT_ITERATIONS):
        lo[ci], hi[ci] = -F, F
        try:
            qp = solve_box_qp(S, target - jump0, lo, hi, P.G if P.G.shape[1] else None, P.e, x0=forces, alpha0=alpha)
        except Infeasible as err:
            raise Mechanism(err.residual) from None
        forces, alpha = qp.x, qp.alpha
        steps += qp.steps
        jump = jump0 + S @ forces + P.G @ alpha
        if not np.all(np.isfinite(jump)):
            raise ComputationError("contact: NaN in the friction solve")
        history.append(int(np.sum(normal & (forces > 0))))
        F_new = b0 + f * np.maximum(forces[pi], 0.0)
        change = float(np.max(np.abs(F_new - F), initial=0.0))
        fscale = max(float(np.max(np.abs(forces), initial=0.0)), 1e-300)
        if change <= FIXED_POINT_RTOL * fscale:
            break
        if change >= last:   # oscillating: relax the update
            theta = max(theta / 2, 1.0 / 64)
        last = change
        F = F + theta * (F_new - F)
    else:
        raise ComputationError(f"contact: friction: the fixed point on the friction bound did not converge in "
                               f"{FIXED_POINT_ITERATIONS} iterations")
    A = normal & (forces > 0.0)
    T = np.full(m, OPEN, np.int8)
    T[ci] = np.where(A[pi] | (C[ci] & (b0 > 0)), STICK, OPEN)
    return result_of(P, forces, alpha, jump, A, T, C, history, fallback=True, iterations=len(history) + steps)
