"""The fracture faces as a polyline file: opening, slip, normal traction and
contact state at every face node of the + face (VTU through meshio)."""
from __future__ import annotations

from pathlib import Path

import numpy as np


def face_state(cm, jump, traction, closed) -> dict:
    """Per pair of `cm` (a CrackMesh): position, opening w = [u].n, slip
    s = [u].t (m), normal traction sigma_nn (Pa, <= 0 in contact) and
    closed (bool), from the pairs' displacement jumps [u] (p, 2), normal
    tractions (p,) and closed flags (p,) (step.Discretisation.face_values)."""
    pairs = np.asarray(cm.pairs, dtype=np.int64).reshape(-1, 2)
    n = np.asarray(cm.pair_normal, float).reshape(-1, 2)
    t = np.c_[n[:, 1], -n[:, 0]]
    jump = np.asarray(jump, float).reshape(-1, 2)
    return {"position": np.asarray(cm.x)[pairs[:, 0]], "opening": np.sum(jump * n, axis=1),
            "slip": np.sum(jump * t, axis=1), "normal_traction": np.asarray(traction, float),
            "closed": np.asarray(closed, bool), "plus": pairs[:, 0]}


def write_faces(path: Path, cm, jump, traction, closed, field_data: dict | None = None) -> Path:
    """line3 cells of the + faces of `cm`; point data at the + face nodes
    (zero at tips, which are not pairs) from the pair values of face_state;
    `field_data` ({name: number}) as in write_fields."""
    import meshio

    from .pvd import add_field_data

    st = face_state(cm, jump, traction, closed)
    edges = np.asarray(cm.crack_edges, dtype=np.int64)
    nodes, local = np.unique(edges, return_inverse=True)
    index = {int(v): i for i, v in enumerate(nodes)}
    data = {k: np.zeros(len(nodes)) for k in ("opening", "slip", "normal_traction", "closed")}
    for j, p in enumerate(st["plus"]):
        i = index.get(int(p))
        if i is not None:
            for k in data:
                data[k][i] = float(st[k][j])
    pts = np.c_[np.asarray(cm.x)[nodes], np.zeros(len(nodes))]
    frac = np.asarray(cm.crack_fracture, dtype=np.int64)
    meshio.Mesh(pts, [("line3", local.reshape(-1, 3))], point_data=data,
                cell_data={"fracture": [frac]}).write(Path(path))
    if field_data:
        add_field_data(path, field_data)
    return Path(path)
