"""The pair operator: B (dofs x rows) and the pair compliance S = B^T K^-1 B.

Column j of B holds +v_j at the + node's dofs and -v_j at the - node's, so
B^T u are the jumps (u+ - u-).v_j and B forces are the pair forces. S comes from
the Schur complement S_c of K on the pair dofs P that MUMPS computes during
the factorisation ((K^-1)_PP = S_c^-1; see fem.schur), or, where that is not
available (several processes: PETSc 3.18 offers MUMPS Schur complements on
one process only), from K^-1 B by MUMPS multi-right-hand-side solves, one per
pair row in effect (the contact phase then grows with pairs x DOFs; see
docs/user-guide/mpi.md).
Either way it is built once per mesh; every active-set
iteration, load factor or slip value is then a small dense solve, and the
pair forces' response is one more back-substitution (none where the
forces lie in the span of the last two: add_forces). Rows of B at Dirichlet
dofs are zeroed for the force side (a prescribed dof takes no force), but
kept for measuring jumps.
"""
from __future__ import annotations

import numpy as np
from mpi4py import MPI
from petsc4py import PETSc
from scipy import linalg, sparse

from ..errors import ComputationError
from .solution_span import SolutionSpan


BLOCK = 20_000_000    # numbers (owned rows x right-hand sides) per MUMPS multi-RHS solve (160 MB)
#: MUMPS ICNTL(27), right-hand sides treated together in the solve phase
#: (the value that solved fastest in the benchmarks of several processes)
RHS_BLOCKING = 64
Z_KEEP = 20_000_000   # keep K^-1 B (owned rows x pairs) up to this many numbers (160 MB)
#: pair-force responses K^-1 B forces kept for forces in their span (fem.solution_span): the
#: contact forces of a problem linear in its load are proportional to the load
#: factor (closed faces without gap or slip), so the critical-load search's
#: second solve of a step takes its response from the first
SPAN = 2
#: ... where the least-squares residual is below this times |forces|: the multipliers come
#: from a dense solve of the pair system, so they carry its round-off, about
#: cond(S_AA) eps (1.9e-14 between two load factors of a closed crack in a plate,
#: tests/unit/test_solve_span.py), above the 1e-14 that assembled right-hand sides meet;
#: a residual within that round-off changes the response no more than the forces' own error does
SPAN_TOLERANCE = 1e-12
_SINGULAR = ("the stiffness matrix is singular: a fracture cuts off a piece of the body that no "
             "boundary condition holds")


