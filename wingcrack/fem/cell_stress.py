"""Per-cell stress at (near) the three vertices, for the error estimator.

The P2 displacement gives a linear stress in each straight cell. It is
evaluated at barycentric points 1e-3 inside the vertices (at a quarter-point
tip vertex the stress is singular) and returned with the local geometry in
gmsh's node order, so the C++ estimator can work on plain arrays.
"""
from __future__ import annotations

import numpy as np
import ufl

from . import compiled
from .mesh import DOLFINX_TO_GMSH

_EPS = 1e-3
# reference points near vertices 0, 1, 2 of the reference triangle
_POINTS = np.array([[_EPS, _EPS], [1 - 2 * _EPS, _EPS], [_EPS, 1 - 2 * _EPS]])


def cell_stress(problem):
    """(x (n,2), cells (m,6) gmsh order, stress (m,3,3)) on this process's cells;
    stress[c, k] = (sxx, syy, sxy) of the total stress near vertex k of cell c."""
    msh = problem.fm.mesh
    s = problem.stress(problem.u, total=True)
    expr = compiled.expression(ufl.as_vector([s[0, 0], s[1, 1], s[0, 1]]), _POINTS, ("cell_stress.stress",))
    ncells = msh.topology.index_map(2).size_local
    cells = np.arange(ncells, dtype=np.int32)
    values = expr.eval(cells).reshape(ncells, 3, 3)
    geo = msh.geometry.dofmap.array.reshape(-1, 6)[:ncells][:, DOLFINX_TO_GMSH]
    return msh.geometry.x[:, :2].copy(), np.ascontiguousarray(geo, dtype=np.int64), values


def whole_mesh_stress(problem):
    """cell_stress of every process's cells, gathered on every process: x by
    mesher node, cells (mesher node numbers, gmsh order) and their stresses
    in the mesher's cell order."""
    fm = problem.fm
    msh = fm.mesh
    x, cells, stress = cell_stress(problem)
    ids = np.asarray(msh.topology.original_cell_index, dtype=np.int64)[:len(cells)]
    part = (ids, fm.original[cells], stress, fm.original, x)
    parts = msh.comm.allgather(part) if msh.comm.size > 1 else [part]
    ids, cells, stress = (np.concatenate([q[i] for q in parts]) for i in range(3))
    order = np.argsort(ids)
    nodes = np.concatenate([q[3] for q in parts])
    xs = np.zeros((nodes.max() + 1, 2))
    xs[nodes] = np.concatenate([q[4] for q in parts])
    return xs, np.ascontiguousarray(cells[order]), np.ascontiguousarray(stress[order])
