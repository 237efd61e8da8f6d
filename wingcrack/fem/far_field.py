"""The far field's factorisation, condensed on its interface and kept across meshes.

An epoch mesh marks the cells outside the remeshed patch (CrackMesh.far).
Its dofs split into I, those of nodes touched by far cells only (no crack
pair node, no tip node), and the rest R; Gamma are the nodes of R that
share a cell with an I node. The far block A_far = K[I u Gamma, I u Gamma]
is factorised once (MUMPS Cholesky) with its Schur complement on Gamma,

    S' = K_GG - K_GI K_II^-1 K_IG,   so   W = K_GG - S' = K_GI K_II^-1 K_IG.

A later mesh whose far cells are the epoch's, bitwise, has the same K_II and
K_IG (the same cells, material and Dirichlet dofs), so its K u = b needs
only the reduced matrix A_R = K[R, R] - W (W on the Gamma positions), the
Schur complement of K on R:

    z = A_far^-1 [b_I; 0]                  (K_GI K_II^-1 b_I = -S' z_G)
    A_R u_R = b_R + S' z_G (on Gamma)
    [x; y] = A_far^-1 [b_I; S' (u_G - z_G)],   u_I = x  (and y = u_G).

z depends on b_I alone, which is b0 + lambda b1 in the far field for every
load factor lambda and every mesh of the epoch: it is kept and recombined
(FarField.load_response), so a solve costs one far solve (the last) besides
the reduced one, as a plain solve costs one solve of the whole K. That last
one, u_I from u_G, waits for a reader of u on I (ElasticProblem.expand):
the critical-load search's trials and the pair forces' responses read u
on R only, so a step's solves cost the reduced ones and one far solve for
its files.

With the contact pair dofs P in R, (K^-1)_PP = (A_R^-1)_PP: MUMPS returns the
Schur complement of A_R on P, as the full factorisation does of K.
One process only, like the Schur path (PETSc 3.18 offers MUMPS Schur
complements on one process).
"""
from __future__ import annotations

import time

import numpy as np
from petsc4py import PETSc
from scipy import sparse

from ..errors import ComputationError
from . import elasticity, schur
from .solution_span import SolutionSpan

#: the far interior must hold at least this share of the dofs: below it the
#: reduced matrix is about as large as the whole, while every solve still
#: goes through the far factor twice
MIN_SHARE = 0.5
#: A_far^-1 [b_I; 0] of this many earlier right-hand sides is kept: the far
#: field's load is b_I = b0 + lambda b1 for every load factor and step, so a
#: third solve finds it in their span and saves one far solve of two
SPAN = 3


def _csr(A: PETSc.Mat) -> sparse.csr_matrix:
    indptr, indices, values = A.getValuesCSR()
    return sparse.csr_matrix((values, indices, indptr), shape=A.getSize())


def _dense_block(W: np.ndarray, g: np.ndarray, n: int) -> sparse.csr_matrix:
    """The (n, n) CSR matrix with the dense W on rows and columns g (distinct
    positions), its indices sorted."""
    order = np.argsort(g)
    rows = g[order]
    k = len(g)
    indptr = np.zeros(n + 1, dtype=np.int64)
    indptr[rows + 1] = k
    block = sparse.csr_matrix((W[np.ix_(order, order)].ravel(), np.tile(rows, k), np.cumsum(indptr)), shape=(n, n))
    block.has_canonical_format = True
    return block


def _aij_of(M: sparse.csr_matrix) -> PETSc.Mat:
    """The SPD PETSc matrix on M's arrays (made canonical CSR: sorted, no
    duplicates, a check where they are already; the Mat keeps the arrays,
    so no copy row by row)."""
    M.sum_duplicates()
    it = PETSc.IntType
    A = PETSc.Mat().createAIJWithArrays(size=M.shape, csr=(M.indptr.astype(it), M.indices.astype(it), M.data),
                                        comm=PETSc.COMM_SELF)
    A.assemble()
    A.setOption(PETSc.Mat.Option.SPD, True)
    return A


def _cholesky_solver(A: PETSc.Mat) -> PETSc.KSP:
    ksp = PETSc.KSP().create(PETSc.COMM_SELF)
    ksp.setOperators(A)
    ksp.setType("preonly")
    pc = ksp.getPC()
    pc.setType("cholesky")
    pc.setFactorSolverType("mumps")
    return ksp


