"""The mesh read back from gmsh (RawMesh): gmsh's first-order mesh made
second order here (_P2), its nodes numbered, its boundary, crack, tip and
bc-point nodes found; with a patch the far cells first (and a cached far
field glued in, far_cache)."""

from __future__ import annotations

import numpy as np

from meshing.far_cache import FarCache
from meshing.records import RawMesh


def rim(domain, boundary_curves):
    """(center, radius, curves): the outer boundary's circle arcs (a disc's
    rim), whose mid nodes lie on the circle; None for straight boundaries."""
    if domain.shape != "disc":
        return None
    return np.asarray(domain.center, dtype=np.float64), float(domain.radius), [c for c, _ in boundary_curves]


class _P2:
    """gmsh's first-order mesh made second order: a mid node on every edge
    of a triangle or of a curve's line element, at 0.5 (a + b), on a circle
    arc (rim) at the circle's point on the edge's bisector (the arc's
    middle, which gmsh's setOrder(2) finds by a Newton solve to a relative
    1e-6 only: tests/unit/test_mid_nodes.py), on a one-edge curve of `mids` at
    the given point. Built here, not by setOrder(2), for its cost: a
    sizeable part of gmsh's time on meshes of many fractures. A mid node
    is a function of its edge's vertex coordinates only (0.5 (a + b) is the
    same bits either way round), so that a far field meshed alike gets the
    same bits in every call (FarCache) and a divider's mids mirror as its
    vertices do (glue). Mid tags follow gmsh's largest tag, in the order
    the line elements, then the triangles' edges 01, 12, 20 meet them.

    tags (n,), xyz (n, 2): the vertices then the mids; tri (m, 6): the cells."""

    def __init__(self, tri3, lines, tags, xyz, rim=None, mids=None):
        mesh = _gmsh_mesh()
        top = int(tags.max()) + 1 if len(tags) else 1
        pos = np.zeros(top, dtype=np.int64)
        pos[tags] = np.arange(len(tags))
        pairs = np.concatenate([lines, tri3[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)])
        lo, hi = pairs.min(axis=1), pairs.max(axis=1)
        key = lo * top + hi
        uniq, first, inverse = np.unique(key, return_index=True, return_inverse=True)
        seen = np.argsort(first, kind="stable")
        rank = np.empty(len(uniq), dtype=np.int64)
        rank[seen] = np.arange(len(uniq))
        a, b = xyz[pos[lo[first]]], xyz[pos[hi[first]]]
        mid = 0.5 * (a + b)
        self._top, self._key, self._mid_tag = top, uniq, top + rank
        if rim is not None:
            center, radius, curves = rim
            e = self._edge(np.concatenate([np.zeros((0, 2), np.int64)] + [self._lines(mesh, c) for c in curves]))
            d = mid[e] - center
            mid[e] = center + radius * d / np.linalg.norm(d, axis=1)[:, None]
        for curve, at in (mids or {}).items():
            mid[self._edge(self._lines(mesh, curve))] = at
        self.on_line = np.zeros(len(uniq), dtype=bool)
        self.on_line[inverse[: len(lines)]] = True
        self.tags = np.concatenate([tags, top + np.arange(len(uniq), dtype=np.int64)])
        self.xyz = np.concatenate([xyz, mid[seen]])
        m = len(tri3)
        self.tri = np.concatenate([tri3, self._mid_tag[inverse[len(lines):]].reshape(m, 3)], axis=1)

    @staticmethod
    def _lines(mesh, curve) -> np.ndarray:
        return np.asarray(mesh.getElementsByType(1, abs(curve))[1], dtype=np.int64).reshape(-1, 2)

    def _edge(self, pairs) -> np.ndarray:
        return np.searchsorted(self._key, pairs.min(axis=1) * self._top + pairs.max(axis=1))

    def curve(self, curve) -> np.ndarray:
        """(k, 3) [a, b, mid] tags of the curve's line elements, in gmsh's order."""
        pairs = self._lines(_gmsh_mesh(), curve)
        return np.concatenate([pairs, self._mid_tag[self._edge(pairs)][:, None]], axis=1)

    def interior_mids(self) -> np.ndarray:
        """The mid tags of the edges on no curve (inside a surface)."""
        return self._mid_tag[~self.on_line]


