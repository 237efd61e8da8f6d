"""P2 elasticity on the cracked mesh: forms, boundary conditions, MUMPS solve.

Initial-stress formulation: the total stress is sigma0 + C:eps(u), where
sigma0 is the constant in-situ stress and u the displacement from the in-situ
state on. The outer boundary carries sigma0.n (plus any prescribed traction),
so only the crack faces feel -sigma0.n: they are traction-free in total.

Everything that changes between solves (load factor, prescribed values) lives
in a fem.Constant, so each form compiles once. The matrix does not depend on
the load: it is factorised once per mesh (Cholesky, MUMPS) and reused;
where the mesh keeps an earlier mesh's far field, only the matrix condensed
on the rest is (fem.far_field).
"""
from __future__ import annotations

import warnings
from functools import cached_property

import numpy as np
import ufl
from dolfinx import fem
from dolfinx.fem import petsc as fpetsc
from petsc4py import PETSc

from ..errors import ComputationError
from ..loads import Loads
from ..material import lame
from . import compiled, schur
from .mesh import cell_tags
from .mumps_failure import MEMORY, describe, failed
from .nodal import nodal_displacements
from .nodal_fields import nodal_fields
from .solution_span import SolutionSpan


def strain(u):
    return ufl.sym(ufl.grad(u))


#: right-hand sides (with their solutions) ElasticProblem.solve keeps: b is
#: affine in the load factor, so two span every other
SPAN = 2
#: MUMPS CNTL(3): pivots below this times ||K|| count as null (see factorize)
NULL_PIVOT = 1e-12
#: below this many DOFs the factorisation orders K by approximate minimum
#: fill (MUMPS ICNTL(7) = 2); above it MUMPS's own choice (PORD in this
#: build, which has neither METIS nor SCOTCH), whose nested dissection fills
#: less but whose analysis costs as much as the factorisation itself on
#: the smaller meshes. With a Schur complement MUMPS orders by AMD whatever
#: ICNTL(7) asks.
AMF_BELOW = 200_000
_OPTIONS_PREFIX = "wingcrack_elastic_"


