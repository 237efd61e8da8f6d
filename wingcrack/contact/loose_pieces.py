"""Pieces of the body that only contact holds, in the friction solve: whether
the rows that hold fix every rigid motion (else the mechanism, or a loose
piece placed in the middle of its opening), and the pieces no load drives
solved without their faces first."""
from __future__ import annotations

import numpy as np
from scipy.optimize import linprog

from .friction_problem import OPEN, STICK, FrictionResult, FrictionRows, Mechanism, PairProblem, Rigid, result_of

#: the rigid modes' jumps on the rows that hold (closed normal, sticking, prescribed) determine the
#: amplitudes when their smallest singular value is above this times the largest
HELD_RTOL = 1e-8
#: a load on a rigid motion below this times the magnitude of the terms it sums is round-off: the
#: motion is unloaded (the in-situ stress's load on an inner piece sums to zero, to ~1e-16 of its terms)
UNLOADED_RTOL = 1e-9


def held(P: PairProblem, res: FrictionResult) -> FrictionResult:
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


def loose_first(P: PairProblem, max_iter, active, start, solve) -> FrictionResult | None:
    """The answer where the pieces that no load drives are loose: their
    faces' rows carry nothing, the rest is solved without them, and each is
    put in the middle of its opening; None where one would then penetrate a
    face (it touches: the whole problem is solved), or where there are no
    such pieces. (Left in the whole problem, a loose piece's place is free,
    and the semi-smooth Newton iteration wanders with it: a pressurised
    block went through tens of state sets without settling.) solve: the
    friction solve itself (contact.friction.solve_friction), for the rest."""
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
    if getattr(start, "state", None) is not None and len(start.forces) == len(gone):
        sub_start = FrictionResult(start.forces[keep], start.jump[keep], start.active[keep], 0, [], start.jump0[keep],
                                   state=start.state[keep], reference=start.reference[keep], law=sub_law,
                                   cohesive=None if start.cohesive is None else start.cohesive[keep])
    sub = solve(P.S[np.ix_(keep, keep)], P.jump0[keep], P.target[keep], P.normal[keep], sub_law, max_iter,
                         None if active is None else np.asarray(active, bool)[keep], sub_start, rigid)
    m = len(gone)
    forces = np.zeros(m)
    forces[keep] = sub.forces
    alpha = np.zeros(r)
    if len(rest):
        alpha[rest] = getattr(sub, "alpha", np.zeros(len(rest)))
    jump = P.jump0 + P.S @ forces + G @ alpha
    rows = gone & P.normal
    GV = G[np.ix_(rows, loose_cols)]
    gamma = (jump - P.target)[rows]
    z = _middle(GV, gamma - float(np.min(gamma, initial=0.0)))   # the best place, from where they stand
    after = gamma + GV @ z
    if np.min(after, initial=0.0) < 0.0:
        return None   # it would penetrate: it touches somewhere
    alpha[loose_cols] += z
    jump = P.jump0 + P.S @ forces + G @ alpha
    A = np.zeros(m, bool)
    A[keep] = sub.active
    T = np.full(m, OPEN, np.int8)
    C = np.zeros(m, bool)
    if getattr(sub, "state", None) is not None:
        T[keep] = sub.state
        C[keep] = sub.cohesive
    res = result_of(P, forces, alpha, jump, A & P.normal, T, C, list(sub.history), fallback=bool(sub.fallback),
                  iterations=int(sub.iterations), broken=int(getattr(sub, "broken", 0)))
    res.loose = int(loose_cols.sum()) + int(getattr(sub, "loose", 0))
    return res


def _complement(vt, r) -> np.ndarray:
    """Rows completing the orthonormal rows vt to a basis of R^r."""
    q, _ = np.linalg.qr(np.vstack([vt, np.eye(r)]).T)
    return q[:, len(vt):r].T
