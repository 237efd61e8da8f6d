"""Cross-check of the solve: the same open-face problem assembled by scikit-fem.

wingcrack's solve (wingcrack.fem, DOLFINx) and this one share the mesh (the
meshing.CrackMesh arrays, quarter points already moved) and the case, nothing
else: the constitutive law, the forms, the node numbering, the boundary
conditions and the load terms are written again here on scikit-fem's own
assembly, and the system is solved by SciPy (SuperLU) instead of MUMPS. Both
are direct solves of the same discrete system, so the displacements must agree
to round-off; displacement correlation (the same C++ kernel on both
displacements) then checks the SIFs end to end.

The problem (see wingcrack/fem/elasticity.py and wingcrack/loads.py for the
contract): P2 vector Lagrange on the P2 (isoparametric) geometry; total
stress sigma0 + C:eps(u) with u measured from the in-situ state, so at load
factor lambda

    a(u, v) = int C:eps(u) : eps(v) dx
    l(v)    = int rho g . v dx - int sigma0 : eps(v) dx
              + int (sigma0 n) . v ds   (every outer boundary edge, not the crack faces)
              + b int t . v ds          (traction conditions on named boundaries)
              + b point forces at bc-point nodes
              - q sum_f p_f int n . v ds  (both faces of every edge of fracture f)

with displacement conditions (times b) at bc-point nodes and on every node
(vertex and mid-edge) of a named boundary. b = lambda and q = lambda with
`propagation.load = "scale"` (and "fixed"), b = 1 and q = lambda with
"pressure"; sigma0 and gravity are never scaled. p_f is the fluid pressure of
the mesh's fracture f, given per fracture (the case's at step 0; after
growth what the loop holds, connected fractures sharing theirs), on every
edge the mesh labels f (its wings included; at a T or where two fractures
meet tip to tip each side's edges keep their own label), n the outward
normal of the face, so that the pressure pushes both faces apart. The crack
faces are found as scikit-fem's boundary facets that are not outer edges,
each face's fracture from the mesh (crack_fracture). Faces are open: a
case's frictionless, Coulomb or slip faces are solved as open on both sides
(their contact, friction and prescribed slip left out, their pressure kept),
and the report says so.

Quadrature: on quarter-point cells (and curved rim cells) the integrands are
rational, not polynomial, so the discrete systems coincide only with the same
rule. DOLFINx integrates at UFL's estimated degrees, 4 on cells and 8 on the
outer facets (the facet forms carry sigma0.n, whose normal raises the
estimate); scikit-fem's rules of these orders are the same point sets as
basix's (the 6-point Strang-Fix triangle rule, 5-point Gauss-Legendre).
"""
from __future__ import annotations

import time
import warnings
from dataclasses import asdict, dataclass, field, replace

import numpy as np
import wingcrack_kernels as kernels
from scipy.sparse.linalg import MatrixRankWarning, spsolve
from skfem import Basis, BilinearForm, ElementTriP2, ElementVector, FacetBasis, LinearForm, MeshTri2
from skfem.helpers import ddot, div, dot, sym_grad
from skfem.mapping import MappingIsoparametric

from .errors import ComputationError
from .fem.nodal import nodal_displacements
from .step import FAILURES, Timer, failure, solve_initial

#: Quadrature orders: those DOLFINx picks for wingcrack's forms (see above).
CELL_ORDER = 4
FACET_ORDER = 8
#: Stop of the Newton iteration that finds a facet's quadrature points in
#: its cell's reference coordinates (skfem's MappingIsoparametric.invF), on
#: the last step |dX| (reference units). Newton converges quadratically, so
#: the points are then at round-off; skfem's own 1e-12 lies at that floor on
#: the faces next to a tip, where the quarter-point map's Jacobian is small
#: (there the steps stall near 2e-12).
NEWTON_TOL = 1e-10
#: A bc point and its mesh node coincide to this (times the domain length scale).
NODE_TOL = 1e-9
#: Default agreement demanded by `wingcrack crosscheck` (u_rel and sif_rel).
#: Two direct solves of one discrete system differ by round-off, measured at
#: 1e-14 to 1e-12 (displacements and SIFs) on the cases of
#: tests/verification/test_crosscheck.py; a wrong load, quadrature or node map shows as 1e-6
#: or more (cell quadrature of order 6 instead of 4: 1e-6 to 4e-5).
TOLERANCE = 1e-6