def _gmsh_mesh():
    import gmsh  # 0.6 s: loaded by the first mesh (worker.load_gmsh), never by check

    return gmsh.model.mesh


def extract(boundary_curves, crack_curves, tip_point, point_tags, divider=(), far_surfaces=None,
            mids=None, far_cells=None, info=None, rim=None) -> RawMesh:
    """The mesh gmsh made (first order; _P2 adds the mid nodes). tip_point:
    (centre, corner) point tags of each tip,
    corner None for a tip not meshed here (its nodes are -1); point_tags: of
    each bc point, None likewise; divider: curves whose nodes are returned as
    divider_nodes; far_surfaces: the surfaces whose cells are RawMesh.far
    (None: far None; else the far cells come first and the nodes are
    numbered in the order the cells meet them, not in gmsh's tag order);
    mids: {curve: (2,)} the mid node of one-edge curves placed there;
    far_cells: a far field meshed before (FarCache), its surfaces not
    meshed now; info: a dict, given "far_interior" (as FarCache keeps it);
    rim: (center, radius, curves) curves on that circle (rim)."""
    mesh = _gmsh_mesh()
    element_tags, tri = mesh.getElementsByType(2)  # 3-node triangles
    tri = np.asarray(tri, dtype=np.int64).reshape(-1, 3)
    tags, coords, _ = mesh.getNodes(returnParametricCoord=False)
    tags = np.asarray(tags, dtype=np.int64)
    xyz = np.asarray(coords, dtype=np.float64).reshape(-1, 3)[:, :2]
    lines = np.asarray(mesh.getElementsByType(1)[1], dtype=np.int64).reshape(-1, 2)
    p2 = _P2(tri, lines, tags, xyz, rim, mids)
    tri, tags, xyz = p2.tri, p2.tags, p2.xyz
    if far_surfaces is None:
        used, cells = np.unique(tri, return_inverse=True)  # drop unused nodes, compact 0-based
        cells = cells.reshape(-1, 6).astype(np.int64)
        order = np.argsort(tags)
        x = xyz[order][np.searchsorted(tags[order], used)].copy()

        def index(node_tags) -> np.ndarray:
            return np.searchsorted(used, np.asarray(node_tags, dtype=np.int64))
        far = None
    else:
        far_tags = np.concatenate([np.asarray(mesh.getElementsByType(2, s)[0], dtype=np.int64)
                                   for s in far_surfaces])
        far = np.isin(np.asarray(element_tags, dtype=np.int64), far_tags)
        if far_cells is not None:
            tri, far, tags, xyz = FarCache.merge(far_cells, far_surfaces, tri, far, tags, xyz, p2)
        at = _table(tags, np.arange(len(tags)))   # position in xyz by tag
        tri = _canonical_cells(tri, xyz[at[tri[:, :3]]])
        # far cells first (stable), nodes numbered as the cells meet them: the far field's
        # numbering is then the same in every call that meshes it alike, whatever gmsh's tags
        order = np.argsort(~far, kind="stable")
        tri, far = tri[order], far[order]
        flat = tri.ravel()
        uniq, first = np.unique(flat, return_index=True)
        rank = np.empty(len(uniq), dtype=np.int64)
        rank[np.argsort(first)] = np.arange(len(uniq))
        x = xyz[at[flat[np.sort(first)]]].copy()
        rank_of = _table(uniq, rank)

        def index(node_tags) -> np.ndarray:
            return rank_of[np.asarray(node_tags, dtype=np.int64)]
        cells = index(tri)
        if info is not None:
            interior = np.concatenate([np.asarray(mesh.getNodes(2, s, includeBoundary=False)[0], dtype=np.int64)
                                       for s in far_surfaces] + [p2.interior_mids()])
            info["far_interior"] = np.isin(tri[far], interior)

    def curve_edges(curve) -> np.ndarray:
        return index(p2.curve(curve))

    # Counter-clockwise cells: swap v1 <-> v2 and m01 <-> m20 where the area is negative.
    v = x[cells[:, :3]]
    area2 = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
    cells[area2 < 0] = cells[area2 < 0][:, [0, 2, 1, 5, 4, 3]]

    b_edges, b_names = [], []
    for c, name in boundary_curves:
        e = curve_edges(c)
        b_edges.append(e)
        b_names += [name] * len(e)

    c_edges, c_frac = [], []
    for c, f, d in crack_curves:
        e = curve_edges(c)
        backwards = np.einsum("ij,j->i", x[e[:, 1]] - x[e[:, 0]], d) < 0
        e[backwards] = e[backwards][:, [1, 0, 2]]
        e = e[np.argsort(x[e[:, 2]] @ d)]  # in order along d
        c_edges.append(e)
        c_frac += [f] * len(e)

    def point_node(tag) -> int:
        if tag is None:
            return -1
        return int(index(mesh.getNodes(0, tag, returnParametricCoord=False)[0])[0])

    on_divider = [curve_edges(c).ravel() for c in divider]
    return RawMesh(
        x=x,
        cells=cells,
        boundary_edges=np.concatenate(b_edges).astype(np.int64),
        boundary_name=tuple(b_names),
        crack_edges=np.concatenate(c_edges).astype(np.int64) if c_edges else np.zeros((0, 3), np.int64),
        crack_fracture=np.array(c_frac, dtype=np.int64),
        tip_node=np.array([point_node(centre if r0 is not None else None) for centre, r0 in tip_point],
                          dtype=np.int64),
        tip_corner=np.array([point_node(r0) for _, r0 in tip_point], dtype=np.int64),
        point_nodes=np.array([point_node(tag) for tag in point_tags], dtype=np.int64),
        divider_nodes=np.unique(np.concatenate(on_divider)) if on_divider else np.zeros(0, np.int64),
        far=far,
        far_reused=far_cells is not None,
    )


