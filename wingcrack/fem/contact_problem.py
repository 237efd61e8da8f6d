"""Elasticity with fracture contact: the plain solve, then the active set on
the pair system (with Coulomb friction where the faces have it), then the
pair forces' response added to the displacement.

Friction is path dependent: every solve is one increment from the reference
slip, the converged slip of the Coulomb rows that accept() last took (at
first: what the previous mesh carried over, contact.slip_history). A solve
does not move the reference; the critical-load search accepts a solution
when it becomes its bracket's lower end, so that no solve starts from a
state further along the load path than its own load.

Pieces that only contact holds (wingcrack.floating) are solved through the
pair problem: u = K_g^-1 (f + B forces) + R alpha on the gauged stiffness,
their equilibrium R^T (f + B forces) = 0 a condition on forces (contact.friction,
Rigid); a piece that contact cannot hold fails with its motion named."""
from __future__ import annotations

import numpy as np

from ..contact.by_sets import solve_by_sets
from ..contact.friction import OPEN, SLIP, STICK, Mechanism, Rigid, solve_friction
from .. import progress
from ..errors import Collapse
from .pair_operator import PairOperator
from .pair_saddle import PairSaddle


class ContactProblem:
    """Wraps an ElasticProblem and the constraint rows of its mesh."""

    def __init__(self, problem, rows, floating=None, saddle: bool = False):
        """floating: the pieces only contact holds (wingcrack.floating.Floating;
        their gauge is among the problem's displacement conditions); saddle:
        solve each state set as one sparse saddle-point system
        (fem.pair_saddle) instead of on the dense pair compliance."""
        self.problem = problem
        self.rows = rows
        self.saddle = None
        if saddle and len(rows):
            self.saddle = PairSaddle(problem, rows)
        self.op = PairOperator(problem, rows) if len(rows) and self.saddle is None else None
        self.result = None
        self.reference = np.zeros(len(rows))   # s_ref on Coulomb rows
        self.floating = floating if floating is not None and floating.r else None
        if self.floating is not None:
            self.G = self.floating.jumps(rows)
            self._modes = self._mode_dofs()

    def _mode_dofs(self) -> list:
        """(owned local scalar dofs, values) of each rigid mode."""
        fm = self.problem.fm
        size = fm.V.dofmap.index_map.size_local
        out = []
        for nodes, values in zip(self.floating.nodes, self.floating.values):
            found, blk = fm.block_dofs(nodes)
            own = found & (blk >= 0) & (blk < size)
            out.append((np.r_[2 * blk[own], 2 * blk[own] + 1].astype(np.int64),
                        np.r_[values[own, 0], values[own, 1]]))
        return out

    def _generalised_loads(self) -> tuple[np.ndarray, np.ndarray]:
        """(e, the sums of its terms' magnitudes): e = R^T f of the last
        right-hand side (its gauge entries as assembled, before the gauge
        set them to zero). Collective."""
        p = self.problem
        b = p.b.getArray(readonly=True).copy()
        b[p.gauge_dofs] = p.b_gauge
        e = np.array([[float(values @ b[dofs]), float(np.abs(values) @ np.abs(b[dofs]))]
                      for dofs, values in self._modes]).reshape(-1, 2)
        e = p.fm.mesh.comm.allreduce(e)
        return e[:, 0], e[:, 1]

    def _add_rigid(self, u, alpha) -> None:
        arr = u.vector.getArray()
        for (dofs, values), a in zip(self._modes, alpha):
            arr[dofs] += a * values
        u.x.scatter_forward()

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
        if self.saddle is not None:
            return self._solve_saddle(load_factor, active)
        p.solve(load_factor, expand=False)   # u on a far interior when it is read (ElasticProblem.expand)
        if self.op is None:
            return None
        u = p.u_at(self.op.blocks)   # the pair dofs, outside a far interior (u there may be deferred)
        jump0 = self.op.jumps(u.vector.getArray())
        rigid = None if self.floating is None else Rigid(self.G, *self._generalised_loads())
        res = self.solve_pairs(jump0, load_factor, active, rigid)
        self.op.add_forces(u, res.forces)
        if rigid is not None:
            self._add_rigid(u, res.alpha)
        return res

    def solve_pairs(self, jump0, load_factor: float = 1.0, active=None, rigid=None):
        """The contact/friction state on the dense pair system for the
        unconstrained jumps `jump0` (the rows' jumps without pair forces) at
        `load_factor` (what scales the prescribed slip), one increment from
        the reference slip: the result (the displacement is not updated; a
        caller that knows jump0's loads, fem.coupled_faces, solves on the
        faces alone)."""
        rows = self.rows
        slip = rows.slip * self.problem.loads.bc_factor(load_factor)   # not scaled when the load is the pressure
        target = np.where(rows.normal, -rows.gap, np.where(rows.coulomb, self.reference, slip))
        progress.doing(f"contact at load factor {load_factor:.6g}: {len(rows)} pair rows")
        try:
            res = solve_friction(self.op.S, jump0, target, rows.normal, rows.friction_law(), active=active,
                                 start=self.result, rigid=rigid)   # the last solve's states: the next trial's start
        except Mechanism as err:
            raise Collapse(self.floating.describe(err.residual, rows, err.closed)) from None
        self.result = res
        return res

    def _solve_saddle(self, load_factor, active):
        """solve() through fem.pair_saddle: each state set with the elasticity
        whole; u becomes the accepted set's."""
        p, rows, sd = self.problem, self.rows, self.saddle
        b = p.prepare(load_factor)
        u = p.u
        n = sd.n_owned
        jump0 = sd.jumps(sd.unconstrained(b))   # K's solution: the set with every row open
        slip = rows.slip * p.loads.bc_factor(load_factor)
        target = np.where(rows.normal, -rows.gap, np.where(rows.coulomb, self.reference, slip))
        law = rows.friction_law()
        prescribed = ~rows.normal & ~rows.coulomb
        last = {}

        def solve(A, T, sign, C):
            eq = (rows.normal & A) | prescribed | (T == STICK)
            uu, forces = sd.solve_set(eq, T == SLIP, sign, law.friction, np.where(C, law.cohesion_force, 0.0), target,
                                  p.b)
            last["u"] = uu
            return forces, sd.jumps(uu)

        def respond(A, T, sign, C, y):   # the rows y's own pair problem, the others held (by_sets._cycling_rows)
            eq = (rows.normal & A) | prescribed | (T == STICK)
            return sd.respond(eq, T == SLIP, sign, law.friction, np.where(C, law.cohesion_force, 0.0), target, p.b, y)

        progress.doing(f"contact at load factor {load_factor:.6g}: {len(rows)} pair rows, a saddle-point system a set")
        # the complementarity parameters' scale: a force per unit length against a jump of the faces, ~E
        res = solve_by_sets(solve, jump0, target, rows.normal, law, sd.stiffness, active=active, start=self.result,
                            respond=respond)
        arr = u.vector.getArray()
        arr[:n] = last["u"]
        u.x.scatter_forward()
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
        # a pair closed on two normals (fractures met end to end at an angle) cannot move: it is held
        held = np.bincount(rows.pair[closed], minlength=num_pairs) >= 2
        state[held] = STICK
        return state

    def slip_increments(self, num_pairs: int) -> np.ndarray:
        """(num_pairs,) ds = s - s_ref of the Coulomb pairs (0 elsewhere)."""
        out = np.zeros(num_pairs)
        if self.result is not None and getattr(self.result, "state", None) is not None:
            c = self.rows.coulomb
            out[self.rows.pair[c]] = self.result.slip_increment()[c]
        return out

    def nodal_forces(self, num_nodes: int) -> np.ndarray:
        """(num_nodes, 2) pair forces on the face nodes (+forces v on the + node)."""
        F = np.zeros((num_nodes, 2))
        if self.result is None:
            return F
        f = self.result.forces[:, None] * self.rows.direction
        np.add.at(F, self.rows.plus, f)
        np.add.at(F, self.rows.minus, -f)
        return F

    def tractions(self) -> np.ndarray:
        """-forces / weight at each row (Pa): sigma_nn on normal rows (<= 0 in
        contact, 0 open), the tangential traction t_t on the + face along t
        on tangential rows."""
        if self.result is None:
            return np.zeros(len(self.rows))
        return -self.result.forces / np.maximum(self.rows.weight, 1e-300)

    def normal_traction(self) -> np.ndarray:
        """sigma_nn on the faces at each row (Pa; <= 0 in contact, 0 open);
        meaningful on normal rows."""
        return self.tractions()
