"""Per-cell stress at (near) the three vertices, for the error estimator.

The P2 displacement gives a linear stress in each straight cell. It is
evaluated at barycentric points 1e-3 inside the vertices (at a quarter-point
tip vertex the stress is singular) and returned with the local geometry in
gmsh's node order, so the C++ estimator can work on plain arrays.
"""
from __future__ import annotations

import numpy as np
import ufl
from dolfinx import fem

_EPS = 1e-3
# reference points near vertices 0, 1, 2 of the reference triangle
_POINTS = np.array([[_EPS, _EPS], [1 - 2 * _EPS, _EPS], [_EPS, 1 - 2 * _EPS]])
# DOLFINx P2 triangle order [v0, v1, v2, m12, m20, m01] -> gmsh [v0, v1, v2, m01, m12, m20]
_TO_GMSH = [0, 1, 2, 5, 3, 4]


def cell_stress(problem):
    """(x (n,2), cells (m,6) gmsh order, stress (m,3,3)) on this process's cells;
    stress[c, k] = (sxx, syy, sxy) of the total stress near vertex k of cell c."""
    msh = problem.fm.mesh
    s = problem.stress(problem.u, total=True)
    expr = fem.Expression(ufl.as_vector([s[0, 0], s[1, 1], s[0, 1]]), _POINTS)
    ncells = msh.topology.index_map(2).size_local
    cells = np.arange(ncells, dtype=np.int32)
    values = expr.eval(cells).reshape(ncells, 3, 3)
    geo = msh.geometry.dofmap.array.reshape(-1, 6)[:ncells][:, _TO_GMSH]
    return msh.geometry.x[:, :2].copy(), np.ascontiguousarray(geo, dtype=np.int64), values
