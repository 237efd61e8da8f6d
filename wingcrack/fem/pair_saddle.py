"""The contact problem of a pair system too large for its dense compliance:
one sparse saddle-point system per state set.

The dense route (fem.pair_operator) makes S = B^T K^-1 B once per mesh: a
dense matrix of the pair rows squared, from MUMPS's Schur complement on the
pair dofs (4 dofs a pair: 36,000 for a network of 1,000 small fractures, a
10 GB dense block MUMPS refuses). Here each state set of the active-set
iteration (contact.friction) is solved with the elasticity whole, the
multipliers beside the displacements:

    [ K      -B ] [u ]   [b]         K, b: the assembled stiffness and load
    [ L_u   L_mu] [mu] = [t]         (Dirichlet rows as assembled)

with, for each row j: an equality row (closed normal, sticking, prescribed)
B_j^T u = target_j; a slipping row mu_j + sign_j f_j mu_p = -sign_j c_j
(p its normal row); an open row mu_j = 0. The upper block is the same for
every set, the lower rows change values, not places: one pattern, factorised
by MUMPS (LU) per set. The jumps are B^T u.

The u block keeps the DOLFINx dof layout (rows and columns by global dof);
the m multiplier rows are the last rank's, after its own dofs, so that the
ownership ranges stay contiguous. Pieces that only contact holds are not
supported here (their rigid modes need the dense pair problem).
"""
from __future__ import annotations

import numpy as np
from mpi4py import MPI
from petsc4py import PETSc
from scipy import sparse

from ..errors import ComputationError

_PREFIX = "wingcrack_saddle_"


