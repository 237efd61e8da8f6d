"""The faces as the flow along the fractures sees them (the `mechanics` of
flow.lubrication): at a pressure field p on the network, the
contact/friction state and the openings, solved on the faces alone.

With the response of fem.face_response the unconstrained row jumps are
j_fixed + S_rp p, the friction law on the pair system gives the row forces
f (one increment from the reference slip, as every solve: the path
dependence of friction), and the edge nodes' openings are
w_fixed + W_p p + W_f f. No back-substitution: a Newton iteration of the
flow costs a pair-system solve. `complete(p)` solves the whole displacement
at the step's pressure once it has converged (the files, the SIFs, the
next step's reference), through the ordinary contact solve: its jumps
equal the faces' to the round-off of the solve.

The derivative the flow's Newton method takes, dw/dp, is that of the
last solve's contact and friction states held: 0 at an edge node whose
pair a normal row holds closed (its opening is the gap's); elsewhere
W_p + W_f df/dp, the forces f of the set moving so that the jumps of its
equality rows (closed normal rows, stuck and prescribed tangential rows)
hold, a slipping row's force the friction bound's share of its normal
row's. The mechanics is piecewise linear in p (one piece a set of states),
and this is the piece's exact derivative: the flow's Newton method is a
semismooth one. Its cost is a dense solve on the set's rows, and none
where no pair is open (closed faults) or no row is closed (an open
hydraulic fracture: W_p).
"""
from __future__ import annotations

import numpy as np

from ..contact.friction import SLIP, STICK
from ..errors import ComputationError
from .face_response import FaceResponse


class CoupledFaces:
    """disc: the step's discretisation (its problem factorised, its contact
    rows on the dense pair system); net: the flow's network on its mesh."""

    def __init__(self, disc, net):
        contact = disc.contact
        if contact.saddle is not None:
            raise ComputationError("the flow along the fractures needs the dense pair system: this mesh has "
                                   f"{len(contact.rows)} pair rows, more than it holds")
        if contact.floating is not None:
            raise ComputationError("the flow along the fractures cannot drive pieces of the body that only "
                                   "contact holds")
        self.disc, self.net, self.contact = disc, net, contact
        problem = disc.problem
        self.response = r = FaceResponse(problem, disc.cm, contact.rows, net)
        self.load = net.load_matrix(len(disc.cm.x))   # (2 n_nodes, n): the pressure field's nodal forces
        # the loads the pressure leaves: the unconstrained solve at load factor 0 (the network's
        # pressure is what the factor multiplies)
        problem.set_face_forces(np.zeros((len(disc.cm.x), 2)))
        u = problem.solve(0.0)
        self.j_fixed = contact.op.jumps(u.vector.getArray()) if contact.op is not None else np.zeros(0)
        self.w_fixed = r.openings_of_solution()
        self.w = None
        self.result = None
        self.resolution = 0.0   # m: the round-off of the last openings
        self.last = None        # (p, w) of the last solve

    def openings(self, p) -> np.ndarray:
        """(k, 3) the opening at every edge node at the pressure field p (Pa,
        the network's nodes), the contact solved on the faces."""
        r = self.response
        p = np.asarray(p, float)
        f = np.zeros(0)
        if self.contact.op is not None:
            self.result = self.contact.solve_pairs(self.j_fixed + r.S_rp @ p, 1.0)
            f = self.result.forces
        parts = [self.w_fixed, r.W_p @ p] + ([r.W_f @ f] if len(f) else [])
        self.w = sum(parts)
        # the openings' round-off: of the sum of its parts (closed faces: parts of the jump scale that
        # cancel to the gap), and of the friction solve's forces that make them
        self.resolution = 64 * np.finfo(float).eps * sum(float(np.max(np.abs(a), initial=0.0)) for a in parts)
        self.last = (p.copy(), self.w.reshape(-1, 3))
        return self.last[1]

    def derivative(self) -> np.ndarray:
        """(3k, n) dw/dp at the last solve, its contact and friction states
        held (module doc)."""
        r, res, rows = self.response, self.result, self.contact.rows
        if res is None:
            return r.W_p
        normal = rows.normal
        closed = normal & res.active
        q = self.net.pair.ravel()
        shut = np.zeros(len(self.disc.cm.pairs), bool)
        shut[rows.pair[closed]] = True
        open_ = (q >= 0) & ~shut[np.maximum(q, 0)]   # the edge nodes whose opening the pressure moves
        W = np.zeros_like(r.W_p)
        if not open_.any():
            return W
        state = res.state if getattr(res, "state", None) is not None else np.zeros(len(rows), np.int8)
        coulomb = rows.coulomb & closed[np.maximum(rows.partner, 0)]
        equal = closed | (~normal & ~rows.coulomb) | (coulomb & (state == STICK))
        slipping = coulomb & (state == SLIP)
        E = np.flatnonzero(equal)
        if not len(E):
            W[open_] = r.W_p[open_]
            return W
        # the forces of the set: free on the equality rows, the friction bound's share of the partner's
        # normal force on the slipping rows (sign of their force), 0 on the open ones
        column = np.full(len(rows), -1)
        column[E] = np.arange(len(E))
        P = np.zeros((len(rows), len(E)))
        P[E, np.arange(len(E))] = 1.0
        s = np.flatnonzero(slipping)
        law = rows.friction_law()
        P[s, column[rows.partner[s]]] = np.sign(res.forces[s]) * law.friction[s]
        M = (r.S @ P)[E]                                    # the equality rows' jumps held
        X = np.linalg.solve(M.T, (r.W_f[open_] @ P).T).T    # (open, |E|)
        W[open_] = r.W_p[open_] - X @ r.S_rp[E]
        return W

    def complete(self, p) -> None:
        """The whole displacement at the pressure field p, with contact: the
        step's solution (its faces' forces set to the field's load)."""
        self.disc.problem.set_face_forces(np.asarray(self.load @ np.asarray(p, float)).reshape(-1, 2))
        self.disc.solver.solve(1.0)
