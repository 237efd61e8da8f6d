"""Zienkiewicz-Zhu recovery error estimate (paper section 3.3.1, eqs. 35-36)
and the element size field it implies, over the C++ kernels `zz_error` and
`zz_sizes`. numpy only: the caller evaluates the FE stress.

Arrays: x (n, 2) in m; cells (m, 6) P2 in gmsh order [v0, v1, v2, m01, m12,
m20] (only the vertices are used); cell_stress (m, 3, 3) with
cell_stress[c, k] = (sxx, syy, sxy) in Pa of cell c's FE stress at its vertex k.
A P2 displacement gives a linear stress on a straight cell, so these 3 values
are the whole of it. On a mesh split along its cracks the two faces have their
own nodes and nothing is averaged across a crack.

Norm: |s|^2 = sxx^2 + syy^2 + 2 sxy^2 (Frobenius, sxy counted twice), for
the error eta and for the stress alike, so eta is in Pa m and no material
constants enter.
"""
from __future__ import annotations

import numpy as np

import wingcrack_kernels as K

_NEXT = [1, 2, 0]  # vertex k -> k+1: the edges (0,1), (1,2), (2,0)
_FROBENIUS = np.array([1.0, 1.0, 2.0])  # sxx, syy, sxy (twice)


def recovered_stress_error(x, cells, cell_stress) -> np.ndarray:
    """(m,) eta_c = ||sigma_h - sigma*|| over each cell (Pa m).

    sigma* is the area-weighted mean of the cells' stresses at each vertex,
    linear in between (eq. 35, with each cell's value at the vertex rather
    than its cell mean, so a linear stress field gives eta = 0)."""
    return K.zz_error(x, cells, cell_stress)[1]


def stress_norm(x, cells, cell_stress) -> float:
    """sqrt(int |sigma_h|^2 dA) over the mesh (Pa m), exact for the linear
    per-cell stress (edge-midpoint rule on the straight vertex triangles)."""
    cells = np.asarray(cells)
    s = np.asarray(cell_stress, dtype=float)
    mid = 0.5 * (s + s[:, _NEXT])  # (m, 3 edges, 3)
    sq = np.einsum("cek,k,cek->c", mid, _FROBENIUS, mid)
    return float(np.sqrt(_areas(x, cells) @ sq / 3.0))


def cell_sizes(x, cells) -> np.ndarray:
    """(m,) current size of each cell: the mean length of its 3 vertex edges,
    the quantity a gmsh mesh-size field prescribes."""
    v = np.take(np.asarray(x, dtype=float), np.asarray(cells)[:, :3], axis=0)
    d = v[:, _NEXT] - v
    return np.sqrt(d[..., 0] ** 2 + d[..., 1] ** 2).mean(axis=1)


def size_field(x, cells, eta, size_min, size_max, target_fraction=0.05, *, cell_stress, p=1.0, grading=0.5):
    """Target mesh size at every vertex: (points (k, 2), values (k,)).

    The total error allowed is target_fraction * stress_norm(x, cells,
    cell_stress): a relative error of sigma in the same norm as eta (the
    classical ZZ relative error, with ||sigma_h|| in place of
    sqrt(||sigma_h||^2 + ||e||^2), which differ by 0.13 % at 5 %).
    Each cell aims at an equal share e* = target / sqrt(m):
    h' = h (e*/eta)^(1/p), h = cell_sizes(); p is the convergence order of
    eta_c in h (1 keeps the sizes responsive; 2 is the classical value for P2
    away from singularities). Sizes are clamped to [size_min, size_max], a
    vertex takes the smallest size of its cells, and the field is graded so
    that neighbouring vertices differ by at most `grading` times their
    distance (a ratio <= 1 + grading across an edge). Crack-face copies of a
    node are separate points and may carry different sizes."""
    cells = np.asarray(cells)
    target = target_fraction * stress_norm(x, cells, cell_stress)
    if not target > 0.0:
        raise ValueError("size_field: the stress is zero, no relative error target")
    sizes = K.zz_sizes(x, cells, eta, cell_sizes(x, cells), target, p=p, h_min=size_min, h_max=size_max,
                       grading=grading)
    vertices = np.unique(cells[:, :3])
    return np.asarray(x, dtype=float)[vertices], sizes[vertices]


def _areas(x, cells):
    v = np.take(np.asarray(x, dtype=float), cells[:, :3], axis=0)
    a, b = v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]
    return 0.5 * np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])