def _table(keys: np.ndarray, values: np.ndarray) -> np.ndarray:
    """A dense lookup table of distinct non-negative int keys: table[k] is
    the value of key k, -1 where k is no key."""
    keys = np.asarray(keys, dtype=np.int64)
    table = np.full(int(keys.max()) + 1 if len(keys) else 0, -1, dtype=np.int64)
    table[keys] = values
    return table


def _canonical_cells(tri, v) -> np.ndarray:
    """P2 cells (m, 6) counter-clockwise and each starting at its lowest
    vertex (by x, then y; v (m, 3, 2) the vertices): which vertex gmsh puts
    first follows its node tags, which differ between a mesh made whole and
    one made with the far field reused (FarCache)."""
    area2 = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
    flip = area2 < 0
    tri, v = tri.copy(), v.copy()
    tri[flip] = tri[flip][:, [0, 2, 1, 5, 4, 3]]
    v[flip] = v[flip][:, [0, 2, 1]]
    k = np.zeros(len(tri), dtype=np.int64)
    for j in (1, 2):
        a, b = v[np.arange(len(v)), k], v[:, j]
        k = np.where((b[:, 0] < a[:, 0]) | ((b[:, 0] == a[:, 0]) & (b[:, 1] < a[:, 1])), j, k)
    turn = np.array([[0, 1, 2, 3, 4, 5], [1, 2, 0, 4, 5, 3], [2, 0, 1, 5, 3, 4]])
    return np.take_along_axis(tri, turn[k], axis=1)
