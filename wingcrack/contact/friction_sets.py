"""The three-state iteration of contact.friction (open, stick, slip a pair):
one state set's linear equations solved densely, the next set from the
semi-smooth Newton update, until a set repeats (converged) or cycles."""
from __future__ import annotations

import numpy as np

from ..errors import ComputationError
from .friction_problem import (OPEN, RESIDUAL_RTOL, SLIP, STATE_BAND, STICK, FrictionResult, PairProblem,
                               result_of)

_SINGULAR = ("contact: the pair system is singular (a pair is held by a displacement condition on both "
             "faces?)")


def start_states(start: FrictionResult, P: PairProblem) -> tuple:
    """(A, T, sign) of the iteration from a result: its closed normal rows,
    its pairs' states, a slip against its tangential force (a pair at the
    bound without force, F = 0, starts sticking)."""
    A = P.normal & np.asarray(start.active, bool)
    ci = P.ci
    T = np.full(len(A), OPEN, np.int8)
    sign = np.zeros(len(A))
    s = np.sign(-start.forces[ci])
    closed = start.state[ci] != OPEN
    slip = (start.state[ci] == SLIP) & (s != 0)
    T[ci] = np.where(closed, np.where(slip, SLIP, STICK), OPEN)
    sign[ci] = np.where(T[ci] == SLIP, s, 0.0)
    return A, T, sign


def iterate_states(P: PairProblem, cn, ct, max_iter, history, active=None, states=None, cohesive=None, frozen=None,
                C_start=None, trial=False):
    """The three-state iteration with complementarity parameters cn, ct,
    from `states` (A, T, sign) or else from the contact set `active`; None
    when the state sets cycle (or do not settle in max_iter). cohesive:
    (m,) the Coulomb rows that hold their cohesion, fixed (the fallback's
    law); None: decided by each iterate's opening (see the module). frozen:
    (m,) rows whose states (and C_start's touching flags) stay those of the
    start (_cycling_rows: solved on their own). trial: without `states`,
    the closed pairs start in the states the update gives the iterate of
    no pair forces (forces = 0, the jumps jump0: slipping where the trial force
    c_t ds exceeds the bound c_n f (g - w) of the penetration), instead of
    all sticking: the iterate the start comes from anyway, one set fewer
    where a set costs a factorisation (contact.by_sets)."""
    S, jump0, target, normal, law = P.S, P.jump0, P.target, P.normal, P.law
    m = len(jump0)
    coulomb = np.asarray(law.coulomb, bool)
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
        if trial and P.G.shape[1] == 0:
            _, T_trial, sign, _ = _next_states(P, np.zeros(m), jump0, A, np.full(m, OPEN, np.int8), np.zeros(m), C,
                                               cn, ct, cohesive)
            T = np.where(T == OPEN, OPEN, np.where(T_trial == SLIP, SLIP, STICK)).astype(np.int8)
            sign = np.where(T == SLIP, sign, 0.0)
    if C_start is not None:
        C = np.where(frozen, C_start, C) if frozen is not None else np.array(C_start, bool)
    seen = {_key(A, T, sign, C): 0}
    visited = [states_of(A, T, sign, C)]
    load = max(np.max(np.abs(target - jump0), initial=0.0), 1e-300)
    alpha_last = None
    for it in range(1, max_iter + 1):
        if P.solve is not None:
            forces, jump = P.solve(A, T, sign, C)
            alpha = np.zeros(0)
        else:
            sol = solve_state_set(P, A, T, sign, C, alpha_last)
            if sol is None:
                return None
            forces, alpha = sol
            alpha_last = alpha
            jump = jump0 + S @ forces + P.G @ alpha
        if not np.all(np.isfinite(jump)):
            raise ComputationError("contact: NaN in the friction iteration")
        history.append(int(A.sum()))
        A_new, T_new, sign_new, C_new = _next_states(P, forces, jump, A, T, sign, C, cn, ct, cohesive)
        if frozen is not None:
            A_new, T_new = np.where(frozen, A, A_new), np.where(frozen, T, T_new)
            sign_new, C_new = np.where(frozen, sign, sign_new), np.where(frozen, C, C_new)
        if np.array_equal(A_new, A) and np.array_equal(T_new, T) and np.array_equal(sign_new, sign) and \
                np.array_equal(C_new, C):
            eq = A | P.prescribed | (coulomb & (T == STICK))
            res = np.max(np.abs((jump - target)[eq]), initial=0.0)
            if P.G.shape[1] and not _balanced(P, forces):
                return None   # a least-squares set (a piece its closed pairs leave free) that no force balances
            if res <= RESIDUAL_RTOL * max(load, np.max(np.abs(jump), initial=0.0)):
                P.last_states, P.last_C = (A, T, sign), C
                return result_of(P, forces, alpha, jump, A, T, C, history, fallback=fixed)
            return None
        key = _key(A_new, T_new, sign_new, C_new)
        P.last_states = (A_new, T_new, sign_new)
        if key in seen:   # cycling: the rows whose states the cycle's sets change
            cycle = visited[seen[key]:]
            P.cycle_rows = np.any(np.stack([c != cycle[0] for c in cycle[1:]] or [np.zeros_like(cycle[0])]),
                                  axis=(0, 2))
            return None
        seen[key] = len(visited)
        visited.append(states_of(A_new, T_new, sign_new, C_new))
        A, T, sign, C = A_new, T_new, sign_new, C_new
    return None


