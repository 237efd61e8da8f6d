"""The contact problem solved set by set, where no dense pair compliance is
at hand (fem.pair_saddle solves each state set with the elasticity whole):
the three-state iteration of contact.friction, its scalings and its start,
and where every scaling cycles, the cycling rows solved as a dense pair
problem of their own (_cycling_rows) with the others held."""
from __future__ import annotations

import numpy as np

from ..errors import ComputationError
from .friction import solve_friction
from .friction_problem import MAX_ITERATIONS, OPEN, SCALINGS, SLIP, FrictionResult, FrictionRows, PairProblem
from .friction_sets import iterate_states, start_states, states_of


def solve_by_sets(solve, jump0, target, normal, law: FrictionRows, c0: float, max_iter: int = MAX_ITERATIONS,
                  active=None, start: FrictionResult | None = None, respond=None) -> FrictionResult:
    """The contact problem where each state set is solved by `solve(A, T,
    sign, C) -> (forces, jump)` (fem.pair_saddle: the elasticity whole, no
    dense compliance), with the complementarity parameters c0: the same
    three-state iteration, its scalings and its start. Where every scaling
    cycles, the cycle's rows are solved as a dense problem of their own
    (_cycling_rows: `respond(A, T, sign, C, rows) -> (jump0, S)` of those
    rows with the others held in their states), at most SUBPROBLEM_ROUNDS
    times; then ComputationError."""
    normal = np.asarray(normal, bool)
    coulomb = np.asarray(law.coulomb, bool)
    P = PairProblem.of(None, jump0, target, normal, ~normal & ~coulomb, law, None)
    P.solve, P.c0 = solve, float(c0)
    history = []
    if getattr(start, "state", None) is not None and len(start.forces) == len(P.jump0):
        res = iterate_states(P, P.c0, P.c0, max_iter, history, states=start_states(start, P))
        if res is not None:
            return res
    states = None
    for k in SCALINGS:
        # each scaling goes on from the sets where the last one cycled, not from the start: a set is a
        # factorisation of the whole saddle system here, and the first ones change thousands of rows; the
        # first starts from the trial states of jump0, not from every closed pair sticking (the set after
        # that changed a third of a network's rows to slip: one factorisation more)
        res = iterate_states(P, P.c0 * k, P.c0 * k, max_iter, history, active, states=states, trial=states is None)
        if res is not None:
            return res
        states = P.last_states
    for _ in range(SUBPROBLEM_ROUNDS if respond is not None else 0):
        res = _cycling_rows(P, respond, max_iter, history)
        if res is not None:
            res.fallback = True
            return res
    raise ComputationError(f"contact: the active set cycles on a pair system of {len(P.jump0)} rows (on "
                           f"{int(np.sum(P.cycle_rows)) if P.cycle_rows is not None else 0} of them), and so "
                           "does the dense solve of those rows")


#: the cycling rows' dense problems solve_by_sets tries before it gives up (each a full set more)
SUBPROBLEM_ROUNDS = 4


def _cycling_rows(P: PairProblem, respond, max_iter, history) -> FrictionResult | None:
    """The rows the last cycle changed, with their pairs' other rows (Y),
    solved as a contact problem of their own by the dense solver and its
    fallbacks (solve_friction), their compliance and free jumps with every
    other row held in its state (respond); then the three-state iteration on
    the others with Y's states frozen; then Y again on the others' new
    states, until Y's states repeat (at most SUBPROBLEM_ROUNDS). None where
    the others cycle, or Y's states do not repeat."""
    A, T, sign = P.last_states
    m = len(P.jump0)
    ci, pi = P.ci, P.pi
    y = np.array(P.cycle_rows, bool)
    y[pi[y[ci]]] = True                     # a Coulomb row's normal row
    y[ci[y[pi]]] = True                     # a normal row's Coulomb row
    rows = np.flatnonzero(y)
    law = P.law
    b0 = np.asarray(law.cohesion_force, float)
    where = np.full(m, -1, np.int64)
    where[rows] = np.arange(len(rows))
    partner = np.asarray(law.partner)[rows]
    sub_law = FrictionRows(np.asarray(law.coulomb, bool)[rows], np.where(partner >= 0, where[np.maximum(partner, 0)], -1),
                           np.asarray(law.friction, float)[rows], b0[rows])
    C = np.zeros(m, bool)
    C[ci] = (A[pi] | (T[ci] != OPEN)) & (b0[ci] > 0)
    res, before = None, None
    for _ in range(SUBPROBLEM_ROUNDS):
        j0, S = respond(A, T, sign, C, y)
        sub = solve_friction(S, j0, P.target[rows], P.normal[rows], sub_law)
        A, T, sign, C = A.copy(), T.copy(), sign.copy(), C.copy()
        A[rows] = P.normal[rows] & sub.active
        state = getattr(sub, "state", None)   # None: no Coulomb row among them (the frictionless result)
        if state is not None:
            T[rows] = np.where(sub_law.coulomb, state, OPEN)
            sign[rows] = np.where(T[rows] == SLIP, np.sign(-sub.forces), 0.0)
            C[rows] = np.where(sub_law.coulomb, sub.cohesive, False)
        now = states_of(A, T, sign, C)[rows]
        if res is not None and np.array_equal(now, before):
            return res                        # Y's answer on the others' states is the one they were solved with
        res = iterate_states(P, P.c0, P.c0, max_iter, history, states=(A, T, sign), frozen=y, C_start=C)
        if res is None:
            return None
        before = now
        (A, T, sign), C = P.last_states, P.last_C
    return None
