"""Elasticity with fracture contact: the plain solve, then the active set on
the pair system (with Coulomb friction where the faces have it), then the
pair forces' response added to the displacement.

Friction is path dependent: every solve is one increment from the reference
slip, the converged slip of the Coulomb rows that accept() last took (at
first: what the previous mesh carried over, contact.slip_history). A solve
does not move the reference; the critical-load search accepts a solution
when it becomes its bracket's lower end, so that no solve starts from a
state further along the load path than its own load."""
from __future__ import annotations

import numpy as np

from ..contact.friction import OPEN, SLIP, solve_friction
from .pair_operator import PairOperator


class ContactProblem:
    """Wraps an ElasticProblem and the constraint rows of its mesh."""

    def __init__(self, problem, rows):
        self.problem = problem
        self.rows = rows
        self.op = PairOperator(problem, rows) if len(rows) else None
        self.result = None
        self.reference = np.zeros(len(rows))   # s_ref on Coulomb rows

    @property
    def has_friction(self) -> bool:
        return bool(np.any(self.rows.coulomb))

    def set_reference(self, slip_per_pair: np.ndarray) -> None:
        """The reference slip of every Coulomb row from the slip of every pair."""
        c = self.rows.coulomb
        self.reference = np.where(c, np.asarray(slip_per_pair, float)[self.rows.pair], 0.0)

    def accept(self) -> None:
        """The current solution becomes the reference of the next increment."""
        if self.result is not None:
            self.reference = np.where(self.rows.coulomb, self.result.jump, 0.0)

    def solve(self, load_factor: float = 1.0, active=None):
        """One increment to `load_factor` from the reference slip; `active`:
        the normal rows the active set starts in contact (default: those
        penetrating without contact forces)."""
        p = self.problem
        p.solve(load_factor, expand=False)   # u on a far interior when it is read (ElasticProblem.expand)
        if self.op is None:
            return None
        rows = self.rows
        u = p.u_at(self.op.blocks)   # the pair dofs, outside a far interior (u there may be deferred)
        jump0 = self.op.jumps(u.vector.getArray())
        slip = rows.slip * p.loads.bc_factor(load_factor)   # not scaled when the load is the pressure
        target = np.where(rows.normal, -rows.gap, np.where(rows.coulomb, self.reference, slip))
        res = solve_friction(self.op.S, jump0, target, rows.normal, rows.friction_law(), active=active,
                             start=self.result)   # the last solve's states: the search's next trial starts there
        self.op.add_forces(u, res.mu)
        self.result = res
        return res

    def pair_states(self, num_pairs: int) -> np.ndarray:
        """(num_pairs,) OPEN / STICK / SLIP of every face-node pair: OPEN
        where no normal row is closed (and on faces without rows), the
        friction law's state on Coulomb pairs, SLIP on other closed pairs
        (frictionless: the tangential traction is 0, the bound)."""
        state = np.full(num_pairs, OPEN, np.int8)
        res = self.result
        if res is None:
            return state
        rows = self.rows
        closed = rows.normal & res.active
        state[rows.pair[closed]] = SLIP
        if getattr(res, "state", None) is not None:
            c = rows.coulomb
            state[rows.pair[c]] = res.state[c]
        return state

    def slip_increments(self, num_pairs: int) -> np.ndarray:
        """(num_pairs,) ds = s - s_ref of the Coulomb pairs (0 elsewhere)."""
        out = np.zeros(num_pairs)
        if self.result is not None and getattr(self.result, "state", None) is not None:
            c = self.rows.coulomb
            out[self.rows.pair[c]] = self.result.slip_increment()[c]
        return out

    def nodal_forces(self, num_nodes: int) -> np.ndarray:
        """(num_nodes, 2) pair forces on the face nodes (+mu v on the + node)."""
        F = np.zeros((num_nodes, 2))
        if self.result is None:
            return F
        f = self.result.mu[:, None] * self.rows.direction
        np.add.at(F, self.rows.plus, f)
        np.add.at(F, self.rows.minus, -f)
        return F

    def tractions(self) -> np.ndarray:
        """-mu / weight at each row (Pa): sigma_nn on normal rows (<= 0 in
        contact, 0 open), the tangential traction t_t on the + face along t
        on tangential rows."""
        if self.result is None:
            return np.zeros(len(self.rows))
        return -self.result.mu / np.maximum(self.rows.weight, 1e-300)

    def normal_traction(self) -> np.ndarray:
        """sigma_nn on the faces at each row (Pa; <= 0 in contact, 0 open);
        meaningful on normal rows."""
        return self.tractions()
