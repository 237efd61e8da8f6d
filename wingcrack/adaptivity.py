"""Mesh sizes for the next step from the Zienkiewicz-Zhu error estimate of
this step's solution (paper section 3.3.1): equal error per element, within
[tip_size, size], graded at most 0.5 per unit length."""
from __future__ import annotations

import numpy as np

from .error_estimate import recovered_stress_error, size_field
from .fem.cell_stress import whole_mesh_stress
from .parallel import snap

#: target: the estimated error is this fraction of the stress norm
TARGET = 0.05


def next_sizes(problem, tip_size: float, size: float):
    """The size field for the next mesh: (triangles (m, 3, 2), values (m, 3)),
    the vertex sizes on every cell of the current mesh, linear in each cell;
    the crack-face copies of a node take the smaller of their sizes, so the
    field is continuous across cracks. Every process computes it on the
    whole mesh in the mesher's cell order, so any number of processes gives
    the field of one (to round-off in the stresses)."""
    x, cells, stress = whole_mesh_stress(problem)
    eta = recovered_stress_error(x, cells, stress)
    pts, vals = size_field(x, cells, eta, tip_size, size, TARGET, cell_stress=stress)
    # merge coincident points (crack-face copies) keeping the minimum
    key = np.round(pts / (1e-9 * max(np.ptp(pts, axis=0).max(), 1e-300))).astype(np.int64)
    _, inv = np.unique(key, axis=0, return_inverse=True)
    inv = inv.ravel()
    merged = np.full(inv.max() + 1, np.inf)
    np.minimum.at(merged, inv, vals)
    per_node = np.full(len(x), np.nan)
    per_node[np.unique(cells[:, :3])] = merged[inv]
    # on a grid of 1e-9 size (parallel.snap, as the kink angles): the field
    # of a run on N processes is then the field of one, bit for bit
    return x[cells[:, :3]], snap(per_node[cells[:, :3]], 1e-9 * size)

