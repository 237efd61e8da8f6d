"""Pieces of the body that no displacement condition holds.

A fracture that cuts the body apart leaves pieces whose stiffness matrix has
rigid-body modes unless displacement conditions on the piece fix all three
(two translations and the rotation). The Cholesky factorisation does not
reliably say so: a piece held at one point only (free to rotate) gave a
pivot no threshold flagged and displacements of 1e9 m. Here the check is
exact and made before factorising: the connected pieces of the split mesh
(crack faces apart), and for each the rank of the rigid modes restricted to
its constrained degrees of freedom. Pieces whose faces carry contact are
then solved through the contact problem (wingcrack.floating).

Pure numpy/scipy on the CrackMesh and the Loads (wingcrack.loads),
identical on every process (every process holds the whole crack mesh).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

#: singular values of the (scaled) constrained rigid modes below this times
#: the largest are zero: well-held pieces give >= ~1e-4 (two constrained
#: points 1e-4 of the piece's size apart), round-off ~1e-16
RANK_TOLERANCE = 1e-10


@dataclass
class FreePiece:
    centre: np.ndarray  # (2,) centre of the piece's bounding box
    motion: str  # what the free rigid-body modes let it do
    cells: int
    nodes: np.ndarray = None  # the piece's CrackMesh nodes
    modes: np.ndarray = None  # (k, 3) its free rigid modes, rows [ux, uy, rotation (-y, x) / size about centre]
    size: float = 1.0         # the largest side of its bounding box (m)


def free_pieces(cm, loads) -> list[FreePiece]:
    """Every connected piece of `cm` whose displacement conditions (loads:
    wingcrack.loads.Loads) leave a rigid-body mode free."""
    x = np.asarray(cm.x, dtype=np.float64)
    cells = np.asarray(cm.cells, dtype=np.int64)
    n = len(x)
    # nodes are linked through cells: node i -- first node of each of its cells
    rows = cells.ravel()
    cols = np.repeat(cells[:, 0], cells.shape[1])
    graph = coo_matrix((np.ones(len(rows)), (rows, cols)), shape=(n, n))
    count, label = connected_components(graph, directed=False)
    used = np.zeros(n, dtype=bool)
    used[cells.ravel()] = True

    fixed = [[] for _ in range(2)]  # constrained nodes per direction
    edges = np.asarray(cm.boundary_edges, dtype=np.int64).reshape(-1, 3)
    tags = np.asarray(cm.boundary_tags, dtype=np.int64)
    for tag, c, _ in loads.boundary_displacements:
        fixed[c].append(edges[tags == tag].ravel())
    for node, c, _ in loads.point_displacements:
        fixed[c].append(np.array([node], dtype=np.int64))
    fixed = [np.unique(np.concatenate(f)) if f else np.zeros(0, np.int64) for f in fixed]

    out = []
    for piece in range(count):
        nodes = np.flatnonzero((label == piece) & used)
        if not len(nodes):
            continue
        lo, hi = x[nodes].min(axis=0), x[nodes].max(axis=0)
        centre = 0.5 * (lo + hi)
        size = max(float(np.max(hi - lo)), 1e-300)
        blocks = []
        for c in (0, 1):
            held = fixed[c][label[fixed[c]] == piece]
            if not len(held):
                continue
            r = (x[held] - centre) / size
            m = np.zeros((len(held), 3))
            m[:, c] = 1.0
            m[:, 2] = -r[:, 1] if c == 0 else r[:, 0]  # rotation: (-y, x)
            blocks.append(m)
        m = np.concatenate(blocks) if blocks else np.zeros((0, 3))
        if len(m):
            _, s, vt = np.linalg.svd(m, full_matrices=True)
            s = np.concatenate([s, np.zeros(3 - len(s))]) if len(s) < 3 else s
            free = vt[s <= RANK_TOLERANCE * max(s[0], 1e-300)]
        else:
            free = np.eye(3)
        if len(free):
            cells_here = int(np.count_nonzero(label[cells[:, 0]] == piece))
            out.append(FreePiece(centre=centre, motion=_modes(free), cells=cells_here, nodes=nodes, modes=free,
                                 size=size))
    return out


def _modes(free: np.ndarray) -> str:
    """What the free rigid-body modes (rows: [ux, uy, rotation]) let the piece do."""
    if len(free) == 3:
        return "is not held at all"
    rotates = np.any(np.abs(free[:, 2]) > 1e-6)
    if rotates and len(free) == 1:
        return "can rotate about the point that holds it"
    if not rotates:
        along = "x" if np.all(np.abs(free[:, 1]) < 1e-6) else "y" if np.all(np.abs(free[:, 0]) < 1e-6) else "some direction"
        return f"can slide in {along}" if len(free) == 1 else "can translate"
    return "can move (held in one direction only)"


def describe(pieces: list[FreePiece]) -> str:
    """One line for the error message."""
    parts = []
    for p in pieces[:3]:
        parts.append(f"the piece around ({p.centre[0]:.4g}, {p.centre[1]:.4g}) {p.motion}")
    more = f" (and {len(pieces) - 3} more)" if len(pieces) > 3 else ""
    return "; ".join(parts) + more
