"""Whether the displacement conditions fix every rigid motion of the domain
(two translations and the rotation): without that the case is statically
undetermined, and the message names the motions left free."""
from __future__ import annotations

import numpy as np

from wingcrack.errors import CaseError

#: Sample points per named boundary for the rigid-body check.
_SAMPLES = 8


def _boundary_samples(domain, name: str) -> np.ndarray:
    """Points along the named boundary: inside each straight edge, around a disc rim."""
    t = (np.arange(_SAMPLES) + 0.5) / _SAMPLES
    if domain.shape == "disc":
        a = 2 * np.pi * t
        return domain.center + domain.radius * np.column_stack([np.cos(a), np.sin(a)])
    v = domain.vertices()
    i = domain.edge_names().index(name)
    a, b = v[i], v[(i + 1) % len(v)]
    return a + t[:, None] * (b - a)


def check_statically_determined(bcs, domain) -> None:
    """Rank of the rigid motions (1,0), (0,1), (-y,x) under the displacement conditions.

    Each prescribed component at a point p gives a row: x: [1, 0, -y], y: [0, 1, x],
    with (x, y) = (p - origin) / L (origin inside the domain, L its length scale,
    so the rows are well scaled). A boundary condition counts at sample points.
    """
    L = float(domain.length_scale())
    origin = domain.center if domain.shape == "disc" else domain.vertices().mean(axis=0)
    rows = []
    for bc in bcs:
        if bc.kind != "displacement":
            continue
        pts = np.array([bc.at]) if bc.at is not None else _boundary_samples(domain, bc.on)
        for x, y in (pts - origin) / L:
            if bc.components[0]:
                rows.append([1.0, 0.0, -y])
            if bc.components[1]:
                rows.append([0.0, 1.0, x])
    A = np.array(rows, dtype=float).reshape(-1, 3)
    rank = np.linalg.matrix_rank(A, tol=1e-8) if len(A) else 0
    if rank < 3:
        raise CaseError("bc", f"statically undetermined: {_free_motions(A, origin / L, L)} free; "
                              "add displacement conditions")


def _free_motions(A: np.ndarray, origin: np.ndarray, L: float) -> str:
    """Name the rigid motions the rows of A leave free (A uses coordinates (p - origin)/L)."""
    if len(A) == 0:
        return "translation x, translation y and rotation are"
    _, s, vt = np.linalg.svd(A)
    null = vt[np.sum(s > 1e-8 * max(s.max(), 1.0)):]
    free = []
    tx = np.linalg.norm(A @ [1.0, 0.0, 0.0]) < 1e-8
    ty = np.linalg.norm(A @ [0.0, 1.0, 0.0]) < 1e-8
    if tx:
        free.append("translation x")
    if ty:
        free.append("translation y")
    if any(abs(v[2]) > 1e-8 for v in null):
        if len(null) == 1:
            a, b, c = null[0]
            centre = (origin + np.array([-b / c, a / c])) * L
            free.append(f"rotation about ({centre[0]:.4g}, {centre[1]:.4g})")
        else:
            free.append("rotation")
    if not free:  # pragma: no cover - a null space always contains one of the above
        free.append("a rigid motion")
    verb = "is" if len(free) == 1 else "are"
    return ", ".join(free[:-1]) + (" and " if len(free) > 1 else "") + free[-1] + f" {verb}"