class ElasticProblem:
    """Assemble once per mesh, factorise once, solve for any load factor."""

    def __init__(self, fm, E: float, nu: float, plane: str, loads: Loads, cm=None, far_interior=None):
        """far_interior: (len(cm.x),) bool, the CrackMesh nodes of the far
        interior of a far field this mesh keeps (FarField.interior_of(cm)):
        the condensed factorisation reads no row of K on them, so K is
        assembled only on the cells with another node (self.partial); the
        whole K is assembled when a factorisation needs it after all."""
        self.fm = fm
        self.cm = cm   # the CrackMesh of fm: needed only to reuse a far field (factorize)
        msh, V = fm.mesh, fm.V
        lame_lambda, lame_mu = lame(E, nu, plane)
        self.lame_lambda = fem.Constant(msh, PETSc.ScalarType(lame_lambda))
        self.lame_mu = fem.Constant(msh, PETSc.ScalarType(lame_mu))
        self.load_factor = fem.Constant(msh, PETSc.ScalarType(1.0))
        self.sigma0 = fem.Constant(msh, np.asarray(loads.sigma0, dtype=PETSc.ScalarType))
        self.body = fem.Constant(msh, np.asarray(loads.body_force, dtype=PETSc.ScalarType))
        self.loads = loads

        u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
        ds = ufl.Measure("ds", domain=msh, subdomain_data=fm.facet_tags)
        dx = ufl.Measure("dx", domain=msh)
        # dx(1) on every cell here, on fewer after the far field (_assemble_part): one kernel for both
        tdim = msh.topology.dim
        num_cells = msh.topology.index_map(tdim).size_local
        every = cell_tags(msh, np.arange(num_cells, dtype=np.int32))
        dx1 = ufl.Measure("dx", domain=msh, subdomain_data=every)(1)
        self._stiffness = compiled.Prepared(ufl.inner(self.stress(u, total=False), strain(v)) * dx1,
                                            ("elasticity.stiffness",))
        self.a = self._stiffness.form()

        L = ufl.inner(self.body, v) * dx - ufl.inner(self.sigma0, strain(v)) * dx
        n = ufl.FacetNormal(msh)
        if loads.outer_tags:
            L += ufl.inner(ufl.dot(self.sigma0, n), v) * ds(tuple(int(t) for t in loads.outer_tags))
        self._traction_values = []
        for tag, tx, ty in loads.tractions:
            c = fem.Constant(msh, np.array([tx, ty], dtype=PETSc.ScalarType))
            self._traction_values.append(c)
            L += self.load_factor * ufl.inner(c, v) * ds(int(tag))
        # the recipe names the tags in the order their traction constants enter: the layout lists the
        # integrals by tag, not which constant each takes (tractions on other edges in another order
        # shared one compiled form and took each other's values)
        self.L = compiled.form(L, ("elasticity.load", tuple(int(t) for t, _, _ in loads.tractions),
                                   tuple(int(t) for t in loads.outer_tags)))

        self.bcs, self._bc_values = self._dirichlet(loads)
        self._point_forces = self._locate_point_forces(loads.point_forces)
        self._face_dofs, self._face_values = self._locate_face_forces(loads.face_forces)
        self._fixed_dofs, self._fixed_values = self._locate_face_forces(loads.fixed_face_forces)

        self.partial = far_interior is not None
        self.A = self._assemble_part(far_interior) if self.partial else self._assemble_whole()
        self.solver = PETSc.KSP().create(msh.comm)
        self.solver.setOperators(self.A)
        self.solver.setType("preonly")
        pc = self.solver.getPC()
        pc.setType("cholesky")
        pc.setFactorSolverType("mumps")
        self._factored = False
        self._schur = None
        self._condensed = None    # fem.far_field.Condensed when factorize reused a far field
        self._forget()
        self.schur_dofs = None
        self.reused_far = False
        self.far_seconds = {}
        self.b = fpetsc.create_vector(self.L)
        self.load_factor_solved = 1.0
        self._u = fem.Function(V, name="displacement")
        self._b_I = None        # b of the last solve on the far interior (a condensed solve's: see expand)
        self._deferred = False  # whether u's values there are still to be computed

    # -- the displacement ----------------------------------------------------
    @property
    def u(self) -> fem.Function:
        """The displacement of the last solve, everywhere (expanded on the
        far interior first where a condensed solve left it, see expand)."""
        self.expand()
        return self._u

    @property
    def u_function(self) -> fem.Function:
        """The displacement Function as it is, not expanded: for forms that
        take it as a coefficient before its values are read (their reader
        asks u_at for the dofs it integrates over)."""
        return self._u

    def u_at(self, blocks) -> fem.Function:
        """The displacement Function, valid at least on the block dofs
        `blocks` (local): expanded first only where one lies in the far
        interior. For readers of a few dofs inside a step (the pair jumps,
        the tips' displacements and SIF domains), which lie outside it."""
        if self._deferred:
            blocks = np.asarray(blocks, dtype=np.int64).ravel()
            if self._far_blocks[blocks[blocks >= 0]].any():   # (-1: a node not on this process)
                self.expand()
        return self._u

    def u_on_cells(self, cells) -> fem.Function:
        """u_at the dofs of the local `cells` (a form integrated over them)."""
        if self._deferred:
            dofmap = self.fm.V.dofmap
            self.u_at(dofmap.list.array.reshape(-1, dofmap.cell_dofs(0).size)[np.asarray(cells, dtype=np.int64)])
        return self._u

    def defer(self) -> None:
        """u changed on R by a response whose load on the far interior is 0
        (the pair forces', PairOperator.add_forces): its values there are
        to be computed again (expand). Nothing without a condensation."""
        if self._condensed is not None and self._b_I is not None:
            self._deferred = True

    def expand(self) -> None:
        """Compute u on the far interior, which a solve through the far
        field's condensation leaves for later: the far field's solve that
        does it (as costly as the reduced one) is needed only by readers of
        the whole field, the files above all, which the propagation loop
        writes while the next mesh is made. Every solve of the step gets its
        own u on R only; u's load on I (b_I of the last solve, the pair
        forces' being 0 there) and u on Gamma then give u on I."""
        if not self._deferred:
            return
        self._deferred = False
        u = self._u.vector.getArray()
        self._condensed.expand(u, self._b_I)
        self._u.x.scatter_forward()
        self._require_finite(u)

    @cached_property
    def _far_blocks(self) -> np.ndarray:
        """(local block dofs,) bool: in the far interior of the condensation."""
        imap = self.fm.V.dofmap.index_map
        mask = np.zeros(imap.size_local + imap.num_ghosts, dtype=bool)
        mask[self._condensed.I // 2] = True
        return mask

    @staticmethod
    def _require_finite(values) -> None:
        if not np.all(np.isfinite(values)):
            raise ComputationError("the displacement has NaN/inf: the body is not held (singular system)")

    # -- stiffness ---------------------------------------------------------
    def _assemble_whole(self) -> PETSc.Mat:
        A = fpetsc.assemble_matrix(self.a, bcs=self.bcs)
        A.assemble()
        A.setOption(PETSc.Mat.Option.SPD, True)
        self.num_cells_assembled = self.fm.mesh.topology.index_map(self.fm.mesh.topology.dim).size_local
        return A

    def _assemble_part(self, interior) -> PETSc.Mat:
        """K's entries from the cells with a node outside `interior` (CrackMesh
        nodes): its rows and columns off the interior are K's; those on it
        are partial (zero where no such cell reaches)."""
        fm = self.fm
        found, blk = fm.block_dofs(np.flatnonzero(np.asarray(interior, dtype=bool)))
        inside = np.zeros(fm.V.dofmap.index_map.size_local + fm.V.dofmap.index_map.num_ghosts, dtype=bool)
        inside[blk[found]] = True
        msh = fm.mesh
        tdim = msh.topology.dim
        num_cells = msh.topology.index_map(tdim).size_local
        dofs = fm.V.dofmap.list.array.reshape(-1, fm.V.dofmap.cell_dofs(0).size)[:num_cells]
        cells = np.flatnonzero(~inside[dofs].all(axis=1)).astype(np.int32)
        a = self._stiffness.form(cell=cell_tags(msh, cells))
        A = fpetsc.create_matrix(a)
        # the Dirichlet rows' unit diagonal goes in on the interior too, where no assembled cell made room
        A.setOption(PETSc.Mat.Option.NEW_NONZERO_ALLOCATION_ERR, False)
        fpetsc.assemble_matrix(A, a, bcs=self.bcs)
        A.assemble()
        self.num_cells_assembled = len(cells)
        return A

    def assemble_whole(self) -> None:
        """K assembled on every cell (after a partial assembly, see __init__)."""
        if not self.partial:
            return
        self.A.destroy()
        self.A = self._assemble_whole()
        self.solver.setOperators(self.A)
        self.partial = False

    @property
    def lam(self):
        """The former name of lame_lambda (deprecated)."""
        warnings.warn("ElasticProblem.lam is deprecated: read .lame_lambda", DeprecationWarning, stacklevel=2)
        return self.lame_lambda

    @property
    def mu(self):
        """The former name of lame_mu, the shear modulus (deprecated)."""
        warnings.warn("ElasticProblem.mu is deprecated: read .lame_mu", DeprecationWarning, stacklevel=2)
        return self.lame_mu

    # -- physics -----------------------------------------------------------
    def stress(self, u, total: bool = True):
        """Cauchy stress of displacement u; with total=True add sigma0."""
        eps = strain(u)
        s = self.lame_lambda * ufl.tr(eps) * ufl.Identity(2) + 2.0 * self.lame_mu * eps
        return s + self.sigma0 if total else s

    def strain_energy(self) -> float:
        """U = 1/2 int (C:eps(u)):eps(u) dx of the current displacement (J/m)."""
        if not hasattr(self, "_energy_form"):
            u = self.u
            self._energy_form = compiled.form(0.5 * ufl.inner(self.stress(u, total=False), strain(u)) * ufl.dx,
                                              ("elasticity.energy",))
        self.expand()
        return self.fm.mesh.comm.allreduce(fem.assemble_scalar(self._energy_form))

    def nodal_displacements(self, nodes) -> np.ndarray:
        """(len(nodes), 2) displacement of CrackMesh `nodes` (m), on every rank."""
        return nodal_displacements(self.fm, self.u, nodes)

    def nodal_fields(self, num_nodes: int, tip_nodes=()) -> dict | None:
        """Displacement, total stress and von Mises stress by CrackMesh node
        (fem.nodal_fields; at the `tip_nodes`, where the stress is singular,
        its convention) on rank 0, None elsewhere. Collective."""
        return nodal_fields(self, num_nodes, tip_nodes)

    # -- boundary conditions ----------------------------------------------
    def _node_dofs(self, node: int) -> np.ndarray:
        """Local block dofs of CrackMesh node `node` on this rank (may be empty)."""
        found, blk = self.fm.block_dofs([node])
        return blk[found]

    def _dirichlet(self, loads: Loads):
        V, msh = self.fm.V, self.fm.mesh
        bcs, values = [], []
        for node, comp, value in loads.point_displacements:
            dofs = (2 * self._node_dofs(node) + comp).astype(np.int32)
            c = fem.Constant(msh, PETSc.ScalarType(value))
            values.append((c, value))
            bcs.append(fem.dirichletbc(c, dofs, V.sub(comp)))
        fdim = msh.topology.dim - 1
        for tag, comp, value in loads.boundary_displacements:
            facets = self.fm.facet_tags.find(int(tag))
            dofs = fem.locate_dofs_topological(V.sub(comp), fdim, facets)
            c = fem.Constant(msh, PETSc.ScalarType(value))
            values.append((c, value))
            bcs.append(fem.dirichletbc(c, dofs, V.sub(comp)))
        # the gauge of pieces only contact holds (wingcrack.floating): zero, never scaled; b's
        # entries there are kept before they are set (the pieces' equilibrium needs them)
        imap = self.fm.V.dofmap.index_map
        gauge = []
        for node, comp in loads.gauge:
            blk = self._node_dofs(node)
            dofs = (2 * blk + comp).astype(np.int32)
            bcs.append(fem.dirichletbc(fem.Constant(msh, PETSc.ScalarType(0.0)), dofs, V.sub(comp)))
            gauge += [int(2 * b + comp) for b in blk if b < imap.size_local]
        self.gauge_dofs = np.array(gauge, dtype=np.int64)
        self.b_gauge = np.zeros(len(gauge))
        return bcs, values

    def _locate_face_forces(self, forces):
        """(owned local scalar dofs, values) of the pressure's nodal forces
        (n_nodes, 2) at factor 1 (on the owning rank only)."""
        if forces is None or not np.any(forces):
            return np.zeros(0, np.int64), np.zeros(0)
        nodes = np.flatnonzero(np.any(forces != 0, axis=1))
        found, blk = self.fm.block_dofs(nodes)
        own = found & (blk < self.fm.V.dofmap.index_map.size_local)
        dofs = np.r_[2 * blk[own], 2 * blk[own] + 1].astype(np.int64)
        return dofs, np.r_[forces[nodes[own], 0], forces[nodes[own], 1]]

    def _locate_point_forces(self, forces):
        """(owned local scalar dof, value) for each point-force component."""
        imap = self.fm.V.dofmap.index_map
        out = []
        for node, fx, fy in forces:
            for blk in self._node_dofs(node):
                if blk < imap.size_local:  # add once, on the owning rank
                    out.append((2 * blk, fx))
                    out.append((2 * blk + 1, fy))
        return out

    # -- solve --------------------------------------------------------------
    def factorize(self, schur_dofs=None, far=None):
        """Factorise K (MUMPS Cholesky). With `schur_dofs` (owned local dofs,
        one process), MUMPS also returns the Schur complement on them (see
        fem.schur): the contact pair system then costs no extra solves.
        With `far` (a fem.far_field.FarField) whose far field this mesh
        (self.cm) keeps, only the reduced matrix on the dofs outside the far
        interior is factorised (self.reused_far; the seconds of its parts in
        self.far_seconds); otherwise K whole."""
        self.expand()   # u of the factorisation before stays whole
        self._b_I = None
        self.__dict__.pop("_far_blocks", None)
        self.schur_dofs = None
        self._schur = None
        self.reused_far = False
        self.far_seconds = {}
        self._forget()   # solutions of another factorisation
        if self._condensed is not None:
            self._condensed.destroy()
            self._condensed = None
        with_schur = schur_dofs is not None and len(schur_dofs) > 0 and schur.available(self.fm.mesh.comm)
        if far is not None:
            if self.cm is None:
                raise ValueError("factorize(far=...) needs the problem's CrackMesh: ElasticProblem(..., cm=cm)")
            self._condensed = far.condense(self, schur_dofs if with_schur else None)
            if self._condensed is not None:
                self.reused_far = True
                if with_schur:
                    self.schur_dofs = np.asarray(schur_dofs, dtype=np.int64)
                self._factored = True
                return
        self.assemble_whole()
        cholesky(self.solver, schur_dofs if with_schur else None, self.fm.num_dofs)
        if with_schur:
            self.schur_dofs = np.asarray(schur_dofs, dtype=np.int64)
        self._factored = True

    def _factor(self) -> PETSc.Mat:
        """The MUMPS factor that holds the Schur complement (K's or, with the
        far field reused, the reduced matrix's)."""
        ksp = self._condensed.ksp if self._condensed is not None else self.solver
        return ksp.getPC().getFactorMatrix()

    def destroy(self) -> None:
        """Free the PETSc objects (matrix, MUMPS factors, vectors) now rather
        than whenever Python's collector gets to them."""
        for obj in (self.solver, self.A, self.b, self._u.vector):
            obj.destroy()
        self._deferred, self._b_I = False, None
        if self._condensed is not None:
            self._condensed.destroy()
            self._condensed = None
        self._factored = False

    def schur_complement(self) -> np.ndarray:
        """The dense Schur complement S_c of K on `schur_dofs`. The first
        solve through the factor factorises S_c in place (PETSc condenses and
        expands through it), and MUMPS then hands back that factorisation,
        not S_c: the copy taken before is kept, so that every contact problem
        built on this factorisation (another face law on the same mesh) gets S_c."""
        if self._schur is None:
            self._schur = schur.schur_complement(self._factor(), len(self.schur_dofs))
        return self._schur

    def assemble_rhs(self, load_factor: float) -> PETSc.Vec:
        """The right-hand side at `load_factor`: it multiplies the bc values
        (unless the load mode is "pressure" or "injection") and the fracture
        pressures (with "injection" those of the injected network only)."""
        pressure = self.loads.pressure_factor(load_factor)
        load_factor = self.loads.bc_factor(load_factor)
        self.load_factor.value = load_factor
        for c, value in self._bc_values:
            c.value = load_factor * value
        b = self.b
        with b.localForm() as bl:
            bl.set(0.0)
        fpetsc.assemble_vector(b, self.L)
        if self._point_forces:
            arr = b.getArray()
            for dof, val in self._point_forces:
                arr[dof] += load_factor * val
        if len(self._face_dofs):
            b.getArray()[self._face_dofs] += pressure * self._face_values
        if len(self._fixed_dofs):
            b.getArray()[self._fixed_dofs] += self._fixed_values
        fpetsc.apply_lifting(b, [self.a], bcs=[self.bcs])
        b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        if len(self.gauge_dofs):
            self.b_gauge = b.getArray(readonly=True)[self.gauge_dofs].copy()
        fpetsc.set_bc(b, self.bcs)
        return b

    def solve(self, load_factor: float = 1.0, expand: bool = True) -> fem.Function:
        """The displacement at `load_factor`. The right-hand side is affine
        in the load factor (b0 + lambda b1), so once it lies in the span of
        the last SPAN right-hand sides of this factorisation (the second
        solve of a problem without fixed loads, the third of any) u is
        their solutions' combination, with no solve. expand=False (through a
        far field's condensation): u on the far interior is left to the
        first reader of the whole field (see expand; the Function returned
        is valid off it)."""
        if not self._factored:
            self.factorize()
        b = self.prepare(load_factor)
        if not self._from_span(b):
            self.solve_vector(b, self._u.vector, expand=False)
            self._remember(b)
        self._u.x.scatter_forward()
        c = self._condensed
        if c is None:
            self._require_finite(self._u.x.array)
        else:   # u on the far interior when it is read (expand)
            self._b_I = b.getArray(readonly=True)[c.I].copy()
            self._deferred = True
            self._require_finite(self._u.x.array[c.R])
        return self.u if expand else self._u

    def prepare(self, load_factor: float) -> PETSc.Vec:
        """The right-hand side at `load_factor`, u to be set by the caller
        (the contact's saddle-point route solves K and the contact as one
        system, with no factorisation of K alone)."""
        b = self.assemble_rhs(load_factor)
        self.load_factor_solved = float(load_factor)   # what u belongs to (the face pressure of the SIFs)
        self._deferred, self._b_I = False, None
        return b

    def _from_span(self, b: PETSc.Vec) -> bool:
        """u from the kept solutions where b lies in their span (collective)."""
        u = self._span.find(b.getArray(readonly=True))
        if u is None:
            return False
        self._u.vector.getArray()[:] = u
        return True

    def _remember(self, b: PETSc.Vec) -> None:
        self._span.add(b.getArray(readonly=True), self._u.vector.getArray(readonly=True))

    def _forget(self) -> None:
        n = self.fm.V.dofmap.index_map.size_local * self.fm.V.dofmap.index_map_bs
        self._span = SolutionSpan(n, n, SPAN, self.fm.mesh.comm)

    @property
    def span_solves(self) -> int:
        """Solves of this factorisation answered from the kept solutions."""
        return self._span.hits

    def solve_vector(self, rhs: PETSc.Vec, out: PETSc.Vec, expand: bool = True) -> None:
        """out = K^-1 rhs, vectors in the problem's dof layout, through the
        factorisation factorize made (the whole K or the far field's
        condensation); no ghost update. expand=False: through the
        condensation, out on R only (its far interior entries untouched),
        for a response added to a u whose expansion is deferred (expand)."""
        if not self._factored:
            self.factorize()
        if self._condensed is not None:
            self._condensed.solve(rhs, out, expand)
            return
        self.solver.solve(rhs, out)
        reason = self.solver.getConvergedReason()
        if reason < 0:
            raise ComputationError(f"linear solve failed (PETSc reason {reason})")


def cholesky(solver: PETSc.KSP, schur_dofs=None, num_dofs: int | None = None) -> None:
    """Set up the MUMPS Cholesky factorisation of the KSP `solver` (its
    operator SPD), with the Schur complement on `schur_dofs` (positions in
    that operator, one process) when given; ComputationError where the
    matrix is singular or not positive definite. num_dofs: the operator's
    size, for the ordering (AMF_BELOW)."""
    pc = solver.getPC()
    pc.setFactorSetUpSolverType()
    if schur_dofs is not None:
        schur.set_schur_dofs(pc.getFactorMatrix(), schur_dofs)
        pc.setFactorSetUpSolverType()
    # Null-pivot detection, a second line behind wingcrack.free_pieces (which finds free
    # pieces exactly, before this): it caught a wholly free piece here, but not one held at a
    # single point and free to rotate (no threshold up to 1e-6 flagged that). A pivot below 1e-12 ||K|| is null.
    # A well-posed mesh's smallest pivot is >= lambda_min(K) ~ ||K|| (h_min / L)^2, above
    # 1e-10 ||K|| for L / h_min up to 1e5; round-off pivots of a free piece are ~1e-16 ||K||.
    F = pc.getFactorMatrix()
    F.setMumpsIcntl(24, 1)
    F.setMumpsCntl(3, NULL_PIVOT)
    # PETSc 3.18 sets ICNTL(7) from the options database at the analysis,
    # over a value MatMumpsSetIcntl gave before (MUMPS then takes its own
    # choice): so it goes in the database, under the factor's own prefix,
    # for this factorisation only
    F.setOptionsPrefix(_OPTIONS_PREFIX)
    options = PETSc.Options()
    ordering = None
    if num_dofs is None:
        num_dofs = solver.getOperators()[0].getSize()[0]
    if schur_dofs is None and num_dofs < AMF_BELOW:
        ordering = _OPTIONS_PREFIX + "mat_mumps_icntl_7"
        options[ordering] = 2
    try:
        solver.setUp()
        if failed(solver) and F.getMumpsInfog(1) in MEMORY:   # PETSc records it as the PC's failure only
            raise ComputationError(describe(solver, None, "the stiffness matrix", singular=""))
        # INFOG(28): null pivots; INFOG(12): negative pivots, which an SPD K never has
        null_pivots = F.getMumpsInfog(28) + F.getMumpsInfog(12)
    except PETSc.Error as err:
        if F.getMumpsInfog(1) in MEMORY:
            raise ComputationError(describe(solver, err, "the stiffness matrix", singular="")) from None
        raise ComputationError(f"the factorisation failed (PETSc error {err.ierr}): the stiffness matrix is "
                               "singular or not positive definite; a fracture may cut off a piece of the body "
                               "that no boundary condition holds") from None
    finally:
        if ordering is not None:
            options.delValue(ordering)
    if null_pivots > 0:
        raise ComputationError(f"the stiffness matrix is singular ({null_pivots} null or negative pivots): a fracture cuts off "
                               "a piece of the body that no boundary condition holds")