class PairOperator:
    def __init__(self, problem, rows):
        self.problem = problem
        fm = problem.fm
        comm = fm.mesh.comm
        V = fm.V
        imap = V.dofmap.index_map
        bs = V.dofmap.index_map_bs
        self.n_owned = imap.size_local * bs
        m = len(rows)
        self.m = m

        # local owned rows of B (sparse, n_owned x m: 4 entries a column)
        dof_i, col_j, val = [], [], []
        for nodes, sign in ((rows.plus, 1.0), (rows.minus, -1.0)):
            found, blk = fm.block_dofs(nodes)
            owned = np.flatnonzero(found & (blk < imap.size_local))
            for comp in (0, 1):
                dof_i.append(bs * blk[owned] + comp)
                col_j.append(owned)
                val.append(sign * rows.direction[owned, comp])
        cat = (lambda a: np.concatenate(a)) if dof_i else (lambda a: np.zeros(0))
        B = sparse.csr_matrix((cat(val), (cat(dof_i).astype(np.int64), cat(col_j).astype(np.int64))),
                              shape=(self.n_owned, m))
        self.B = B
        fixed = np.zeros(self.n_owned, dtype=bool)
        for bc in problem.bcs:
            dofs, _ = bc.dof_indices()
            dofs = np.asarray(dofs)
            fixed[dofs[dofs < self.n_owned]] = True
        self.B_free = sparse.diags((~fixed).astype(float)) @ B
        self.blocks = np.unique(np.r_[fm.block_dofs(rows.plus)[1], fm.block_dofs(rows.minus)[1]])
        self.blocks = self.blocks[self.blocks >= 0]   # the local block dofs of the pair nodes
        self.Z = None
        self._responses = SolutionSpan(m, self.n_owned, SPAN, comm, SPAN_TOLERANCE)   # earlier forces and K^-1 B forces
        if getattr(problem, "schur_dofs", None) is not None:
            P = problem.schur_dofs
            Sc = problem.schur_complement()
            BP = self.B_free[P].toarray()
            # Sc is SPD: S = W^T W with W = L^-1 B_P, Sc = L L^T (symmetric by construction)
            try:
                L = linalg.cholesky(Sc, lower=True)
            except np.linalg.LinAlgError:
                raise ComputationError(_SINGULAR) from None
            W = linalg.solve_triangular(L, BP, lower=True)
            self.S = W.T @ W
            return

        # S = B^T K^-1 B by MUMPS multi-right-hand-side solves on dense
        # blocks of B's columns (a parallel MUMPS takes a distributed dense
        # right-hand side; its sparse one must sit on one process). Z = K^-1 B
        # is kept for the pair-force response when it is small, otherwise
        # that response is one more solve.
        if not problem._factored:
            problem.factorize()
        F = problem.solver.getPC().getFactorMatrix()
        F.setMumpsIcntl(27, RHS_BLOCKING)
        biggest = comm.allreduce(self.n_owned, op=MPI.MAX)
        keep = biggest * m <= Z_KEEP   # the same choice on every process (add_forces is collective)
        block = max(1, BLOCK // max(biggest, 1))
        Z = np.zeros((self.n_owned, m)) if keep else None
        self.S = np.zeros((m, m))
        Bf = self.B_free.tocsc()
        for c0 in range(0, m, block):
            c1 = min(m, c0 + block)
            Rm = PETSc.Mat().createDense([(self.n_owned, PETSc.DETERMINE), (PETSc.DECIDE, c1 - c0)],
                                         array=np.asfortranarray(Bf[:, c0:c1].toarray()), comm=comm)
            Zm = PETSc.Mat().createDense([(self.n_owned, PETSc.DETERMINE), (PETSc.DECIDE, c1 - c0)], comm=comm)
            Zm.setUp()
            F.matSolve(Rm, Zm)
            Zb = Zm.getDenseArray()
            self.S[:, c0:c1] = Bf.T @ Zb
            if keep:
                Z[:, c0:c1] = Zb
            for obj in (Rm, Zm):
                obj.destroy()
        self.Z = Z
        self.S = comm.allreduce(self.S)
        self.S = 0.5 * (self.S + self.S.T)  # symmetric up to round-off

    def jumps(self, u_owned: np.ndarray) -> np.ndarray:
        """B^T u for the owned part of a displacement vector."""
        return self.problem.fm.mesh.comm.allreduce(self.B.T @ u_owned)

    def add_forces(self, u, forces: np.ndarray) -> None:
        """u += K^-1 B forces (the response to the pair forces), then update ghosts."""
        if self.Z is not None:
            arr = u.vector.getArray()
            arr += self.Z @ forces
        else:
            forces = np.asarray(forces, dtype=np.float64)
            du = self._responses.find(forces)   # forces is the same on every process: the sums only scale
            if du is None:
                p = self.problem
                rhs = p.b.duplicate()
                rhs.getArray()[:] = self.B_free @ forces
                dv = rhs.duplicate()
                # through the far field's condensation where factorize reused it: on R only, u's far
                # interior part is computed from u on R when it is read (p.defer, ElasticProblem.expand)
                p.solve_vector(rhs, dv, expand=False)
                du = dv.getArray(readonly=True).copy()
                self._responses.add(forces, du)
                rhs.destroy()
                dv.destroy()
            arr = u.vector.getArray()
            arr += du
            self.problem.defer()
        u.x.scatter_forward()

    @property
    def span_solves(self) -> int:
        """Pair-force responses answered from the kept ones."""
        return self._responses.hits

    @staticmethod
    def pair_dofs(fm, rows) -> np.ndarray:
        """Owned local dofs touched by the rows (the Schur set)."""
        imap = fm.V.dofmap.index_map
        found, blk = fm.block_dofs(np.unique(np.r_[rows.plus, rows.minus]))
        blk = np.unique(blk[found & (blk < imap.size_local)])
        return np.sort(np.r_[2 * blk, 2 * blk + 1]).astype(np.int64)