@dataclass
class CrossCheck:
    """Agreement of the scikit-fem solve with wingcrack's on one case.

    u_rel = max_nodes |u_skfem - u_wingcrack| / max_nodes |u_wingcrack|
    (Euclidean norm per node); sif_rel = max |K_skfem - K_wingcrack| /
    max |K_wingcrack| over every tip and both modes (displacement
    correlation, Pa m^0.5). tips: per tip fracture, end, KI, KII (wingcrack)
    and KI_skfem, KII_skfem. opened: {fracture, faces} of every fracture
    whose contact or slip faces were solved as open. load_factor: the factor
    both solved at. loads: what both solves apply (one phrase each);
    left_out: one line, what of the case's `sif` neither solve has.
    seconds: wall time per phase (wingcrack's, then skfem_mesh, skfem_solve).
    """
    title: str
    dofs: int
    cells: int
    opened: list
    u_max: float
    u_diff: float
    u_rel: float
    sif_rel: float
    tips: list = field(default_factory=list)
    seconds: dict = field(default_factory=dict)
    load_factor: float = 1.0
    loads: list = field(default_factory=list)
    left_out: str = ""

    def agrees(self, tol: float = TOLERANCE) -> bool:
        return self.u_rel <= tol and self.sif_rel <= tol

    def as_dict(self) -> dict:
        return asdict(self)


def open_faces(case):
    """(case with every fracture's faces "open", [{fracture, faces}] of those that were not)."""
    opened = [{"fracture": i, "faces": f.faces} for i, f in enumerate(case.fractures) if f.faces != "open"]
    fractures = tuple(replace(f, faces="open", slip=0.0) for f in case.fractures)
    return replace(case, fractures=fractures), opened


#: What solving a kind of face open leaves out of it.
LEFT_OUT = {"frictionless": ("contact",), "coulomb": ("contact", "friction"), "slip": ("contact", "prescribed slip")}


def left_out(opened, pressures) -> str:
    """One line: what solving the `opened` fractures ({fracture, faces})
    open leaves out; pressures: the case fractures' (Pa), which are kept.
    A kind of load that only some of them have names those."""
    if not opened:
        return "left out: nothing (every face is open in the case)"
    one = len(opened) == 1

    def which(subset):
        if len(subset) == len(opened):
            return "it" if one else "them"
        return ("fracture " if len(subset) == 1 else "fractures ") + ", ".join(str(o["fracture"]) for o in subset)

    kinds = []
    for k in ("contact", "friction", "prescribed slip"):
        having = [o for o in opened if k in LEFT_OUT[o["faces"]]]
        if having:
            kinds.append(k if len(having) == len(opened) else f"{k} ({which(having)})")
    names = ", ".join(f"fracture {o['fracture']} ({o['faces']})" for o in opened)
    line = f"left out: {names} solved as open: {'its' if one else 'their'} {' and '.join(kinds)}"
    pressed = [o for o in opened if pressures[o["fracture"]]]
    if pressed:
        line += f"; the fluid pressure on {which(pressed)} is applied"
    return line


def factors(case, load_factor: float) -> tuple[float, float]:
    """(what multiplies the bc values, what multiplies the fracture
    pressures) at `load_factor`: with load = "pressure" the factor scales the
    pressures only, otherwise both."""
    lam = float(load_factor)
    return (1.0 if case.propagation.load == "pressure" else lam), lam


def applied_loads(case, load_factor: float, pressures) -> list:
    """What both solves apply, one phrase each (the report's loads line)."""
    b, q = factors(case, load_factor)
    out = []
    if np.any(case.stress.tensor()):
        out.append("in-situ stress")
    if case.material.density and np.any(case.body.gravity):
        out.append("gravity")
    kinds = {"force": "point force", "traction": "traction", "displacement": "displacement condition"}
    count = {}
    for bc in case.bcs:
        count[kinds[bc.kind]] = count.get(kinds[bc.kind], 0) + 1
    out += [f"{n} {k}{'s' if n > 1 else ''} x {b:g}" for k, n in count.items()]
    p = [(i, float(v)) for i, v in enumerate(pressures) if v]
    if p:
        out.append("fluid pressure " + ", ".join(f"{v:g} Pa on fracture {i}" for i, v in p) + f" x {q:g}")
    return out


