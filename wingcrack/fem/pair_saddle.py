"""The contact problem of a pair system too large for its dense compliance:
one sparse saddle-point system per state set.

The dense route (fem.pair_operator) makes S = B^T K^-1 B once per mesh: a
dense matrix of the pair rows squared, from MUMPS's Schur complement on the
pair dofs (4 dofs a pair: 36,000 for a network of 1,000 small fractures, a
10 GB dense block MUMPS refuses). Here each state set of the active-set
iteration (contact.friction) is solved with the elasticity whole, the
multipliers beside the displacements:

    [ K      -B ] [u ]   [b]         K, b: the assembled stiffness and load
    [ L_u   L_f] [forces] = [t]         (Dirichlet rows as assembled)

with, for each row j: an equality row (closed normal, sticking, prescribed)
B_j^T u = target_j; a slipping row forces_j + sign_j f_j forces_p = -sign_j c_j
(p its normal row); an open row forces_j = 0. The upper block is the same for
every set, the lower rows change values, not places: one pattern, factorised
by MUMPS (LU). The jumps are B^T u.

The equality rows are scaled by the faces' jump stiffness (PairSaddle.stiffness, ~E):
s B_j^T u = s target_j, so that every lower row is a force (N/m) as the
slipping and open rows are, and a row that changes from one kind to the
other changes the matrix by a term of its own size (unscaled, a row from
slip to stick changed it by 1 against a response of 1e-10: the update's
capacitance matrix below lost ten digits to that cancellation).

The active set's first iterations change thousands of rows, its last ones a
few hundred at most, and these change the same rows back and forth: a
set whose lower rows differ from the factorised set's in r rows is that
matrix plus a rank-r change, solved through the factorisation kept by the
Sherman-Morrison-Woodbury formula (_updated), with two solves and the
entries of the factors' inverse at the changed rows' columns
(fem.mumps_inverse: MUMPS prunes its solves to them, so a few hundred rows
cost about what two solves do, where a column each cost a solve). The
factorisation is renewed when a set changes more than REUSE_ROWS rows, or
needs more than REUSE_ENTRIES of those entries, or when the update's
residual is not that of a direct solve.

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
from . import mumps_failure, mumps_inverse
from .solution_span import SolutionSpan

_PREFIX = "wingcrack_saddle_"
#: at most this many changed rows are solved by an update of the factorisation kept (its capacitance
#: matrix is dense, r x r) ...
REUSE_ROWS = 1000
#: ... and at most this many entries of the inverse computed for it (rows changed x the columns their
#: lower rows use): on a saddle system of 3.8M unknowns, 2e6 of them cost about half a numeric
#: factorisation, a few thousand about a solve
REUSE_ENTRIES = 2_000_000
#: an update whose residual exceeds this times ||F|| ||x|| + ||b|| (infinity norms; a direct solve's is
#: ~1e-16 of it) is not trusted: the set is factorised instead
UPDATE_RESIDUAL = 1e-11
#: nor one whose capacitance matrix I + D Z is this ill-conditioned (the set near singular)
UPDATE_CONDITION = 1e10
#: MUMPS ICNTL(7) of the analysis: approximate minimum fill. PORD (MUMPS's own choice in a build
#: without METIS and SCOTCH, as Debian's) fills less but orders several times slower on large pair
#: systems, while a set's numeric factorisation is memory-bound, not flop-bound, and costs the same
ORDERING = 2


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
        self.owns_forces = last
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
        self.B_free = sparse.csr_matrix((val[free], (di[free], rj[free])), shape=(self.n_owned, m))   # forces
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
        self.partner = np.asarray(rows.partner, np.int64)
        self.rows = rows
        # the faces' jump stiffness: the force per unit length a unit jump takes, ~E (the scale of the
        # equality rows here, and of the complementarity parameters of the iteration, contact.by_sets)
        lame_lambda, lame_mu = float(problem.lame_lambda.value), float(problem.lame_mu.value)
        self.stiffness = 4.0 * lame_mu * (lame_lambda + lame_mu) / (lame_lambda + 2.0 * lame_mu)
        K = problem.A
        indptr, indices, values = K.getValuesCSR()
        Kc = sparse.csr_matrix((values, indices, indptr), shape=(self.n_owned, n_global + m))
        Bf = sparse.csr_matrix((-val[free], (di[free], n_global + rj[free])), shape=(self.n_owned, n_global + m))
        upper = (Kc + Bf).tocsr()
        del Kc, Bf, indptr, indices, values
        upper.sort_indices()
        if last:
            lower_pattern = self._lower(np.ones(m, bool), np.zeros(m), np.zeros(m), pattern=True)
            self._lower_pattern = lower_pattern
            M = sparse.vstack([upper, lower_pattern]).tocsr()
        else:
            M = upper
        M.sort_indices()
        del upper
        n_local = self.n_owned + (m if last else 0)
        it = PETSc.IntType
        self.M = PETSc.Mat().createAIJ(size=((n_local, n_global + m), (n_local, n_global + m)),
                                       csr=(M.indptr.astype(it), M.indices.astype(it), M.data), comm=comm)
        self.M.assemble()
        del M   # PETSc holds the matrix; a set changes the lower rows only (_set_lower)
        self.ksp = PETSc.KSP().create(comm)
        self.ksp.setOptionsPrefix(_PREFIX)
        self.ksp.setType("preonly")
        pc = self.ksp.getPC()
        pc.setType("lu")
        pc.setFactorSolverType("mumps")
        self.ksp.setOperators(self.M)
        pc.setFactorSetUpSolverType()
        # PETSc 3.18 reads ICNTL(7) from the options database at the analysis (over MatMumpsSetIcntl):
        # under the factor's own prefix, set for the analysis only (_factorised)
        pc.getFactorMatrix().setOptionsPrefix(_PREFIX + "factor_")
        self.x, self.rhs = self.M.createVecs()
        self.factorisations = 0
        self.updates = 0      # sets solved by an update of the factorisation kept
        self.entries = 0      # entries of F^-1 computed for them
        self._factored = None  # the lower rows' values of the factorised set (last rank; True elsewhere)
        self._gather_columns(last)
        self._span = SolutionSpan(self.n_owned, self.n_owned, 2, comm)   # K^-1 b of the last loads (unconstrained)

    def _gather_columns(self, last: bool) -> None:
        """A scatter of a vector's entries at the lower rows' columns to the
        last rank (D x of an update, D a difference of lower rows), and the
        position of each lower pattern entry among them."""
        if last:
            cols = np.unique(self._lower_pattern.indices).astype(np.int64)
            self._pos = np.searchsorted(cols, self._lower_pattern.indices)
        else:
            cols = np.zeros(0, np.int64)
        self._cols = cols
        self._seq = PETSc.Vec().createSeq(len(cols), comm=PETSc.COMM_SELF)
        index = PETSc.IS().createGeneral(cols.astype(PETSc.IntType), comm=self.comm)
        self._scatter = PETSc.Scatter().create(self.x, index, self._seq, None)
        index.destroy()

    def _at_columns(self, vec: PETSc.Vec) -> np.ndarray:
        """vec's entries at the lower rows' columns, on the last rank (empty elsewhere). Collective."""
        self._scatter.scatter(vec, self._seq, addv=PETSc.InsertMode.INSERT, mode=PETSc.ScatterMode.FORWARD)
        return self._seq.getArray(readonly=True).copy()

    def _lower(self, eq, coef, diag, pattern=False) -> sparse.csr_matrix:
        """The m lower rows (global columns): B^T on equality rows (scaled by
        the stiffness, see the module), `diag` on
        the diagonal, coef at the partner column of slipping rows; with
        pattern, every place any set may use (values 1)."""
        m, n = self.m, self.n_global
        keep = np.ones(len(self._low_r), bool) if pattern else eq[self._low_r]
        rows = [self._low_r, np.arange(m)]
        cols = [self._low_c, n + np.arange(m)]
        vals = [np.where(keep, self.stiffness * self._low_v, 0.0) if not pattern else np.ones(len(self._low_r)),
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

    def unconstrained(self, b: PETSc.Vec) -> np.ndarray:
        """K^-1 b on this rank's owned dofs: the set with every row open (forces =
        0), through this system's factorisation (K is not factorised alone);
        from the kept solutions where b lies in their span (the loads are
        affine in the load factor: two such solves a mesh at most). Collective."""
        b_owned = b.getArray(readonly=True)[:self.n_owned]
        u = self._span.find(b_owned)
        if u is None:
            none = np.zeros(self.m, bool)
            u, _ = self.solve_set(none, none, np.zeros(self.m), np.zeros(self.m), np.zeros(self.m),
                                  np.zeros(self.m), b)
            self._span.add(b_owned, u)
        return u

    def solve_set(self, eq, slip, sign, f, b0_cohesive, target, b: PETSc.Vec):
        """(u owned (n_owned,), forces (m,)) of one state set: eq (m,) bool equality rows; slip (m,) bool
        slipping rows with sign, friction f and cohesion force b0_cohesive (0 where the pair holds none);
        the rest open. b: the assembled load (the problem's right-hand side). Collective."""
        low = self._prepare(eq, slip, sign, f, b0_cohesive, target, b)
        x = self._updated(low)
        if x is None:
            x = self._factorised(low)
        return self._parts(x)

    def _prepare(self, eq, slip, sign, f, b0_cohesive, target, b: PETSc.Vec):
        """The set's right-hand side into self.rhs; its lower rows' values
        (pattern order, last rank; None elsewhere)."""
        coef = np.where(slip, sign * f, 0.0)
        coef = np.where(slip & (self.partner >= 0), coef, 0.0)
        diag = np.where(eq, 0.0, 1.0)
        low_rhs = np.where(eq, self.stiffness * target, np.where(slip, -sign * b0_cohesive, 0.0))
        arr = self.rhs.getArray()
        arr[:self.n_owned] = b.getArray(readonly=True)[:self.n_owned]
        low = None
        if self.owns_forces:
            arr[self.n_owned:] = low_rhs
            low = _values_on(self._lower_pattern, self._lower(eq, coef, diag))
        return low

    def _parts(self, x):
        """(u owned, forces (m,) on every rank) of a solution's entries on this rank."""
        u = x[:self.n_owned].copy()
        forces = self.comm.bcast(x[self.n_owned:].copy() if self.owns_forces else None, root=self.comm.size - 1)
        if not (np.all(np.isfinite(u)) and np.all(np.isfinite(forces))):
            raise ComputationError("contact: the saddle-point system of a state set is singular (NaN)")
        return u, forces

    def _factorised(self, low) -> np.ndarray:
        """The set's solution (this rank's entries) by a new factorisation of
        the matrix with lower rows `low` (pattern order, last rank)."""
        self._set_lower(low)
        self.ksp.setOperators(self.M)
        options = PETSc.Options()
        ordering = _PREFIX + "factor_mat_mumps_icntl_7"
        options[ordering] = ORDERING
        try:
            self.ksp.setUp()
        except PETSc.Error as err:
            raise ComputationError(_factor_failure(self.ksp, err)) from None
        finally:
            options.delValue(ordering)
        # PETSc records a factorisation MUMPS refused (out of memory, singular) as the PC's failure, not
        # an error: the solve would only say it diverged. MUMPS's INFOG(1) says what happened.
        if mumps_failure.failed(self.ksp):
            raise ComputationError(_factor_failure(self.ksp, None))
        self.factorisations += 1
        self._norm = self.M.norm(PETSc.NormType.INFINITY)
        self._factored = low if self.owns_forces else True
        self._solve(self.rhs, self.x)
        return self.x.getArray(readonly=True).copy()

    def _set_lower(self, low) -> None:
        """The lower rows' values (last rank's); collective (assembly)."""
        if self.owns_forces:
            P = self._lower_pattern
            for i in range(self.m):
                a, z = P.indptr[i], P.indptr[i + 1]
                self.M.setValues(self.n_global + i, P.indices[a:z], low[a:z], PETSc.InsertMode.INSERT_VALUES)
        self.M.assemble()

    def _solve(self, rhs: PETSc.Vec, out: PETSc.Vec) -> None:
        self.ksp.solve(rhs, out)
        if self.ksp.getConvergedReason() < 0:
            raise ComputationError("contact: the saddle-point solve of a state set failed")

    def _updated(self, low):
        """The set's solution through the factorisation kept, where the set
        differs from the factorised one in few rows; None where it must be
        factorised. M = F + E^T D (E: the r changed rows, D: their change),
        M^-1 b = F^-1 (b - E^T c) with c = (I + D Z)^-1 D F^-1 b and
        Z = F^-1 E^T: of Z only the entries at D's columns are needed (D Z),
        computed by MUMPS without a solve of each column. Collective."""
        if self._factored is None or not mumps_inverse.available():
            return None
        changed, diff = None, None
        if self.owns_forces:
            diff = low - self._factored
            changed = np.flatnonzero(np.add.reduceat(np.abs(diff), self._lower_pattern.indptr[:-1]) > 0.0) \
                if len(diff) else np.zeros(0, np.int64)
        changed = self.comm.bcast(changed, root=self.comm.size - 1)
        if len(changed) > REUSE_ROWS:
            return None
        D, used, columns = None, None, None
        if self.owns_forces and len(changed):
            D = self._difference(diff, changed)
            used = np.unique(D.indices)               # D's columns, among the gathered ones
            columns = self._cols[used]                # their global indices
        columns = self.comm.bcast(columns, root=self.comm.size - 1)
        if len(changed) and len(changed) * len(columns) > REUSE_ENTRIES:
            return None
        y = self.x
        self._solve(self.rhs, y)
        if not len(changed):
            return y.getArray(readonly=True).copy()
        yc = self._at_columns(y)
        W = mumps_inverse.inverse_entries(self.ksp.getPC().getFactorMatrix(), columns, self.n_global + changed,
                                          self.comm)   # Z at D's columns, on rank 0
        if self.comm.size > 1:
            W = self.comm.bcast(W, root=0)
        c = None
        if self.owns_forces and W is not None:
            C = np.eye(len(changed)) + D[:, used] @ W
            if np.linalg.cond(C) < UPDATE_CONDITION:
                c = np.linalg.solve(C, D @ yc)
        c = self.comm.bcast(c, root=self.comm.size - 1)
        if c is None:
            return None
        e = self.rhs.duplicate()
        self.rhs.copy(e)
        if self.owns_forces:
            e.getArray()[self.n_owned + changed] -= c
        self._solve(e, y)
        x = y.getArray(readonly=True).copy()
        ok = self._residual_ok(x, diff, changed, e)
        e.destroy()
        if not ok:
            return None
        self.updates += 1
        self.entries += len(changed) * len(columns)
        return x

    def _block_solve(self, rhs: np.ndarray) -> list:
        """F^-1 of k right-hand sides at once (this rank's rows, (n_local, k)):
        MUMPS solves them together (40 cost as much as 6 single solves on
        1.1M DOFs); a PETSc Vec of each solution, collective."""
        N, k = self.x.getSize(), rhs.shape[1]
        n_local = self.x.getLocalSize()
        B = PETSc.Mat().createDense(((n_local, N), (None, k)), comm=self.comm)
        B.setUp()
        B.getDenseArray()[:] = rhs
        B.assemble()
        X = PETSc.Mat().createDense(((n_local, N), (None, k)), comm=self.comm)
        X.setUp()
        X.assemble()
        self.ksp.getPC().getFactorMatrix().matSolve(B, X)
        out = []
        for c in range(k):
            column = self.x.duplicate()
            X.getColumnVector(c, column)
            out.append(column)
        for obj in (B, X):
            obj.destroy()
        return out

    def respond(self, eq, slip, sign, f, b0_cohesive, target, b: PETSc.Vec, y) -> tuple[np.ndarray, np.ndarray]:
        """(jump0_y, S_yy): the jumps of the rows y (bool (m,)) and their
        response to forces on them, with every other row in its state (the
        arguments as solve_set's) and the rows y free (open): the pair
        problem of the rows y alone (contact.by_sets._cycling_rows). One
        factorisation of that set and one block solve of |y| loads. Collective."""
        rows = np.flatnonzero(y)
        # that set factorised itself (not updated): the loads' block solve goes through its factors
        u0, _ = self._parts(self._factorised(self._prepare(eq & ~y, slip & ~y, sign, f, b0_cohesive, target, b)))
        rhs = np.zeros((self.x.getLocalSize(), len(rows)))
        rhs[:self.n_owned] = self.B_free[:, rows].toarray()   # a unit force on each row: B's column
        S = np.zeros((len(rows), len(rows)))
        for c, column in enumerate(self._block_solve(rhs)):
            S[:, c] = self.jumps(column.getArray(readonly=True)[:self.n_owned])[rows]
            column.destroy()
        return self.jumps(u0)[rows], S


    def _difference(self, diff, changed) -> sparse.csr_matrix:
        """D (r, columns gathered): the changed rows' change, on the gathered columns (last rank)."""
        P = self._lower_pattern
        counts = np.diff(P.indptr)[changed]
        take = np.concatenate([np.arange(P.indptr[j], P.indptr[j + 1]) for j in changed])
        row = np.repeat(np.arange(len(changed)), counts)
        return sparse.csr_matrix((diff[take], (row, self._pos[take])), shape=(len(changed), len(self._cols)))

    def _residual_ok(self, x, diff, changed, work: PETSc.Vec) -> bool:
        """|M x - b| within UPDATE_RESIDUAL of a direct solve's scale: M x = F x + E^T (D x). Collective."""
        xv = self.x
        xv.getArray()[:] = x
        xv.assemble()
        self.M.mult(xv, work)   # M still holds F's values: only the factorised set's lower rows are set
        r = work.getArray()
        r -= self.rhs.getArray(readonly=True)
        xc = self._at_columns(xv)
        if self.owns_forces:
            r[self.n_owned + changed] += self._difference(diff, changed) @ xc
        res = self.comm.allreduce(float(np.max(np.abs(r), initial=0.0)), op=MPI.MAX)
        scale = self._norm * xv.norm(PETSc.NormType.INFINITY) + self.rhs.norm(PETSc.NormType.INFINITY)
        return res <= UPDATE_RESIDUAL * scale

    def destroy(self) -> None:
        for obj in (self.ksp, self.M, self.x, self.rhs, self._seq, self._scatter):
            obj.destroy()


def _factor_failure(ksp, err) -> str:
    """What stopped MUMPS's factorisation of a set (fem.mumps_failure)."""
    return mumps_failure.describe(ksp, err, "the saddle-point system of the pair rows",
                                  singular="the saddle-point system of a state set is singular: its closed "
                                           "pairs leave a motion free", prefix="contact: ")


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
