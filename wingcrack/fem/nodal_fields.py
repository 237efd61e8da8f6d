"""Displacement, total stress and von Mises stress at the CrackMesh nodes, as
plain arrays by CrackMesh node index for the field files (io/fields.py).

The stress is discontinuous between cells; a node takes the value of one of
its cells (display only). At a crack-tip node it has no value: the stress
is singular there (1/sqrt(r)), and in a quarter-point cell the geometry
map's Jacobian vanishes at the tip vertex, so the stress interpolated there
is NaN. A tip node takes instead, by convention, the mean over the cells
that have it as a vertex (the rosette's) of each cell's stress at its
point of the 3-point Gauss rule nearest the tip (barycentric 2/3 at the tip
vertex, 1/6 at the others; about h/9 from the tip, h the rosette radius,
where the quarter-point nodes are at h/4): finite, of the size of the
stress next to the tip, and the same on any number of processes (a mean,
where "one of its cells" would depend on the partition)."""
from __future__ import annotations

import numpy as np
import ufl
from dolfinx import fem

from . import compiled

#: reference point of the 3-point Gauss rule nearest each vertex of DOLFINx's
#: reference triangle, (0, 0), (1, 0), (0, 1): barycentric 2/3 at the vertex
NEAR_VERTEX = np.array([[1 / 6, 1 / 6], [2 / 3, 1 / 6], [1 / 6, 2 / 3]])


def _stress_components(problem):
    s = problem.stress(problem.u, total=True)
    return ufl.as_vector([s[0, 0], s[1, 1], s[0, 1]])


def _nodal_stress(problem) -> np.ndarray:
    """Total stress (sxx, syy, sxy) at the P2 nodes, per local geometry node
    (NaN at a quarter-point tip vertex: see the module doc)."""
    fm = problem.fm
    T = compiled.function_space(fm.mesh, ufl.VectorElement("Lagrange", fm.mesh.ufl_cell(), 2, dim=3))
    expr = compiled.expression(_stress_components(problem), T.element.interpolation_points(),
                               ("nodal_fields.stress",))
    f = fem.Function(T)
    f.interpolate(expr)
    node_dof = fm.node_dof  # same P2 layout as the displacement space
    return f.x.array.reshape(-1, 3)[node_dof]


def local_tip_stress(problem, tip_nodes) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """This process's part of the tip nodes' stress convention (module doc):
    (CrackMesh node (k,), sum (k, 3) of (sxx, syy, sxy) over this process's
    owned cells with that node as a vertex, each at NEAR_VERTEX of it, and
    the number of those cells (k,)), for the `tip_nodes` (CrackMesh indices)
    on this process."""
    fm = problem.fm
    msh = fm.mesh
    tip_nodes = np.unique(np.asarray(tip_nodes, dtype=np.int64))
    geo_nodes = np.flatnonzero(np.isin(fm.original, tip_nodes))
    ncells = msh.topology.index_map(2).size_local     # owned cells only: each counted once over the ranks
    vertices = msh.geometry.dofmap.array.reshape(-1, 6)[:ncells, :3]
    cells, corner = np.nonzero(np.isin(vertices, geo_nodes))
    node = fm.original[vertices[cells, corner]]
    total = np.zeros((len(tip_nodes), 3))
    count = np.zeros(len(tip_nodes))
    # on every rank, with tip cells or none: the first compilation is collective (DOLFINx's JIT)
    expr = compiled.expression(_stress_components(problem), NEAR_VERTEX, ("nodal_fields.tip_stress",))
    if len(cells):
        values = expr.eval(cells.astype(np.int32)).reshape(len(cells), 3, 3)[np.arange(len(cells)), corner]
        at = np.searchsorted(tip_nodes, node)
        np.add.at(total, at, values)
        np.add.at(count, at, 1.0)
    return tip_nodes, total, count


def von_mises(s: np.ndarray) -> np.ndarray:
    """The von Mises stress of in-plane stresses (n, 3) (sxx, syy, sxy)."""
    return np.sqrt(s[:, 0] ** 2 - s[:, 0] * s[:, 1] + s[:, 1] ** 2 + 3 * s[:, 2] ** 2)


def local_nodal_fields(problem) -> dict:
    """{name: (local geometry nodes, k) array}: displacement (ux, uy) in m,
    total stress (sxx, syy, sxy) and von Mises stress of the in-plane
    components in Pa (NaN at tip nodes: nodal_fields gives them their
    convention)."""
    fm = problem.fm
    u = problem.u.x.array.reshape(-1, 2)[fm.node_dof]
    s = _nodal_stress(problem)
    # a quarter-point tip vertex's stress is not a number (NaN or inf: inf - inf warns); nodal_fields
    # replaces it by the tip convention, so no warning is the user's to read
    with np.errstate(invalid="ignore", over="ignore"):
        vm = von_mises(s)
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


def nodal_fields(problem, num_nodes: int, tip_nodes=()) -> dict | None:
    """local_nodal_fields of every rank by CrackMesh node index (num_nodes of
    them) on rank 0, with the stress (and von Mises stress) of the
    `tip_nodes` (CrackMesh indices of the quarter-point tips) by the
    convention of the module doc; None on the other ranks. Collective."""
    out = gather_nodal(problem.fm, local_nodal_fields(problem), num_nodes)
    parts = problem.fm.mesh.comm.gather(local_tip_stress(problem, tip_nodes), root=0)
    if out is None:
        return None
    nodes, total, count = parts[0][0], sum(p[1] for p in parts), sum(p[2] for p in parts)
    if np.any(count == 0):
        raise ValueError(f"tip nodes {nodes[count == 0][:5].tolist()} are a vertex of no cell")
    out["stress"][nodes] = total / count[:, None]
    out["von_mises"][nodes] = von_mises(out["stress"][nodes])
    return out
