"""The far field of the patch kept from the last call (FarCache), and glued
into a mesh whose far field is the same."""

from __future__ import annotations

import hashlib
import pickle

import numpy as np


class CacheMiss(RuntimeError):
    """A cached far field that does not fit the mesh made around it."""


class FarCache:
    """The far field this process meshed last (in the meshing worker: across
    calls), so that a call whose far field is the same does not mesh it
    again: its surfaces are hidden from gmsh (Mesh.MeshOnlyVisible; their
    boundary curves are still meshed, alike), and its cells are taken from
    here, glued by their nodes on those curves, which carry the same bits
    (tests/unit/test_meshing_patch.py: the mesh is then bitwise the one that
    meshing it gives). Only the last far field is kept: a propagation
    loop's far field changes seldom and is large."""

    _last: tuple | None = None

    @staticmethod
    def key(domain, plan, inside, circle, half, size, tip_size, sectors, sizes, mirror_sizes, algorithm) -> bytes:
        """A digest of everything the far field's mesh depends on: the domain,
        the anchors, the fractures and tips outside the circle (by their
        place among those outside), the circle, the outer divider, the
        sizes and the size field, the algorithm."""
        group = [f for f, i in enumerate(inside) if not i]
        where = {f: k for k, f in enumerate(group)}

        def b(a) -> bytes:
            return np.ascontiguousarray(a, dtype=np.float64).tobytes()

        parts = (
            domain.shape, b(domain.center) if domain.shape == "disc" else b(domain.vertices()),
            float(domain.radius) if domain.shape == "disc" else 0.0,
            [(e, float(t), b(p)) for e, t, p in plan.anchors],
            [b(plan.fractures[f]) for f in group],
            sorted((where[f], end, a) for (f, end), a in plan.mouth_anchor.items() if f in where),
            sorted((where[f], end, where.get(g, -1), v) for (f, end), (g, v) in plan.junction.items() if f in where),
            [(where[t.fracture], t.end, b(t.x), b(t.back), float(t.h)) for t in plan.tips if t.fracture in where],
            b(circle.center), float(circle.radius), b(circle.points), b(circle.mids),
            None if half is None else (b(half.center), b(half.u), b(half.points), half.k_out),
            float(size), float(tip_size), int(sectors), bool(mirror_sizes), int(algorithm),
            None if sizes is None else (b(sizes[0]), b(sizes[1])),
        )
        return hashlib.sha256(pickle.dumps(parts)).digest()

    @classmethod
    def get(cls, key):
        return cls._last[1] if cls._last is not None and cls._last[0] == key else None

    @classmethod
    def put(cls, key, cells, interior) -> None:
        cls._last = (key, (np.array(cells, dtype=np.float64), np.array(interior, dtype=bool)))
        cls._nodes = None

    @classmethod
    def clear(cls) -> None:
        cls._last = cls._nodes = None

    @staticmethod
    def merge(cached, far_surfaces, tri, far, tags, xyz, p2):
        """gmsh's cells (tri (m, 6) node tags; none of them far; p2 the p2_readback._P2
        that numbered their mid nodes) with the cached
        far cells in front: a cached node on the far field's boundary is
        gmsh's node of the same coordinates (same bits), a cached interior
        node a new tag. Raises CacheMiss when a boundary node has no match."""
        import gmsh  # 0.6 s: loaded by the first mesh (worker.load_gmsh), never by check

        cells, interior = cached
        if far.any():
            raise CacheMiss("the far surfaces were meshed")
        inner_first, inner_fresh, boundary, boundary_of = FarCache._nodes_of(cells, interior)
        on = set()
        for _, tag in gmsh.model.getBoundary([(2, s) for s in far_surfaces], combined=False, oriented=False):
            on.add(abs(tag))
        for s in far_surfaces:  # the fractures outside, embedded in the far surface
            on.update(abs(t) for dim, t in gmsh.model.mesh.getEmbedded(2, s) if dim == 1)
        on_tags = np.unique(np.concatenate([np.zeros(0, np.int64)] + [p2.curve(curve).ravel()
                                                                      for curve in sorted(on)]))
        by_tag = np.argsort(tags)
        known, first = np.unique(_bits(xyz[by_tag[np.searchsorted(tags[by_tag], on_tags)]]), return_index=True)
        known_tag = on_tags[first]
        flat, inner = cells.reshape(-1, 2), interior.ravel()
        out = np.empty(len(flat), dtype=np.int64)
        j = np.minimum(np.searchsorted(known, boundary), max(len(known) - 1, 0))
        if len(boundary) and (not len(known) or np.any(known[j] != boundary)):
            raise CacheMiss("a node of the far field's boundary is not in the mesh")
        out[~inner] = known_tag[j][boundary_of]
        top = int(tags.max()) + 1 if len(tags) else 1
        out[inner] = top + inner_fresh
        tri = np.concatenate([out.reshape(-1, 6), tri])
        far = np.concatenate([np.ones(len(cells), dtype=bool), far])
        tags = np.concatenate([tags, np.arange(top, top + len(inner_first), dtype=np.int64)])
        xyz = np.concatenate([xyz, flat[inner][inner_first]])
        return tri, far, tags, xyz

    _nodes = None   # (cells, interior, their _nodes_of): the last cached far field's

    @classmethod
    def _nodes_of(cls, cells, interior):
        """The node structure of a cached far field (cells (m, 6, 2) places,
        interior (m, 6) its nodes off the boundary), the same in every call
        it is glued in, so worked out once: (first, fresh) of its interior
        nodes (np.unique of their places' bits: the first occurrence of each,
        the index of each occurrence's node), (boundary, of) of its boundary
        nodes (their places' bits sorted unique, and the index in those of
        each occurrence)."""
        last = cls._nodes
        if last is not None and last[0] is cells and last[1] is interior:
            return last[2]
        flat, inner = cells.reshape(-1, 2), interior.ravel()
        _, first, fresh = np.unique(_bits(flat[inner]), return_index=True, return_inverse=True)
        boundary, of = np.unique(_bits(flat[~inner]), return_inverse=True)
        out = (first, fresh.ravel(), boundary, of.ravel())
        cls._nodes = (cells, interior, out)
        return out


def _bits(a) -> np.ndarray:
    """(n, 2) float64 rows as (n,) keys that compare and sort by their bits."""
    return np.ascontiguousarray(a, dtype=np.float64).view(np.dtype((np.void, 16))).ravel()