class PairSaddle:
    """The saddle-point solver of one mesh's pair rows (rows: ConstraintRows)."""

    def __init__(self, problem, rows):
        self.problem = problem
        fm = problem.fm
        comm = fm.mesh.comm
        self.comm = comm
        imap = fm.V.dofmap.index_map
        bs = fm.V.dofmap.index_map_bs
        self.n_owned = imap.size_local * bs
        n_global = imap.size_global * bs
        self.n_global = n_global
        m = len(rows)
        self.m = m
        last = comm.rank == comm.size - 1
        self.owns_mu = last
        start = imap.local_range[0] * bs
        self.start = start
        ghosts = imap.ghosts
        # global index of every local scalar dof (owned, then ghosts)
        local_blocks = np.r_[np.arange(imap.local_range[0], imap.local_range[1], dtype=np.int64),
                             np.asarray(ghosts, dtype=np.int64)]
        self.global_dof = (bs * local_blocks[:, None] + np.arange(bs)[None, :]).ravel()

        # B's entries on this rank, owned dofs only: (local dof, row, value), for measuring jumps
        # (every dof) and for the forces (free dofs only: a prescribed dof takes no force)
        fixed = np.zeros(self.n_owned, bool)
        for bc in problem.bcs:
            dofs, _ = bc.dof_indices()
            dofs = np.asarray(dofs)
            fixed[dofs[dofs < self.n_owned]] = True
        di, rj, val = [], [], []
        for nodes, sign in ((rows.plus, 1.0), (rows.minus, -1.0)):
            found, blk = fm.block_dofs(nodes)
            owned = np.flatnonzero(found & (blk >= 0) & (blk < imap.size_local))
            for comp in (0, 1):
                di.append(bs * blk[owned] + comp)
                rj.append(owned)
                val.append(sign * rows.direction[owned, comp])
        cat = (lambda a: np.concatenate(a)) if di else (lambda a: np.zeros(0))
        di, rj, val = cat(di).astype(np.int64), cat(rj).astype(np.int64), cat(val)
        self.B = sparse.csr_matrix((val, (di, rj)), shape=(self.n_owned, m))
        free = ~fixed[di]
        # the lower rows' u entries: every rank's B^T entries, on the last rank (global columns)
        gathered = comm.gather((rj, self.global_dof[di], val), root=comm.size - 1)
        if last:
            r_all = np.concatenate([g[0] for g in gathered]).astype(np.int64)
            c_all = np.concatenate([g[1] for g in gathered]).astype(np.int64)
            v_all = np.concatenate([g[2] for g in gathered])
            order = np.lexsort((c_all, r_all))
            self._low_r, self._low_c, self._low_v = r_all[order], c_all[order], v_all[order]
        # the pattern: upper rows = K's local rows + -B_free's entries; lower rows (last rank) = B^T entries,
        # the diagonal and the partner column of Coulomb rows
        K = problem.A
        indptr, indices, values = K.getValuesCSR()
        Kc = sparse.csr_matrix((values, indices, indptr), shape=(self.n_owned, n_global + m))
        Bf = sparse.csr_matrix((-val[free], (di[free], n_global + rj[free])), shape=(self.n_owned, n_global + m))
        upper = (Kc + Bf).tocsr()
        upper.sort_indices()
        self._upper = upper
        self.partner = np.asarray(rows.partner, np.int64)
        self.rows = rows
        if last:
            lower_pattern = self._lower(np.ones(m, bool), np.zeros(m), np.zeros(m), pattern=True)
            self._lower_pattern = lower_pattern
            M = sparse.vstack([upper, lower_pattern]).tocsr()
        else:
            M = upper
        M.sort_indices()
        self._nnz_upper = len(upper.data)
        n_local = self.n_owned + (m if last else 0)
        it = PETSc.IntType
        self.M = PETSc.Mat().createAIJ(size=((n_local, n_global + m), (n_local, n_global + m)),
                                       csr=(M.indptr.astype(it), M.indices.astype(it), M.data), comm=comm)
        self.M.assemble()
        self._csr = M
        self.ksp = PETSc.KSP().create(comm)
        self.ksp.setOptionsPrefix(_PREFIX)
        self.ksp.setType("preonly")
        pc = self.ksp.getPC()
        pc.setType("lu")
        pc.setFactorSolverType("mumps")
        self.ksp.setOperators(self.M)
        self.x, self.rhs = self.M.createVecs()
        self.factorisations = 0

    def _lower(self, eq, coef, diag, pattern=False) -> sparse.csr_matrix:
        """The m lower rows (global columns): B^T on equality rows, `diag` on
        the diagonal, coef at the partner column of slipping rows; with
        pattern, every place any set may use (values 1)."""
        m, n = self.m, self.n_global
        keep = np.ones(len(self._low_r), bool) if pattern else eq[self._low_r]
        rows = [self._low_r, np.arange(m)]
        cols = [self._low_c, n + np.arange(m)]
        vals = [np.where(keep, self._low_v, 0.0) if not pattern else np.ones(len(self._low_r)),
                np.ones(m) if pattern else diag]
        c = np.flatnonzero(self.rows.coulomb)
        rows.append(c)
        cols.append(n + self.partner[c])
        vals.append(np.ones(len(c)) if pattern else coef[c])
        L = sparse.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                              shape=(m, n + m))
        L.sum_duplicates()
        L.sort_indices()
        return L

    def jumps(self, u_owned) -> np.ndarray:
        """B^T u (every row), on every rank."""
        return self.comm.allreduce(self.B.T @ u_owned)

    def solve_set(self, eq, slip, sign, f, b0_cohesive, target, b: PETSc.Vec):
        """(u owned (n_owned,), mu (m,)) of one state set: eq (m,) bool equality rows; slip (m,) bool
        slipping rows with sign, friction f and cohesion force b0_cohesive (0 where the pair holds none);
        the rest open. b: the assembled load (the problem's right-hand side). Collective."""
        m = self.m
        coef = np.where(slip, sign * f, 0.0)
        coef = np.where(slip & (self.partner >= 0), coef, 0.0)
        diag = np.where(eq, 0.0, 1.0)
        low_rhs = np.where(eq, target, np.where(slip, -sign * b0_cohesive, 0.0))
        data = self._csr.data
        if self.owns_mu:
            # the lower rows' values in the fixed pattern's order (the pattern holds every place)
            data = data.copy()
            data[self._nnz_upper:] = _values_on(self._lower_pattern, self._lower(eq, coef, diag))
        self.M.setValuesCSR(self._csr.indptr.astype(PETSc.IntType), self._csr.indices.astype(PETSc.IntType), data)
        self.M.assemble()
        self.ksp.setOperators(self.M)
        arr = self.rhs.getArray()
        arr[:self.n_owned] = b.getArray(readonly=True)[:self.n_owned]
        if self.owns_mu:
            arr[self.n_owned:] = low_rhs
        try:
            self.ksp.setUp()
            self.ksp.solve(self.rhs, self.x)
        except PETSc.Error as err:
            raise ComputationError(f"contact: the saddle-point system of a state set could not be factorised "
                                   f"(PETSc error {err.ierr}): its closed pairs leave it singular") from None
        self.factorisations += 1
        if self.ksp.getConvergedReason() < 0:
            raise ComputationError("contact: the saddle-point solve of a state set failed")
        x = self.x.getArray(readonly=True)
        u = x[:self.n_owned].copy()
        mu = self.comm.bcast(x[self.n_owned:].copy() if self.owns_mu else None, root=self.comm.size - 1)
        if not (np.all(np.isfinite(u)) and np.all(np.isfinite(mu))):
            raise ComputationError("contact: the saddle-point system of a state set is singular (NaN)")
        return u, mu

    def destroy(self) -> None:
        for obj in (self.ksp, self.M, self.x, self.rhs):
            obj.destroy()


def _values_on(pattern: sparse.csr_matrix, values: sparse.csr_matrix) -> np.ndarray:
    """The entries of `values` at the places of `pattern` (both canonical CSR, values' places a subset),
    in pattern's order."""
    p_rows = np.repeat(np.arange(pattern.shape[0]), np.diff(pattern.indptr))
    v_rows = np.repeat(np.arange(values.shape[0]), np.diff(values.indptr))
    key_p = p_rows.astype(np.int64) * pattern.shape[1] + pattern.indices
    key_v = v_rows.astype(np.int64) * values.shape[1] + values.indices
    out = np.zeros(len(key_p))
    where = np.searchsorted(key_p, key_v)
    out[where] = values.data
    return out
