"""Field files that ParaView opens: VTU (meshio) of the P2 mesh with nodal
displacement (x, y, 0), total stress as a 3 x 3 tensor (nine components,
which ParaView treats as a tensor: sxx, sxy, 0, sxy, syy, 0, 0, 0, 0; the
out-of-plane stress is not computed and is written as 0) and the von Mises
stress of the in-plane components.

DOLFINx 0.5's XDMF writer pulls mesh nodes back to the reference cell with a
Newton iteration, which cannot converge in quarter-point cells (their
Jacobian vanishes at the tip); writing the CrackMesh nodes directly avoids
that and keeps the file in the mesh's own node numbering. Values are gathered
to rank 0, which writes the file.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import ufl
from dolfinx import fem


def _nodal_stress(problem) -> tuple[np.ndarray, np.ndarray]:
    """Total stress (sxx, syy, sxy) at the P2 nodes, per local geometry node.

    The stress is discontinuous between cells; each node takes the value of
    one of its cells (display only)."""
    fm = problem.fm
    T = fem.VectorFunctionSpace(fm.mesh, ("Lagrange", 2), dim=3)
    s = problem.stress(problem.u, total=True)
    expr = fem.Expression(ufl.as_vector([s[0, 0], s[1, 1], s[0, 1]]), T.element.interpolation_points())
    f = fem.Function(T)
    f.interpolate(expr)
    node_dof = fm.node_dof  # same P2 layout as the displacement space
    vals = f.x.array.reshape(-1, 3)[node_dof]
    return vals


def nodal_fields(problem) -> dict:
    """{name: (local geometry nodes, k) array} for the output file."""
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


def stress_tensor(s: np.ndarray) -> np.ndarray:
    """(n, 9) row-major 3 x 3 tensors from (n, 3) rows (sxx, syy, sxy)."""
    t = np.zeros((len(s), 9))
    t[:, 0], t[:, 4] = s[:, 0], s[:, 1]
    t[:, 1] = t[:, 3] = s[:, 2]
    return t


def write_fields(path: Path, problem, cm, field_data: dict | None = None) -> Path:
    """Write the mesh with displacement, stress tensor and von Mises stress
    to `path` (.vtu); `field_data` ({name: number}, e.g. the step and its
    load factor) goes into the file's field data. Collective; rank 0
    writes."""
    import meshio

    from .pvd import add_field_data

    path = Path(path)
    full = gather_nodal(problem.fm, nodal_fields(problem), len(cm.x))
    if full is not None:
        points = np.c_[cm.x, np.zeros(len(cm.x))]
        disp = np.c_[full["displacement"], np.zeros(len(cm.x))]
        mesh = meshio.Mesh(points, [("triangle6", np.asarray(cm.cells))],
                           point_data={"displacement": disp, "stress": stress_tensor(full["stress"]),
                                       "von_mises": full["von_mises"]})
        mesh.write(path)
        if field_data:
            add_field_data(path, field_data)
    return path
