"""Mesh sizes for the next step from the Zienkiewicz-Zhu error estimate of
this step's solution (paper section 3.3.1): equal error per element, within
[tip_size, size], graded at most 0.5 per unit length."""
from __future__ import annotations

import numpy as np

from .error_estimate import recovered_stress_error, size_field
from .fem.cell_stress import cell_stress

#: target: the estimated error is this fraction of the stress norm
TARGET = 0.05


def next_sizes(problem, tip_size: float, size: float):
    """(points (k,2), sizes (k,)) at the current mesh's vertices; the two
    copies of a split crack node get the smaller of their sizes."""
    x, cells, stress = cell_stress(problem)
    eta = recovered_stress_error(x, cells, stress)
    pts, vals = size_field(x, cells, eta, tip_size, size, TARGET, cell_stress=stress)
    # merge coincident points (crack-face copies) keeping the minimum
    key = np.round(pts / (1e-9 * max(np.ptp(pts, axis=0).max(), 1e-300))).astype(np.int64)
    _, inv = np.unique(key, axis=0, return_inverse=True)
    inv = inv.ravel()
    merged = np.full(inv.max() + 1, np.inf)
    np.minimum.at(merged, inv, vals)
    first = np.full(inv.max() + 1, -1)
    first[inv[::-1]] = np.arange(len(inv))[::-1]
    return pts[first], merged
