"""The records that pass between the mesher's stages (meshing/mesher.py).

gmsh's mesh read back (RawMesh, from `p2_readback.extract`; for a point-symmetric
geometry one half, completed by point_symmetry.glue) -> the crack faces split
apart (SplitMesh, from wingcrack_kernels.split_faces) -> the CrackMesh the
caller gets. RawMesh crosses the meshing worker's process boundary pickled,
so both are module-level classes of numpy arrays and tuples.

Both are in gmsh's frame (frame.Frame: the caller's coordinates moved
and scaled by a power of two), before the quarter points are moved. Node
indices are 0-based rows of `x`; cells are P2 triangles in gmsh's order
[v0, v1, v2, m01, m12, m20], counter-clockwise; an edge is [a, b, mid].
Fracture direction d runs from a polyline's first point to its last.
Frozen: a stage makes a new record (dataclasses.replace) instead of changing
the one it got; the arrays themselves are not copied.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


def _no_nodes() -> np.ndarray:
    return np.zeros(0, np.int64)


@dataclass(frozen=True, eq=False)
class RawMesh:
    """gmsh's P2 mesh, each node once (the crack faces still joined).

    Tip and point entries follow the plan's order (plan.Plan.tips and
    .point_anchor, i.e. the caller's bc points)."""

    #: (n, 2) float64: node coordinates; gmsh's nodes that no cell uses are
    #: dropped and the rest numbered in gmsh's tag order. After glue: the
    #: half's nodes, then the images of those not on the divider.
    x: np.ndarray
    #: (m, 6) int64: the P2 triangles, counter-clockwise (after glue: the
    #: half's, then their images).
    cells: np.ndarray
    #: (b, 3) int64 [a, b, mid]: the edges of the outer boundary, curve by
    #: curve as gmsh walks each (after glue: then their images).
    boundary_edges: np.ndarray
    #: (b,) the name (Domain.boundary_names()) of the boundary each edge lies on.
    boundary_name: tuple[str, ...]
    #: (k, 3) int64 [a, b, mid]: the crack edges (the rosettes' spokes on
    #: the crack included), a -> b along d, grouped by fracture in order and
    #: in order along each fracture from its first point to its last.
    crack_edges: np.ndarray
    #: (k,) int64: the fracture of each crack edge.
    crack_fracture: np.ndarray
    #: (t,) int64: the node at each tip; -1 for a tip in the half gmsh did
    #: not mesh (before glue).
    tip_node: np.ndarray
    #: (t,) int64: each tip's rosette corner on the crack (the ring node of
    #: spoke 0, at the rosette radius h from the tip); -1 as tip_node.
    tip_corner: np.ndarray
    #: (q,) int64: the node of each bc point. Before glue, for a point in
    #: the half gmsh did not mesh: the node of its image R(point).
    point_nodes: np.ndarray
    #: (d,) int64, sorted: the nodes on the divider of a meshed half (what
    #: glue mirrors); empty for a whole mesh, and after glue.
    divider_nodes: np.ndarray = field(default_factory=_no_nodes)
    #: (m,) bool: True for the cells of the far field (outside crack_mesh's
    #: patch circle; after glue: then their images); None without a patch.
    far: np.ndarray | None = None
    #: True when the far field's cells were taken from the last call's (far_cache.FarCache).
    far_reused: bool = False


@dataclass(frozen=True, eq=False)
class SplitMesh:
    """The mesh with its crack faces split apart (wingcrack_kernels.split_faces
    on a RawMesh): every node on a crack face has one copy per side.
    An interior tip stays one node; a node inside a crack or at an edge-crack
    mouth gets 2 copies, a T-junction 3."""

    #: (n', 2) float64: the raw nodes (same indices), then the new copies.
    x: np.ndarray
    #: (m, 6) int64: the raw cells, in the same order, each referring to the
    #: copies on its own side.
    cells: np.ndarray
    #: (b, 3) int64: the raw boundary edges, row for row, remapped to the
    #: copies of the cell they belong to (RawMesh.boundary_name still applies).
    boundary_edges: np.ndarray
    #: (n',) int64: the raw node of each node (parent[i] = i for the raw ones).
    parent: np.ndarray
    #: (p, 2) int64 [plus, minus]: the two copies facing each other across a
    #: crack, plus on the left of d; in the order the crack edges meet them
    #: (a, mid, b of each edge), each pair once.
    pairs: np.ndarray
    #: (p, 2) float64: unit left normal of d at each pair (into the + side;
    #: at a polyline vertex the mean of its two edges' normals).
    pair_normal: np.ndarray
    #: (p,) int64: the fracture of each pair.
    pair_fracture: np.ndarray
    #: (k, 3) int64: the + face copy of each raw crack edge, row for row,
    #: same orientation.
    crack_edges: np.ndarray
    #: (k, 3) int64: the - face copy, likewise.
    crack_edges_minus: np.ndarray