def lame(E: float, nu: float, plane: str) -> tuple[float, float]:
    """In-plane Lame constants (lambda, mu) in Pa; plane stress: lambda = E nu / (1 - nu^2)."""
    lame_mu = E / (2.0 * (1.0 + nu))
    lame_lambda = E * nu / (1.0 - nu * nu) if plane == "stress" else E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
    return lame_lambda, lame_mu


class SkfemProblem:
    """The open-face problem of `case` on the CrackMesh `cm` at `load_factor`,
    assembled by scikit-fem. pressures: the fluid pressure (Pa, at load
    factor 1) of each fracture the mesh was made from, in mesh order (default
    the case fractures'). `dof[node, c]` is the scikit-fem dof of component c
    (0: x, 1: y) of CrackMesh node `node`."""

    def __init__(self, case, cm, pressures=None, load_factor: float = 1.0):
        self.case, self.cm = case, cm
        self.pressures = np.asarray([f.pressure for f in case.fractures] if pressures is None else pressures,
                                    dtype=np.float64).reshape(-1)
        self.load_factor = float(load_factor)
        x = np.asarray(cm.x, dtype=np.float64)
        cells = np.asarray(cm.cells, dtype=np.int64)
        # gmsh's tri6 order [v0, v1, v2, m01, m12, m20] is the external order
        # MeshTri2 takes (its edges are 01, 12, 02); it renumbers the nodes
        # (vertices first, then one dof per edge), so the map back is built
        # from the element dofs and checked against the node positions.
        self.mesh = MeshTri2(x.T.copy(), cells.T.astype(np.int32))
        self.element = ElementVector(ElementTriP2())
        self.basis = Basis(self.mesh, self.element, intorder=CELL_ORDER)
        dof = np.full((len(x), 2), -1, dtype=np.int64)
        edofs = self.basis.element_dofs  # (12, cells): [n0 x, n0 y, n1 x, ...]
        for i in range(6):
            for c in range(2):
                dof[cells[:, i], c] = edofs[2 * i + c]
        if np.any(dof < 0) or not np.allclose(self.basis.doflocs[:, dof[:, 0]].T, x, rtol=0, atol=1e-12 * _scale(x)):
            raise ComputationError("scikit-fem renumbered the mesh nodes unexpectedly")
        self.dof = dof
        self.ndofs = self.basis.N

        # CrackMesh vertex node -> scikit-fem vertex; edges are found by
        # their sorted vertex pair (crack faces are split, so no two edges
        # share a pair)
        self._vertex = np.full(len(x), -1, dtype=np.int64)
        self._vertex[cells[:, :3].T] = self.mesh.t
        keys = self._edge_keys(self.mesh.facets.T)
        self._facet_order = np.argsort(keys)
        self._facet_keys = keys[self._facet_order]
        self._FacetBasis = FacetBasis
        self._facet_mapping = _facet_mapping(self.mesh)

    # -- mesh lookups -------------------------------------------------------
    def _edge_keys(self, pairs) -> np.ndarray:
        v = np.sort(np.asarray(pairs, dtype=np.int64), axis=1)
        return v[:, 0] * self.mesh.nvertices + v[:, 1]

    def facets(self, edges) -> np.ndarray:
        """scikit-fem facet indices of CrackMesh edges [a, b, mid]."""
        keys = self._edge_keys(self._vertex[np.asarray(edges, dtype=np.int64)[:, :2]])
        pos = np.minimum(np.searchsorted(self._facet_keys, keys), len(self._facet_keys) - 1)
        if not np.array_equal(self._facet_keys[pos], keys):
            raise ComputationError("a boundary edge of the mesh is no scikit-fem facet")
        return self._facet_order[pos]

    def facet_basis(self, edges=None, facets=None):
        facets = self.facets(edges) if facets is None else facets
        try:
            return self._FacetBasis(self.mesh, self.element, mapping=self._facet_mapping, facets=facets,
                                    intorder=FACET_ORDER)
        except Exception as err:   # skfem's own failures (its Newton iteration's) are plain Exceptions
            raise ComputationError(f"scikit-fem's facet quadrature failed: {err}") from None

    def crack_faces(self) -> list:
        """[(fracture, scikit-fem facets)] of both faces of every crack edge:
        the mesh's boundary facets that are no outer edge, every one of them
        (checked), each with the fracture of its CrackMesh edge."""
        cm = self.cm
        outer = self.facets(np.asarray(cm.boundary_edges, dtype=np.int64).reshape(-1, 3))
        faces = np.setdiff1d(self.mesh.boundary_facets(), outer)
        sides = [np.asarray(e, dtype=np.int64).reshape(-1, 3) for e in (cm.crack_edges, cm.crack_edges_minus)]
        fracture = np.asarray(cm.crack_fracture, dtype=np.int64).reshape(-1)
        found = np.concatenate([self.facets(e) for e in sides]) if len(fracture) else np.zeros(0, np.int64)
        if len(np.unique(found)) != len(found) or not np.array_equal(np.sort(found), faces):
            raise ComputationError("the crack faces of the mesh are not the boundary facets inside the domain")
        of = np.tile(fracture, 2)
        return [(int(f), found[of == f]) for f in np.unique(of)]

    def point_node(self, at) -> int:
        """The node of the bc point `at` (the CrackMesh's choice at a crack mouth)."""
        points = np.asarray(self.case.bc_points(), float).reshape(-1, 2)
        node = int(self.cm.point_nodes[int(np.argmin(np.linalg.norm(points - np.asarray(at), axis=1)))])
        if np.linalg.norm(np.asarray(self.cm.x[node]) - np.asarray(at)) > NODE_TOL * self.case.length_scale:
            raise ComputationError(f"bc point {tuple(at)} is not a mesh node")
        return node

    # -- assembly -------------------------------------------------------------
    def assemble(self):
        """(K, f, prescribed dofs, their values), K sparse CSR (N/m^2 per m)."""
        case, cm = self.case, self.cm
        b, q = factors(case, self.load_factor)
        lame_lambda, lame_mu = lame(case.material.E, case.material.nu, case.material.plane)
        sigma0 = np.asarray(case.stress.tensor(), float)[:, :, None, None]
        rho_g = case.material.density * np.asarray(case.body.gravity, float)[:, None, None]

        @BilinearForm
        def stiffness(u, v, w):
            return lame_lambda * div(u) * div(v) + 2.0 * lame_mu * ddot(sym_grad(u), sym_grad(v))

        @LinearForm
        def volume(v, w):
            return dot(rho_g, v) - ddot(sigma0, sym_grad(v))

        @LinearForm
        def insitu_traction(v, w):
            return dot(np.einsum("ij...,j...->i...", sigma0, w.n), v)

        K = stiffness.assemble(self.basis).tocsr()
        f = volume.assemble(self.basis)
        edges = np.asarray(cm.boundary_edges, dtype=np.int64)
        tags = np.asarray(cm.boundary_tags)
        if np.any(sigma0) and len(edges):
            f += insitu_traction.assemble(self.facet_basis(edges))
        if np.any(self.pressures):
            for fracture, facets in self.crack_faces():
                pf = q * float(self.pressures[fracture])
                if pf:   # the face traction -p n_out on both faces
                    f += LinearForm(lambda v, w, pf=pf: -pf * dot(w.n, v)).assemble(self.facet_basis(facets=facets))

        fixed = {}
        for bc in case.bcs:
            comps = [c for c in (0, 1) if bc.components[c]]
            if bc.at is not None:
                node = self.point_node(bc.at)
                if bc.kind == "force":
                    f[self.dof[node]] += b * np.asarray(bc.value, float)
                else:
                    fixed.update({int(self.dof[node, c]): b * float(bc.value[c]) for c in comps})
                continue
            on = edges[tags == int(cm.boundary_names[bc.on])]
            if bc.kind == "traction":
                t = b * np.asarray(bc.value, float)[:, None, None]
                f += LinearForm(lambda v, w, t=t: dot(t, v)).assemble(self.facet_basis(on))
            else:
                nodes = np.unique(on)
                fixed.update({int(d): b * float(bc.value[c]) for c in comps for d in self.dof[nodes, c]})
        D = np.fromiter(fixed.keys(), dtype=np.int64, count=len(fixed))
        values = np.fromiter(fixed.values(), dtype=np.float64, count=len(fixed))
        return K, f, D, values

    def solve(self) -> np.ndarray:
        """(nodes, 2) displacement (m) at every CrackMesh node."""
        K, f, D, values = self.assemble()
        free = np.setdiff1d(np.arange(self.ndofs), D)
        u = np.zeros(self.ndofs)
        u[D] = values
        rhs = f[free] - K[free][:, D] @ values
        with warnings.catch_warnings():
            warnings.simplefilter("error", MatrixRankWarning)
            try:
                u[free] = spsolve(K[free][:, free].tocsc(), rhs)
            except (MatrixRankWarning, RuntimeError) as err:
                raise ComputationError(f"scikit-fem system is singular ({err}): the body is not held") from None
        if not np.all(np.isfinite(u)):
            raise ComputationError("scikit-fem displacement has NaN/inf: the body is not held")
        return u[self.dof]


