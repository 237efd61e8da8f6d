"""Coulomb friction on the pair system: a primal-dual active set with three
states a pair (open, stick, slip), the semi-smooth Newton method of Hueber,
Stadler & Wohlmuth (2008) written for 2D, where the tangential space of a
pair is one line and the slip direction one sign.

With the elasticity factorised, jumps depend on the row forces (the
contact multipliers: nodal forces, + on the + node) through the dense pair
compliance S, and, where a piece of the body is held by contact alone, on
the amplitudes alpha of its rigid-body modes (their jumps G):

    jump(forces, alpha) = jump0 + S forces + G alpha,    G^T forces + e = 0,

the second the piece's equilibrium (e: its other loads as generalised forces
on the modes; FETI's coarse problem). Without such pieces G has no columns.

Rows: normal rows (w + g >= 0, forces_n >= 0, forces_n (w + g) = 0), prescribed
tangential rows ("slip" faces: jump = target) and Coulomb tangential rows
paired with their normal row p. On a Coulomb row the friction law acts on
the slip increment ds = s - s_ref from the last converged state s_ref:

    |forces_t| <= F = c w_p + friction forces_n     (bound; forces; c only while touching)
    |forces_t| <  F  ->  ds = 0                      (stick)
    |forces_t| =  F  ->  forces_t ds <= 0            (slip, against the increment)

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

With q = -forces_t the update of a closed pair's state is
    z = q + c_t ds;  |z| > F: slip with sign(z), q = F sign(z); else stick,
and F from the normal predictor forces_n - c_n (w + g) (Hueber et al.); a pair
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

import numpy as np

from .active_set import solve_active_set
from .friction_fixed_point import fallback, fixed_point_solve
from .friction_problem import (BOUND_RTOL, MAX_ITERATIONS, OPEN, RESIDUAL_RTOL, SCALINGS, SLIP, STATE_BAND, STICK,
                               TOUCH_RTOL, FrictionResult, FrictionRows, Mechanism, PairProblem, Rigid,
                               complementarity_parameters)
from .friction_sets import iterate_states, start_states
from .loose_pieces import held, loose_first

__all__ = ["BOUND_RTOL", "MAX_ITERATIONS", "OPEN", "RESIDUAL_RTOL", "SCALINGS", "SLIP", "STATE_BAND", "STICK",
           "TOUCH_RTOL", "FrictionResult", "FrictionRows", "Mechanism", "Rigid", "fixed_point_solve", "solve_friction"]


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
    P = PairProblem.of(S, jump0, target, normal, ~normal & ~coulomb, law, rigid)
    if r:
        res = loose_first(P, max_iter, active, start, solve_friction)
        if res is not None:
            return res
    cn, ct = complementarity_parameters(P)
    history = []
    if getattr(start, "state", None) is not None and len(start.forces) == len(P.jump0):
        res = iterate_states(P, cn, ct, max_iter, history, states=start_states(start, P))
        if res is not None:
            return held(P, res)
    for k in SCALINGS:
        res = iterate_states(P, cn * k, ct * k, max_iter, history, active)
        if res is not None:
            return held(P, res)
    return held(P, fallback(P, history, max_iter))
