"""From a meshing.CrackMesh (plain arrays on rank 0) to a distributed DOLFINx mesh.

The CrackMesh nodes keep their identity through DOLFINx's redistribution:
`FEMesh.node_dof` maps every local geometry node to its displacement block
dof, and `FEMesh.original` gives the CrackMesh index of each local geometry
node, so tip and pair nodes can be found on any number of ranks.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
import ufl
from dolfinx import cpp as _cpp
from dolfinx import fem
from dolfinx import mesh as dmesh
from mpi4py import MPI

from . import compiled

#: P2 triangle nodes, CrackMesh (gmsh) order [v0, v1, v2, m01, m12, m20] ->
#: DOLFINx order [v0, v1, v2, m12, m20, m01] (a mid node sits opposite the
#: vertex of its number): cells_dolfinx = cells_gmsh[:, GMSH_TO_DOLFINX].
#: A P2 line is [v0, v1, m] in both.
GMSH_TO_DOLFINX = np.array([0, 1, 2, 4, 5, 3])
#: its inverse: cells_gmsh = cells_dolfinx[:, DOLFINX_TO_GMSH]
DOLFINX_TO_GMSH = np.argsort(GMSH_TO_DOLFINX)


@dataclass
class FEMesh:
    mesh: dmesh.Mesh
    facet_tags: object
    V: fem.FunctionSpace
    original: np.ndarray   # (local geometry nodes,) CrackMesh node index
    node_dof: np.ndarray   # (local geometry nodes,) block dof in V
    num_dofs: int          # global scalar dofs
    num_cells: int         # global cells

    def block_dofs(self, nodes) -> tuple[np.ndarray, np.ndarray]:
        """Where the CrackMesh `nodes` are on this rank: (found (k,) bool,
        block dof in V (k,), -1 where not found). A node is on every rank
        that owns or ghosts it."""
        nodes = np.asarray(nodes, dtype=np.int64).ravel()
        table = self._block_of_node
        blk = np.full(len(nodes), -1, dtype=self.node_dof.dtype)
        inside = (nodes >= 0) & (nodes < len(table))
        blk[inside] = table[nodes[inside]]
        return blk >= 0, blk

    @cached_property
    def _block_of_node(self) -> np.ndarray:
        """(max CrackMesh index on this rank + 1,) the block dof of each
        CrackMesh node, -1 where the node is not on this rank: made once per
        mesh, for block_dofs' lookups."""
        table = np.full(int(self.original.max()) + 1 if len(self.original) else 0, -1, dtype=self.node_dof.dtype)
        table[self.original] = self.node_dof
        return table


def cell_tags(msh, cells: np.ndarray):
    """Meshtags marking `cells` (sorted local indices of owned cells) 1: the
    cells of a form's dx(1) integral (fem.compiled.Prepared.form)."""
    return dmesh.meshtags(msh, msh.topology.dim, np.asarray(cells, dtype=np.int32),
                          np.ones(len(cells), dtype=np.int32))


def _coordinate_domain() -> ufl.Mesh:
    # FFCx gives a coordinate element without a variant the equispaced one,
    # in place, at its first form on the mesh, which changes the
    # signatures of the mesh's later forms (fem.compiled keys on the element)
    return ufl.Mesh(ufl.VectorElement(ufl.FiniteElement("Lagrange", ufl.triangle, 2, variant="equispaced")))


def _one_process(comm, nparts, tdim, cells, ghost_mode):
    """The cell partition on one process: every cell stays on it."""
    return _cpp.graph.AdjacencyList_int32(np.zeros(cells.num_nodes, dtype=np.int32))


