"""Interaction (M-) integral: SIFs by an equivalent-domain integral.

For each tip, with Williams' auxiliary fields (K = 1) written in the tip frame
(x1 along the crack, out of it; x2 to its left) and a weight q that is 1 on the
tip rosette and falls linearly to 0 at radius r_out:

    I = int_A [ sigma_ij du^a_i/dx1 + sigma^a_ij du_i/dx1 - sigma_ik eps^a_ik delta_1j ] dq/dxj dA
        - int_A b_i du^a_i/dx1 q dA
    K_I = E' I(mode I aux) / 2,   K_II = E' I(mode II aux) / 2

(Yau, Wang & Corten 1980; Shih & Asaro 1988). sigma and u are the TOTAL
fields: the in-situ stress sigma0 and its uniform strain eps0 are added, so the
crack faces are traction-free in the fields integrated. q is a P1 function
that is constant (1) on the quarter-point rosette, so the singular elements
contribute nothing to the gradient term. One compiled form serves every tip
and both modes: the tip position, frame and aux mode are fem.Constants.
"""
from __future__ import annotations

from functools import cached_property

import numpy as np
import ufl
from dolfinx import fem
from petsc4py import PETSc
from scipy.spatial import cKDTree

from ..material import e_prime, in_plane_strain, kappa
from . import compiled
from .mesh import cell_tags