def correlation_sifs(cm, u: np.ndarray, E: float, nu: float, plane: str):
    """(KI, KII) of every tip of `cm` by displacement correlation on the nodal
    displacement `u` (nodes, 2)."""
    tips = cm.tips
    if not tips:
        return np.zeros(0), np.zeros(0)
    nodes = np.array([[t.upper[0], t.upper[1], t.lower[0], t.lower[1]] for t in tips], dtype=np.int64)
    q = u[nodes]
    KI, KII = kernels.displacement_correlation(
        q[:, 0], q[:, 1], q[:, 2], q[:, 3], np.array([t.ex for t in tips], float),
        np.array([t.ey for t in tips], float), np.array([t.h for t in tips], float),
        E / (2 * (1 + nu)), kernels.kappa(nu, plane))
    return np.atleast_1d(KI), np.atleast_1d(KII)


def crosscheck(case, load_factor: float = 1.0) -> CrossCheck:
    """Solve `case` with open faces by wingcrack and by scikit-fem on the
    same mesh at `load_factor` (1: what `sif` solves); compare displacements
    and displacement-correlation SIFs."""
    case, opened = open_faces(case.at_start())   # with a pump: t = 0, what `sif` solves
    timer = Timer()
    try:
        sol = solve_initial(case, timer, load_factor=load_factor)
    except FAILURES as err:   # as `sif` fails: exit 1 with the reason
        raise ComputationError(failure(0, err)) from None
    if len(sol.contact.rows):   # what the report's "solved as open" promises of wingcrack's side
        raise ComputationError(f"wingcrack's open-face solve has {len(sol.contact.rows)} contact rows")
    cm, problem = sol.cm, sol.problem
    u_wc = nodal_displacements(problem.fm, problem.u, np.arange(len(cm.x)))
    timer.lap("nodal")
    pressures = [float(f.pressure) for f in case.fractures]
    skfem = SkfemProblem(case, cm, pressures, load_factor)
    timer.lap("skfem_mesh")
    u_sk = skfem.solve()
    timer.lap("skfem_solve")

    m = case.material
    KI, KII = correlation_sifs(cm, u_sk, m.E, m.nu, m.plane)
    tips = [dict(fracture=t.fracture, end=t.end, KI=t.KI, KII=t.KII, KI_skfem=float(KI[i]),
                 KII_skfem=float(KII[i])) for i, t in enumerate(sol.tips)]
    K_wc = np.array([[t["KI"], t["KII"]] for t in tips]).reshape(-1, 2)
    K_sk = np.array([[t["KI_skfem"], t["KII_skfem"]] for t in tips]).reshape(-1, 2)
    sif_rel = float(np.max(np.abs(K_sk - K_wc)) / np.max(np.abs(K_wc))) if len(tips) else 0.0

    u_max = float(np.max(np.linalg.norm(u_wc, axis=1)))
    u_diff = float(np.max(np.linalg.norm(u_sk - u_wc, axis=1)))
    if not u_max > 0:
        raise ComputationError("wingcrack's displacement is zero: nothing to compare")
    seconds = {k: round(v, 6) for k, v in timer.seconds.items()}
    seconds["total"] = round(sum(timer.seconds.values()), 6)
    return CrossCheck(case.title, int(skfem.ndofs), int(len(cm.cells)), opened, u_max, u_diff,
                      u_diff / u_max, sif_rel, tips, seconds, float(load_factor),
                      applied_loads(case, load_factor, pressures), left_out(opened, pressures))


def _facet_mapping(mesh):
    """The mesh's isoparametric map with the inverse's Newton stop NEWTON_TOL."""
    class Mapping(MappingIsoparametric):
        def invF(self, x, tind=None, newton_max_iters=50, newton_tol=NEWTON_TOL):
            return super().invF(x, tind=tind, newton_max_iters=newton_max_iters, newton_tol=newton_tol)

    return Mapping(mesh, mesh.elem(), mesh.bndelem)


def _scale(x: np.ndarray) -> float:
    return float(np.max(np.ptp(x, axis=0))) if len(x) else 1.0