def _facet_tags_one_process(msh, facets, values):
    """The facet tags of the boundary edges `facets` (mesher node numbers,
    vertices first) on one process, by a search on the sorted facet vertex
    pairs: what distribute_entity_data and meshtags_from_entities give
    there (the same sorted facets and values), without their
    vertex-to-entity maps. None where an edge is not a facet or is tagged
    twice (then the caller takes dolfinx's way)."""
    if len(facets) == 0:
        return None
    c2v = msh.topology.connectivity(2, 0).array.reshape(-1, 3)
    # a cell's first three geometry nodes are its vertices, in topology order
    node_vertex = np.full(msh.geometry.x.shape[0], -1, dtype=np.int64)
    node_vertex[msh.geometry.dofmap.array.reshape(-1, 6)[:, :3]] = c2v
    original = np.asarray(msh.geometry.input_global_indices, dtype=np.int64)
    vertex = np.full(max(int(original.max()), int(facets[:, :2].max())) + 1, -1, dtype=np.int64)
    vertex[original] = node_vertex
    ends = vertex[facets[:, :2]]
    f2v = msh.topology.connectivity(1, 0).array.reshape(-1, 2).astype(np.int64)
    n = int(c2v.max()) + 1

    def key(pairs):
        return pairs.min(axis=1) * n + pairs.max(axis=1)

    keys = key(f2v)
    order = np.argsort(keys)
    wanted = key(ends)
    pos = np.minimum(np.searchsorted(keys, wanted, sorter=order), len(order) - 1)
    index = order[pos]
    if np.any(ends < 0) or np.any(keys[index] != wanted) or len(np.unique(index)) != len(index):
        return None
    sort = np.argsort(index)
    return dmesh.meshtags(msh, 1, index[sort].astype(np.int32), np.asarray(values, dtype=np.int32)[sort])


def to_dolfinx(cm, comm: MPI.Comm = MPI.COMM_WORLD, root: int = 0) -> FEMesh:
    """Distribute the CrackMesh `cm` (only read on `root`) and build P2 space."""
    domain = _coordinate_domain()
    if comm.rank == root:
        cells = np.ascontiguousarray(np.asarray(cm.cells, dtype=np.int64)[:, GMSH_TO_DOLFINX])
        x = np.ascontiguousarray(np.asarray(cm.x, dtype=np.float64))
        facets = np.ascontiguousarray(np.asarray(cm.boundary_edges, dtype=np.int64))
        values = np.asarray(cm.boundary_tags, dtype=np.int32)
    else:
        cells = np.empty((0, 6), dtype=np.int64)
        x = np.empty((0, 2), dtype=np.float64)
        facets = np.empty((0, 3), dtype=np.int64)
        values = np.empty((0,), dtype=np.int32)
    if comm.size == 1:
        # what dmesh.create_mesh does, without its first try (a TypeError on
        # the array) and without partitioning a graph into one part
        cmap = _cpp.fem.CoordinateElement(_cpp.mesh.CellType.triangle, 2)
        msh = dmesh.Mesh(_cpp.mesh.create_mesh(comm, _cpp.graph.AdjacencyList_int64(cells), cmap, x,
                                               dmesh.GhostMode.shared_facet, _one_process), domain)
    else:
        msh = dmesh.create_mesh(comm, cells, x, domain)
    tdim = msh.topology.dim
    msh.topology.create_connectivity(tdim - 1, tdim)
    msh.topology.create_connectivity(tdim - 1, 0)
    ft = _facet_tags_one_process(msh, facets, values) if comm.size == 1 else None
    if ft is None:
        local_entities, local_values = _cpp.io.distribute_entity_data(msh._mesh, tdim - 1, facets, values)
        adj = _cpp.graph.AdjacencyList_int32(local_entities)
        ft = dmesh.meshtags_from_entities(msh, tdim - 1, adj, local_values.astype(np.int32))

    V = compiled.function_space(msh, ufl.VectorElement("Lagrange", msh.ufl_cell(), 2))
    geo = msh.geometry.dofmap.array
    dofs = V.dofmap.list.array
    node_dof = np.full(msh.geometry.x.shape[0], -1, dtype=np.int32)
    # Same element (P2 Lagrange) for geometry and displacement: the local
    # node order inside each cell coincides, so the two maps line up.
    node_dof[geo] = dofs
    original = np.asarray(msh.geometry.input_global_indices, dtype=np.int64)
    imap = V.dofmap.index_map
    num_dofs = imap.size_global * V.dofmap.index_map_bs
    num_cells = msh.topology.index_map(tdim).size_global
    return FEMesh(msh, ft, V, original, node_dof, num_dofs, num_cells)
