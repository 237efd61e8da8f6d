"""The compliance of force columns supported on the faces, B^T K^-1 B, from
the step's factorisation.

Where the factorisation holds the Schur complement S_c on a set of dofs P
that carries every column's support ((K^-1)_PP = S_c^-1, fem.schur), it is
W^T W with W = L^-1 B_P, S_c = L L^T: dense algebra on the faces, no
back-substitution. Elsewhere (several processes: PETSc 3.18 offers MUMPS
Schur complements on one process only; or columns outside P) it takes
MUMPS multi-right-hand-side solves on dense blocks of B's columns, one per
column in effect (a parallel MUMPS takes a distributed dense right-hand
side; its sparse one must sit on one process), and can keep K^-1 B.
"""
from __future__ import annotations

import numpy as np
from mpi4py import MPI
from petsc4py import PETSc
from scipy import linalg, sparse

from ..errors import ComputationError

#: numbers (owned rows x right-hand sides) per MUMPS multi-RHS solve (160 MB)
BLOCK = 20_000_000
#: MUMPS ICNTL(27), right-hand sides treated together in the solve phase
#: (the value that solved fastest in the benchmarks of several processes)
RHS_BLOCKING = 64
_SINGULAR = ("the stiffness matrix is singular: a fracture cuts off a piece of the body that no "
             "boundary condition holds")


def free_rows(problem, B: sparse.spmatrix) -> sparse.csr_matrix:
    """B (owned dofs x columns) with its rows at prescribed dofs zeroed: a
    prescribed dof takes no force (its row of K is the identity's)."""
    n = B.shape[0]
    fixed = np.zeros(n, dtype=bool)
    for bc in problem.bcs:
        dofs, _ = bc.dof_indices()
        dofs = np.asarray(dofs)
        fixed[dofs[dofs < n]] = True
    return (sparse.diags((~fixed).astype(float)) @ B).tocsr()


def schur_factor(problem):
    """The lower Cholesky factor L of the factorisation's Schur complement
    S_c = L L^T (dense), kept on the problem: every compliance of this
    factorisation uses the one factor."""
    cached = getattr(problem, "_schur_factor", None)
    if cached is not None and cached[0] is problem.schur_dofs:
        return cached[1]
    try:
        L = linalg.cholesky(problem.schur_complement(), lower=True)
    except np.linalg.LinAlgError:
        raise ComputationError(_SINGULAR) from None
    problem._schur_factor = (problem.schur_dofs, L)
    return L


def on_schur_dofs(problem, B: sparse.spmatrix) -> bool:
    """Does the factorisation's Schur complement carry every row of B?"""
    P = getattr(problem, "schur_dofs", None)
    if P is None:
        return False
    outside = np.ones(B.shape[0], dtype=bool)
    outside[P] = False
    return not sparse.csr_matrix(B)[outside].count_nonzero()


def compliance(problem, B_free: sparse.spmatrix, keep: int = 0) -> tuple[np.ndarray, np.ndarray | None]:
    """(S, Z): S = B^T K^-1 B (m, m), symmetric, for the force columns
    B_free (owned dofs x m, free_rows); Z = K^-1 B (owned dofs x m) where
    it was solved for and holds at most `keep` numbers on every process,
    else None. Collective."""
    if on_schur_dofs(problem, B_free):
        L = schur_factor(problem)
        W = linalg.solve_triangular(L, B_free[problem.schur_dofs].toarray(), lower=True)
        return W.T @ W, None
    comm = problem.fm.mesh.comm
    n_owned, m = B_free.shape
    if not problem._factored:
        problem.factorize()
    F = problem.solver.getPC().getFactorMatrix()
    F.setMumpsIcntl(27, RHS_BLOCKING)
    biggest = comm.allreduce(n_owned, op=MPI.MAX)
    kept = biggest * m <= keep   # the same choice on every process (a caller's use of Z is collective)
    block = max(1, BLOCK // max(biggest, 1))
    Z = np.zeros((n_owned, m)) if kept else None
    S = np.zeros((m, m))
    Bf = sparse.csc_matrix(B_free)
    for c0 in range(0, m, block):
        c1 = min(m, c0 + block)
        Rm = PETSc.Mat().createDense([(n_owned, PETSc.DETERMINE), (PETSc.DECIDE, c1 - c0)],
                                     array=np.asfortranarray(Bf[:, c0:c1].toarray()), comm=comm)
        Zm = PETSc.Mat().createDense([(n_owned, PETSc.DETERMINE), (PETSc.DECIDE, c1 - c0)], comm=comm)
        Zm.setUp()
        F.matSolve(Rm, Zm)
        Zb = Zm.getDenseArray()
        S[:, c0:c1] = Bf.T @ Zb
        if kept:
            Z[:, c0:c1] = Zb
        for obj in (Rm, Zm):
            obj.destroy()
    S = comm.allreduce(S)
    return 0.5 * (S + S.T), Z   # symmetric up to round-off