def _solve(ksp: PETSc.KSP, rhs: PETSc.Vec, out: PETSc.Vec) -> None:
    ksp.solve(rhs, out)
    reason = ksp.getConvergedReason()
    if reason < 0:
        raise ComputationError(f"linear solve failed (PETSc reason {reason})")


def _dofs(fm, nodes: np.ndarray) -> np.ndarray:
    """Scalar dofs [2b, 2b + 1] of each CrackMesh node in turn."""
    found, blk = fm.block_dofs(nodes)
    if not np.all(found):
        raise RuntimeError("a CrackMesh node has no dof (a bug: the mesh and its FEMesh differ)")
    return np.stack([2 * blk, 2 * blk + 1], axis=1).ravel().astype(np.int64)


def _by_dof(fm, nodes: np.ndarray) -> np.ndarray:
    """`nodes` in the order of their block dofs."""
    return nodes[np.argsort(fm.block_dofs(nodes)[1], kind="stable")]


def _fixed(problem) -> np.ndarray:
    """(num dofs,) bool: the Dirichlet dofs of the problem."""
    fixed = np.zeros(problem.fm.num_dofs, dtype=bool)
    for bc in problem.bcs:
        fixed[np.asarray(bc.dof_indices()[0])] = True
    return fixed


def _material(problem) -> tuple:
    """What K's entries on the same cells depend on besides their nodes: the
    Lame constants (the run's material, plane stress or strain)."""
    return float(problem.lame_lambda.value), float(problem.lame_mu.value)


def _avoided(cm) -> np.ndarray:
    """CrackMesh nodes that never go into I: the crack pairs' and the tips'."""
    tips = [np.r_[t.node, t.upper, t.lower] for t in cm.tips]
    return np.unique(np.concatenate([np.asarray(cm.pairs, np.int64).ravel()] + [np.asarray(t, np.int64) for t in tips]))


#: odd 64-bit constants of the node hash (splitmix64's)
_MIX = (np.uint64(0x9E3779B97F4A7C15), np.uint64(0xBF58476D1CE4E5B9), np.uint64(0x94D049BB133111EB))


def _mix(z: np.ndarray) -> np.ndarray:
    """splitmix64's finaliser (a bijection of uint64 that spreads every bit)."""
    z = (z ^ (z >> np.uint64(30))) * _MIX[1]
    z = (z ^ (z >> np.uint64(27))) * _MIX[2]
    return z ^ (z >> np.uint64(31))


def _node_hashes(x: np.ndarray) -> np.ndarray:
    """(n,) uint64: a hash of each node's coordinate bits (equal places,
    equal hashes; x and y mixed apart, so that mirrored places, whose bits
    differ in the signs only, do not collide)."""
    bits = np.ascontiguousarray(x, dtype=np.float64).view(np.uint64).reshape(-1, 2)
    with np.errstate(over="ignore"):
        return _mix(_mix(bits[:, 0] + _MIX[0]) + bits[:, 1])


