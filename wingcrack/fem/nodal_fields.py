"""Displacement, total stress and von Mises stress at the CrackMesh nodes, as
plain arrays by CrackMesh node index for the field files (io/fields.py)."""
from __future__ import annotations

import numpy as np
import ufl
from dolfinx import fem

from . import compiled


def _nodal_stress(problem) -> np.ndarray:
    """Total stress (sxx, syy, sxy) at the P2 nodes, per local geometry node.

    The stress is discontinuous between cells; each node takes the value of
    one of its cells (display only)."""
    fm = problem.fm
    T = compiled.function_space(fm.mesh, ufl.VectorElement("Lagrange", fm.mesh.ufl_cell(), 2, dim=3))
    s = problem.stress(problem.u, total=True)
    expr = compiled.expression(ufl.as_vector([s[0, 0], s[1, 1], s[0, 1]]), T.element.interpolation_points(),
                               ("nodal_fields.stress",))
    f = fem.Function(T)
    f.interpolate(expr)
    node_dof = fm.node_dof  # same P2 layout as the displacement space
    return f.x.array.reshape(-1, 3)[node_dof]


def local_nodal_fields(problem) -> dict:
    """{name: (local geometry nodes, k) array}: displacement (ux, uy) in m,
    total stress (sxx, syy, sxy) and von Mises stress of the in-plane
    components in Pa."""
    fm = problem.fm
    u = problem.u.x.array.reshape(-1, 2)[fm.node_dof]
    s = _nodal_stress(problem)
    vm = np.sqrt(s[:, 0] ** 2 - s[:, 0] * s[:, 1] + s[:, 1] ** 2 + 3 * s[:, 2] ** 2)
    return {"displacement": u, "stress": s, "von_mises": vm}


def gather_nodal(fm, fields: dict, num_nodes: int) -> dict | None:
    """Fields by CrackMesh node index on rank 0 (None on the other ranks)."""
    comm = fm.mesh.comm
    parts = comm.gather((fm.original, fields), root=0)
    if comm.rank != 0:
        return None
    out = {}
    for name, arr in fields.items():
        shape = (num_nodes,) + arr.shape[1:]
        full = np.zeros(shape)
        for original, f in parts:
            full[original] = f[name]
        out[name] = full
    return out


def nodal_fields(problem, num_nodes: int) -> dict | None:
    """local_nodal_fields of every rank by CrackMesh node index (num_nodes of
    them) on rank 0, None on the other ranks. Collective."""
    return gather_nodal(problem.fm, local_nodal_fields(problem), num_nodes)
