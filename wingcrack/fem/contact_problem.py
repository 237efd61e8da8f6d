"""Elasticity with fracture contact: the plain solve, then the active set on
the pair system, then the pair forces' response added to the displacement."""
from __future__ import annotations

import numpy as np

from ..contact.active_set import solve_active_set
from .pair_operator import PairOperator


class ContactProblem:
    """Wraps an ElasticProblem and the constraint rows of its mesh."""

    def __init__(self, problem, rows):
        self.problem = problem
        self.rows = rows
        self.op = PairOperator(problem, rows) if len(rows) else None
        self.result = None

    def solve(self, load_factor: float = 1.0, active=None):
        p = self.problem
        p.solve(load_factor)
        if self.op is None:
            return None
        rows = self.rows
        jump0 = self.op.jumps(p.u.vector.getArray())
        target = np.where(rows.normal, -rows.gap, rows.slip * load_factor)
        res = solve_active_set(self.op.S, jump0, target, rows.normal, active=active)
        self.op.add_forces(p.u, res.mu)
        self.result = res
        return res

    def nodal_forces(self, num_nodes: int) -> np.ndarray:
        """(num_nodes, 2) pair forces on the face nodes (+mu v on the + node)."""
        F = np.zeros((num_nodes, 2))
        if self.result is None:
            return F
        f = self.result.mu[:, None] * self.rows.direction
        np.add.at(F, self.rows.plus, f)
        np.add.at(F, self.rows.minus, -f)
        return F

    def normal_traction(self) -> np.ndarray:
        """sigma_nn on the faces at each row (Pa; <= 0 in contact, 0 open);
        meaningful on normal rows."""
        if self.result is None:
            return np.zeros(len(self.rows))
        return -self.result.mu / np.maximum(self.rows.weight, 1e-300)
