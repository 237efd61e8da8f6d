"""fem.mumps_inverse (entries of the inverse of a MUMPS factor, MUMPS's ICNTL(30)) against numpy's
inverse of the same matrix, and a plain solve through the same factor afterwards (PETSc leaves the
controls of the entries' solve set; they are put back)."""
import numpy as np
from mpi4py import MPI
from petsc4py import PETSc
from scipy import sparse

from wingcrack.fem import mumps_inverse


def _factor(A):
    n = A.shape[0]
    M = PETSc.Mat().createAIJ(size=(n, n), csr=(A.indptr.astype(PETSc.IntType), A.indices.astype(PETSc.IntType),
                                                A.data), comm=PETSc.COMM_SELF)
    M.assemble()
    ksp = PETSc.KSP().create(PETSc.COMM_SELF)
    ksp.setType("preonly")
    ksp.getPC().setType("lu")
    ksp.getPC().setFactorSolverType("mumps")
    ksp.setOperators(M)
    ksp.setUp()
    return M, ksp


def test_the_entries_are_those_of_the_inverse_and_a_solve_after_them_is_a_solve():
    assert mumps_inverse.available()
    rng = np.random.default_rng(3)
    n = 300
    # unsymmetric, with zero diagonal entries as a saddle system has (MUMPS pivots off the diagonal)
    A = (sparse.random(n, n, density=0.02, random_state=4) + sparse.diags(rng.uniform(1, 2, n))).tolil()
    i = np.arange(0, n, 7)
    A[i, i] = 0.0
    A[i, (i + 1) % n] = 3.0
    A = A.tocsr()
    A.sort_indices()
    dense_inverse = np.linalg.inv(A.toarray())
    M, ksp = _factor(A)
    F = ksp.getPC().getFactorMatrix()
    rows = np.array([250, 3, 17, 0, 128])          # unsorted: the result is in the order asked
    cols = np.array([9, 299, 40])
    W = mumps_inverse.inverse_entries(F, rows, cols, MPI.COMM_SELF)
    # a direct solve's accuracy on a matrix of condition ~1e3
    np.testing.assert_allclose(W, dense_inverse[np.ix_(rows, cols)], rtol=0,
                               atol=1e-12 * np.abs(dense_inverse).max())
    b, x = M.createVecs()
    b.setArray(rng.normal(size=n))
    ksp.solve(b, x)
    np.testing.assert_allclose(x.getArray(), dense_inverse @ b.getArray(), rtol=0,
                               atol=1e-12 * np.abs(dense_inverse @ b.getArray()).max())
    assert F.getMumpsIcntl(30) == 0