def cell_keys(x: np.ndarray, cells: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(keys (m,) uint64, nodes (m, 6)): each cell's key, the sum of its
    nodes' hashes (_node_hashes: the same for the same six places in any
    order), and its nodes ordered by their hashes. Equal places give equal
    keys and the nodes in the same order; equal keys need not be equal
    places (a hash collision): a match by key is verified on the
    coordinates (FarField.node_map). A cell's six nodes never share a place;
    the two copies of a crack node do, but lie in different cells."""
    cells = np.asarray(cells, dtype=np.int64)
    h = _node_hashes(x)[cells]
    with np.errstate(over="ignore"):
        keys = h.sum(axis=1, dtype=np.uint64)
    nodes = np.take_along_axis(cells, np.argsort(h, axis=1), axis=1)
    return keys, nodes


class FarField:
    """The far field of one epoch: A_far's factor with its Schur complement
    S' on Gamma, and what a later mesh is matched against. Owns its PETSc
    objects (they outlive the epoch's ElasticProblem); destroy() frees them."""

    def __init__(self):
        raise TypeError("use FarField.start(problem, cm)")

    @classmethod
    def start(cls, problem, cm) -> FarField | None:
        """The far field of `cm` (with cm.far) from its assembled, not yet
        factorised `problem`; None where it cannot help: no far cells
        marked, several processes, or an interior of fewer than half the
        dofs. self.seconds: the time of its parts."""
        if cm.far is None or not schur.available(problem.fm.mesh.comm):
            return None
        t0 = time.perf_counter()
        far = np.asarray(cm.far, dtype=bool)
        cells = np.asarray(cm.cells, dtype=np.int64)
        n = len(cm.x)
        interior = np.zeros(n, dtype=bool)
        interior[cells[far].ravel()] = True
        interior[cells[~far].ravel()] = False
        interior[_avoided(cm)] = False
        if 2 * np.count_nonzero(interior) < MIN_SHARE * problem.fm.num_dofs:
            return None
        touching = interior[cells].any(axis=1)
        gamma = np.zeros(n, dtype=bool)
        gamma[cells[touching].ravel()] = True
        gamma &= ~interior

        self = object.__new__(cls)
        fm = problem.fm
        self.interior = interior
        # in the order of their dofs, so that A_far is K's submatrix on sorted dofs
        self.I_nodes, self.G_nodes = (_by_dof(fm, np.flatnonzero(m)) for m in (interior, gamma))
        x = np.ascontiguousarray(cm.x, dtype=np.float64)
        keys, nodes = cell_keys(x, cells[touching])
        self._key_order = np.argsort(keys)
        self._keys = keys[self._key_order]
        self._cell_nodes = nodes[self._key_order]
        self._x_bits = x.view(np.int64).reshape(-1, 2).copy()   # what a match is verified on
        self.num_nodes = n
        I, G = _dofs(fm, self.I_nodes), _dofs(fm, self.G_nodes)
        self.nI, self.nG = len(I), len(G)
        both = np.sort(np.r_[I, G])
        # positions in A_far of I's and Gamma's dofs, both ascending
        self._pI, self._pG = np.searchsorted(both, I), np.searchsorted(both, G)
        t1 = time.perf_counter()

        sub = PETSc.IS().createGeneral(both.astype(PETSc.IntType), comm=PETSc.COMM_SELF)
        A = problem.A.createSubMatrix(sub, sub)
        sub.destroy()
        A.setOption(PETSc.Mat.Option.SPD, True)
        sub = PETSc.IS().createGeneral(G.astype(PETSc.IntType), comm=PETSc.COMM_SELF)
        block = problem.A.createSubMatrix(sub, sub)
        sub.destroy()
        K_GG = _csr(block).toarray()
        block.destroy()
        self._fixed = _fixed(problem)[np.r_[I, G]]
        self._material = _material(problem)
        t2 = time.perf_counter()

        ksp = _cholesky_solver(A)
        try:
            elasticity.cholesky(ksp, self._pG)
            # the copy before the first solve factorises S' in place (see ElasticProblem.schur_complement)
            self.S = schur.schur_complement(ksp.getPC().getFactorMatrix(), self.nG)
            # the factor alone solves (MatSolve): A_far, as large as most of K, is not kept beside it
            self.F = ksp.getPC().getFactorMatrix()
            self._rhs, self._x = A.createVecs()
        finally:
            ksp.destroy()
            A.destroy()
        self.W = K_GG - self.S
        self.W = 0.5 * (self.W + self.W.T)
        self._responses = SolutionSpan(self.nI, self.nI + self.nG, SPAN)   # earlier b_I and A_far^-1 [b_I; 0]
        t3 = time.perf_counter()
        self.seconds = {"select": t1 - t0, "extract": t2 - t1, "factorise": t3 - t2}
        return self

    @property
    def num_dofs(self) -> tuple[int, int]:
        """(|I|, |Gamma|) in scalar dofs."""
        return self.nI, self.nG

    def destroy(self) -> None:
        self._matched = None
        for obj in (self.F, self._rhs, self._x):
            obj.destroy()

    # -- matching a later mesh ----------------------------------------------
    def node_map(self, cm) -> tuple[np.ndarray, np.ndarray] | None:
        """(I nodes, Gamma nodes) of `cm` in the epoch's order, or None when
        cm's far field is not the epoch's: every epoch cell touching I must
        be among cm's far cells (cm.far; all cells where None) bitwise, no
        other cell of cm may touch the I nodes, the node map from the
        matched cells must be one to one, and no crack pair or tip node of
        cm may fall in I."""
        cells = np.asarray(cm.cells, dtype=np.int64)
        x = np.ascontiguousarray(cm.x, dtype=np.float64)
        candidates = np.flatnonzero(cm.far) if cm.far is not None else np.arange(len(cells))
        if len(candidates) < len(self._keys):
            return None
        keys, nodes = cell_keys(x, cells[candidates])
        pos = np.minimum(np.searchsorted(self._keys, keys), len(self._keys) - 1)
        hit = self._keys[pos] == keys
        epoch = pos[hit]
        if len(epoch) != len(self._keys) or np.bincount(epoch, minlength=len(self._keys)).max() > 1:
            return None
        mine, theirs = nodes[hit].ravel(), self._cell_nodes[epoch].ravel()
        to_epoch = np.full(len(x), -1, dtype=np.int64)
        to_epoch[mine] = theirs
        if np.any(to_epoch[mine] != theirs):   # a node of two matched cells mapped two ways
            return None
        mapped = np.flatnonzero(to_epoch >= 0)
        if np.bincount(to_epoch[mapped], minlength=self.num_nodes).max() > 1:
            return None
        # the keys' match verified: each node bitwise at its epoch node's place
        if not np.array_equal(x.view(np.int64).reshape(-1, 2)[mapped], self._x_bits[to_epoch[mapped]]):
            return None
        in_I = np.zeros(len(x), dtype=bool)
        in_I[mapped] = self.interior[to_epoch[mapped]]
        other = np.ones(len(cells), dtype=bool)
        other[candidates[hit]] = False
        if in_I[cells[other]].any() or in_I[_avoided(cm)].any():
            return None
        from_epoch = np.full(self.num_nodes, -1, dtype=np.int64)
        from_epoch[to_epoch[mapped]] = mapped
        return from_epoch[self.I_nodes], from_epoch[self.G_nodes]

    def matches(self, cm) -> bool:
        """Whether cm's far field is the epoch's (see node_map). The map is
        kept for the factorisation of the same mesh that usually follows."""
        self._matched = (cm, self.node_map(cm))
        return self._matched[1] is not None

    def interior_of(self, cm) -> np.ndarray | None:
        """(len(cm.x),) bool: the nodes of cm in this far field's interior I,
        or None when cm's far field is not the epoch's (see node_map): what
        ElasticProblem(far_interior=...) need not assemble K's rows of."""
        found = self._node_map_of(cm)
        if found is None:
            return None
        inside = np.zeros(len(cm.x), dtype=bool)
        inside[found[0]] = True
        return inside

    def _node_map_of(self, cm):
        """node_map(cm), the one matches(cm) found when it was asked of this very mesh."""
        last = getattr(self, "_matched", None)
        if last is not None and last[0] is cm:
            return last[1]
        return self.node_map(cm)

    # -- solves -------------------------------------------------------------
    def solve(self, top: np.ndarray, bottom: np.ndarray) -> np.ndarray:
        """A_far^-1 [top; bottom] (on I, then Gamma)."""
        r = self._rhs.getArray()
        r[self._pI] = top
        r[self._pG] = bottom
        self.F.solve(self._rhs, self._x)
        x = self._x.getArray()
        return np.r_[x[self._pI], x[self._pG]]

    def load_response(self, b_I: np.ndarray) -> np.ndarray:
        """A_far^-1 [b_I; 0] (on I, then Gamma): a combination of earlier
        ones where b_I lies in the span of their right-hand sides, else a
        solve (then kept)."""
        if not b_I.any():   # the pair forces' right-hand sides (PairOperator.add_forces)
            return np.zeros(self.nI + self.nG)
        z = self._responses.find(b_I)
        if z is None:
            z = self.solve(b_I, np.zeros(self.nG))
            self._responses.add(b_I, z)
        return z

    @property
    def reused_responses(self) -> int:
        """Load responses answered from the kept ones."""
        return self._responses.hits

    def condense(self, problem, schur_dofs=None) -> Condensed | None:
        """The reduced factorisation of `problem` (of problem.cm) on this far
        field, or None when its far field is not the epoch's. Records the
        seconds of its parts in problem.far_seconds."""
        t0 = time.perf_counter()
        found = self._node_map_of(problem.cm)
        seconds = problem.far_seconds
        seconds["match"] = time.perf_counter() - t0
        if found is None:
            return None
        fm = problem.fm
        I, G = _dofs(fm, found[0]), _dofs(fm, found[1])
        n = fm.num_dofs
        fixed = _fixed(problem)
        # the same cells, bitwise (node_map), of the same material with the same Dirichlet dofs: the same K_II, K_IG
        if np.any(fixed[np.r_[I, G]] != self._fixed) or _material(problem) != self._material:
            return None
        keep = np.ones(n, dtype=bool)
        keep[I] = False
        R = np.flatnonzero(keep)
        position = np.full(n, -1, dtype=np.int64)
        position[R] = np.arange(len(R))
        g = position[G]
        P = None
        if schur_dofs is not None and len(schur_dofs):
            P = position[np.asarray(schur_dofs, dtype=np.int64)]
            if np.any(P < 0):
                return None
        t1 = time.perf_counter()

        sub = PETSc.IS().createGeneral(R.astype(PETSc.IntType), comm=PETSc.COMM_SELF)
        K_RR = problem.A.createSubMatrix(sub, sub)
        sub.destroy()
        M = _csr(K_RR)
        K_RR.destroy()
        M = M - _dense_block(self.W, g, M.shape[0])
        A_R = _aij_of(M)
        t2 = time.perf_counter()

        seconds["reduce"] = t2 - t1
        ksp = _cholesky_solver(A_R)
        try:
            elasticity.cholesky(ksp, P)
        except BaseException:
            ksp.destroy()
            A_R.destroy()
            raise
        seconds["factorise"] = time.perf_counter() - t2
        return Condensed(self, A_R, ksp, I, R, g)


class Condensed:
    """One mesh's reduced factorisation on a FarField (valid while the far
    field lives)."""

    def __init__(self, far: FarField, A: PETSc.Mat, ksp: PETSc.KSP, I, R, g):
        self.far, self.A, self.ksp = far, A, ksp
        self.I, self.R, self.g = I, R, g
        self._rhs, self._x = A.createVecs()
        self.y = None   # A_far^-1's Gamma part in the last solve: u_G (a check)
        self._last = None   # (b_I, A_far^-1 [b_I; 0]) of the last solve

    def solve(self, rhs: PETSc.Vec, out: PETSc.Vec, expand: bool = True) -> None:
        """out = K^-1 rhs (vectors in the problem's dof layout); with
        expand=False on R only (out's I entries are left as they were: see
        expand)."""
        far, g = self.far, self.g
        b = rhs.getArray(readonly=True)
        b_I = b[self.I]
        z = far.load_response(b_I)
        self._last = (b_I, z)
        z_G = z[far.nI:]
        r = self._rhs.getArray()
        r[:] = b[self.R]
        r[g] += far.S @ z_G
        _solve(self.ksp, self._rhs, self._x)
        u = out.getArray()
        u[self.R] = self._x.getArray()
        if expand:
            self._expand(u, z)

    def expand(self, u: np.ndarray, b_I: np.ndarray) -> None:
        """u[I] of the solution of K u = b from its part on R, u[R], and
        b's on I, b_I: the far field's interior is determined by its load and
        u on Gamma,

            [x; y] = A_far^-1 [b_I; S' (u_G - z_G)],   u_I = x   (z = A_far^-1 [b_I; 0]),

        linear in (b_I, u_G): so u[R] may be any combination of solutions
        (earlier ones, the pair forces' responses, whose load on I is 0)
        whose loads on I add up to b_I."""
        last = self._last
        same = last is not None and np.array_equal(last[0], b_I)   # the last solve's load: its z as it was
        self._expand(u, last[1] if same else self.far.load_response(b_I))

    def _expand(self, u: np.ndarray, z: np.ndarray) -> None:
        far = self.far
        # [x; y] = z + A_far^-1 [0; S' (u_G - z_G)]
        xy = z + far.solve(np.zeros(far.nI), far.S @ (u[self.R[self.g]] - z[far.nI:]))
        u[self.I] = xy[:far.nI]
        self.y = xy[far.nI:]

    def destroy(self) -> None:
        for obj in (self.ksp, self.A, self._rhs, self._x):
            obj.destroy()