def _next_states(P: PairProblem, forces, jump, A, T, sign, C, cn, ct, cohesive):
    """(A, T, sign, C) of the next set from an iterate (forces, jump) of the set
    (A, T, sign, C): the semi-smooth Newton update (see the module), the
    touching flags fixed where `cohesive` is given."""
    m = len(forces)
    ci, pi = P.ci, P.pi
    f = np.asarray(P.law.friction, float)
    b0 = np.asarray(P.law.cohesion_force, float)
    cohesion = b0[ci] > 0
    target = P.target
    gamma = jump - target                     # on normal rows: w + g
    A_new = P.normal & (forces - cn * gamma > 0)
    C_new = C.copy()
    if cohesive is None:
        C_new[ci] = (A_new[pi] | (gamma[pi] <= 1.5 * P.touch)) & cohesion
    T_new = np.full(m, OPEN, np.int8)
    sign_new = np.zeros(m)
    F = np.where(C_new[ci], b0[ci], 0.0) + f[ci] * np.maximum(forces[pi] - cn * gamma[pi], 0.0)
    z = -forces[ci] + ct * (jump[ci] - target[ci])
    band = STATE_BAND * max(np.max(np.abs(forces), initial=0.0), 1e-300)
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
    return A_new, T_new, sign_new, C_new


def _balanced(P: PairProblem, forces) -> bool:
    """Whether the pieces' equilibrium G^T forces + e = 0 holds to round-off."""
    terms = np.abs(P.G).T @ np.abs(forces) + (np.abs(P.e) if P.e_scale is None else P.e_scale)
    return bool(np.all(np.abs(P.G.T @ forces + P.e) <= RESIDUAL_RTOL * np.maximum(terms, 1e-300)))


def states_of(A, T, sign, C) -> np.ndarray:
    """(m, 4) a set's states, row by row."""
    return np.stack([A.astype(np.int8), T.astype(np.int8), np.sign(sign).astype(np.int8), C.astype(np.int8)], axis=1)


def _key(A, T, sign, C) -> bytes:
    return A.tobytes() + T.tobytes() + np.sign(sign).astype(np.int8).tobytes() + C.tobytes()


def solve_state_set(P: PairProblem, A, T, sign, C, alpha_last=None):
    """(forces, alpha) of one state set: jump = target on contact normal,
    prescribed and sticking rows; forces_t = -sign (b0 [cohesive] + f forces_n) on
    slipping rows; forces = 0 on open ones; the pieces' equilibrium G^T forces + e
    = 0. The slipping rows' forces follow from their normal rows', so they
    are eliminated: one dense solve on the equality rows (and the pieces'
    amplitudes) only. Where that system is singular with floating pieces
    (this set's closed pairs leave a piece free), the amplitudes nearest the
    last iterate's."""
    S, normal, law = P.S, P.normal, P.law
    partner, f, b0 = law.partner, law.friction, law.cohesion_force
    m = len(P.jump0)
    r = P.G.shape[1]
    forces = np.zeros(m)
    eq = np.flatnonzero((normal & A) | P.prescribed | (T == STICK))
    sl = np.flatnonzero(T == SLIP)
    if len(eq) + len(sl) == 0 and r == 0:
        return forces, np.zeros(0)
    n = len(eq)
    # forces_sl = c_sl + D forces_eq: D has -sign f at the column of the slipping row's normal row (if it is an
    # equality row; else the pair touches without a normal force, forces_n = 0)
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
            # unloaded: loose_pieces.held)
            last = np.r_[np.zeros(n), np.zeros(r) if alpha_last is None else alpha_last]
            sol = last + np.linalg.lstsq(M, rhs - M @ last, rcond=None)[0]
    if r and not np.all(np.isfinite(sol)):
        return None
    forces[eq] = sol[:n]
    if len(sl):
        forces[sl] = c_sl + coef * (sol[np.maximum(pcol, 0)] if n else 0.0)
    return forces, sol[n:]