class InteractionIntegral:
    def __init__(self, problem, E: float, nu: float, plane: str, sigma0: np.ndarray, quadrature_degree: int = 6):
        self.problem = problem
        msh = problem.fm.mesh
        self.Q = compiled.function_space(msh, ufl.FiniteElement("Lagrange", msh.ufl_cell(), 1))
        self.q = fem.Function(self.Q)
        self.tip = fem.Constant(msh, np.zeros(2, dtype=PETSc.ScalarType))
        self.R = fem.Constant(msh, np.eye(2, dtype=PETSc.ScalarType))  # rows: ex, ey
        self.mode = fem.Constant(msh, np.array([1.0, 0.0], dtype=PETSc.ScalarType))
        self.eps0 = fem.Constant(msh, in_plane_strain(np.asarray(sigma0, float), E, nu, plane).astype(PETSc.ScalarType))
        self.kappa = kappa(nu, plane)
        lame_lambda, lame_mu = problem.lame_lambda, problem.lame_mu
        kap = self.kappa

        x = ufl.SpatialCoordinate(msh)
        R = self.R
        X = ufl.dot(R, x - self.tip)
        r = ufl.sqrt(ufl.dot(X, X))
        th = ufl.atan_2(X[1], X[0])
        c, s = ufl.cos(th / 2), ufl.sin(th / 2)
        c3, s3 = ufl.cos(3 * th / 2), ufl.sin(3 * th / 2)
        f = 1.0 / ufl.sqrt(2.0 * np.pi * r)
        g = ufl.sqrt(r / (2.0 * np.pi)) / (2.0 * lame_mu)
        kI, kII = self.mode[0], self.mode[1]
        s11 = kI * f * c * (1 - s * s3) - kII * f * s * (2 + c * c3)
        s22 = kI * f * c * (1 + s * s3) + kII * f * s * c * c3
        s12 = kI * f * c * s * c3 + kII * f * c * (1 - s * s3)
        sig_a = ufl.as_matrix([[s11, s12], [s12, s22]])
        u_a = ufl.as_vector([
            kI * g * c * (kap - 1 + 2 * s * s) + kII * g * s * (kap + 1 + 2 * c * c),
            kI * g * s * (kap + 1 - 2 * c * c) - kII * g * c * (kap - 1 - 2 * s * s),
        ])
        # d u_a / dX = d u_a / dx . dx/dX, with x = tip + R^T X
        du_a = ufl.dot(ufl.grad(u_a), R.T)
        eps_a = (sig_a - lame_lambda * ufl.tr(sig_a) / (2 * lame_lambda + 2 * lame_mu) * ufl.Identity(2)) / (2 * lame_mu)

        u = problem.u_function   # its values read on each tip's cells (sifs: ElasticProblem.u_at)
        grad_u = ufl.grad(u) + self.eps0                      # total, global frame
        du = ufl.dot(ufl.dot(R, grad_u), R.T)                  # local frame
        sig = ufl.dot(ufl.dot(R, problem.stress(u, total=True)), R.T)
        dq = ufl.dot(R, ufl.grad(self.q))
        b = ufl.dot(R, problem.body)
        e1 = ufl.as_vector([1.0, 0.0])
        # P_j = sigma_ij du^a_i/dx1 + sigma^a_ij du_i/dx1 - W^{int} delta_1j
        P = ufl.dot(sig.T, du_a[:, 0]) + ufl.dot(sig_a.T, du[:, 0]) - ufl.inner(sig, eps_a) * e1
        integrand = ufl.dot(P, dq) - ufl.dot(b, du_a[:, 0]) * self.q
        self.integrand = integrand
        self.quadrature_degree = quadrature_degree
        self.Eprime = e_prime(E, nu, plane)
        # vertex coordinates of every local cell, to integrate near each tip only
        tdim = msh.topology.dim
        n_local = msh.topology.index_map(tdim).size_local
        self._cell_x = msh.geometry.x[msh.geometry.dofmap.array.reshape(-1, 6)[:n_local, :3], :2]
        # q's dofs are the vertices: q is set there (the values interpolate() gives: P1's
        # interpolation is evaluation at its dof points, the vertices' coordinates)
        self._q_x = self.Q.tabulate_dof_coordinates()[:, :2]
        # one form for every tip, made on each tip's cells (_form_near) without reading
        # its expression again; compiled with an empty cell set, as the tips' will be
        none = cell_tags(msh, np.zeros(0, dtype=np.int32))
        dx = ufl.Measure("dx", domain=msh, subdomain_data=none, metadata={"quadrature_degree": quadrature_degree})
        self._prepared = compiled.Prepared(integrand * dx(1), ("interaction_integral", self.kappa))

    def sifs(self, tip_xy, ex, ey, r_in: float, r_out: float) -> tuple[float, float]:
        """(K_I, K_II) at one tip; q = 1 for r <= r_in, 0 for r >= r_out."""
        tip_xy = np.asarray(tip_xy, float)
        self.tip.value[:] = tip_xy
        self.R.value[:] = np.array([ex, ey], float)

        # q vanishes from r_out on: only the dofs a tree finds within it are set (the same values as
        # over every dof; per tip the search is local, not a pass over the mesh)
        near = np.asarray(self._q_tree.query_ball_point(tip_xy, r_out), dtype=np.int64)
        p = self._q_x[near]
        d = np.hypot(p[:, 0] - tip_xy[0], p[:, 1] - tip_xy[1])
        q = self.q.x.array
        q[:] = 0.0
        q[near] = np.clip((r_out - d) / (r_out - r_in), 0.0, 1.0)
        form, cells = self._form_near(tip_xy, r_out)
        self.problem.u_on_cells(cells)   # u where the form reads it (a far interior's expanded if it reaches there)
        comm = self.problem.fm.mesh.comm
        out = []
        for mode in ([1.0, 0.0], [0.0, 1.0]):
            self.mode.value[:] = mode
            local = fem.assemble_scalar(form)
            out.append(comm.allreduce(local) * self.Eprime / 2.0)
        return out[0], out[1]

    def _form_near(self, tip_xy, r_out):
        """(form, cells): the form on the cells with a vertex closer than r_out to the tip:
        elsewhere q (P1, vertex dofs) and its gradient vanish, so the
        integral over these cells alone is the integral over the mesh."""
        msh = self.problem.fm.mesh
        near = np.asarray(self._vertex_tree.query_ball_point(tip_xy, r_out), dtype=np.int64) // 3
        near = np.unique(near)
        d = np.linalg.norm(self._cell_x[near] - np.asarray(tip_xy)[None, None, :], axis=2)
        cells = near[d.min(axis=1) < r_out].astype(np.int32)   # in ascending order, as over every cell
        return self._prepared.form(cell=cell_tags(msh, cells)), cells

    @cached_property
    def _vertex_tree(self):
        """A k-d tree of the local cells' vertices (point 3 c + i: vertex i of cell c)."""
        return cKDTree(self._cell_x.reshape(-1, 2))

    @cached_property
    def _q_tree(self):
        return cKDTree(self._q_x)
