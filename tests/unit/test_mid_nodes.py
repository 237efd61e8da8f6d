"""The mesher's own mid nodes (p2_readback._P2) against gmsh's setOrder(2).

gmsh meshes first order; _P2 adds a mid node on every edge. The reference
is gmsh's own second-order mesh of the same session: after p2_readback.extract has
read the first-order mesh back, the test calls gmsh.model.mesh.setOrder(2)
and compares. setOrder leaves the vertices where they are, so both meshes
must have the same vertices (bit for bit) and the same cells; each mid node
must be gmsh's up to round-off on straight edges; on the disc rim and the
patch circle's one-edge arcs the arc's middle, which gmsh finds to
GMSH_ARC of the edge only; and no edge may have two mid nodes (the node
counts equal).

Checked on the first mesh of every case in cases/ (as a run meshes it:
the case's domain, fractures, bc points and sizes), a patched plate, a
patched point-symmetric disc and a point-symmetric disc (the half gmsh
meshes, before glue mirrors it).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from meshing import Domain, crack_mesh, far_cache, gmsh_geometry
from meshing import patch as patch_module
from wingcrack.case import Case

CASES = sorted((Path(__file__).resolve().parents[2] / "cases").glob("*.toml"))
# On a straight edge both compute the same point in float64 from the same
# vertex bits (gmsh through the curve's or the plane's parametrisation, here
# 0.5 (a + b)): they differed by up to 1.3e-13 of the domain's size; 1e-12
# is tests/unit/test_meshing_symmetry.py's round-off.
ROUND_OFF = 1e-12
# gmsh's setOrder puts a curved edge's mid node at equal arc lengths from
# its ends by a Newton iteration that stops at a relative 1e-6
# (computeEquidistantParameters in gmsh's Mesh/HighOrder.cpp, PRECISION),
# not exactly: on the disc rim its mids were up to 2.7e-10 of the radius
# nearer one end than the other (ours, on the bisector, 3e-16) and up to
# 3.8e-8 of their edge's length from ours. So a curved edge's mid must be
# gmsh's to 1e-6 of its edge and the arc's middle (as far from both ends) to round-off.
GMSH_ARC = 1e-6


def _bits(a) -> np.ndarray:
    return np.ascontiguousarray(a, dtype=np.float64).view(np.dtype((np.void, 16))).ravel()


def _gmsh_p2():
    """gmsh's second-order mesh of the current model: node coordinates by
    tag, 6-node triangles, 3-node lines."""
    import gmsh

    gmsh.model.mesh.setOrder(2)
    tags, coords, _ = gmsh.model.mesh.getNodes(returnParametricCoord=False)
    xyz = np.zeros((int(np.max(tags)) + 1, 2))
    xyz[np.asarray(tags, dtype=np.int64)] = np.asarray(coords).reshape(-1, 3)[:, :2]
    tri = np.asarray(gmsh.model.mesh.getElementsByType(9)[1], dtype=np.int64).reshape(-1, 6)
    lines = np.asarray(gmsh.model.mesh.getElementsByType(8)[1], dtype=np.int64).reshape(-1, 3)
    return xyz, tri, lines


class Reference:
    """Wraps p2_readback.extract: every mesh read back is compared with
    gmsh's setOrder(2) of the same session."""

    def __init__(self):
        self.original = gmsh_geometry.extract
        self.meshes: list[dict] = []

    def __call__(self, *args, **kwargs):
        raw = self.original(*args, **kwargs)
        self.meshes.append(compare(raw, *_gmsh_p2()))
        return raw


def compare(raw, xyz, tri, lines) -> dict:
    del lines  # every line element's edge is a cell's: the cells' edges cover them
    x, cells = raw.x, raw.cells
    scale = float(np.max(x.max(axis=0) - x.min(axis=0)))
    # the vertex table: gmsh's vertices by their bits
    verts, vert_of_tag = np.unique(_bits(xyz[tri[:, :3]].reshape(-1, 2)), return_inverse=True)
    vert_of_tag = vert_of_tag.reshape(-1, 3)

    def vertex(rows) -> np.ndarray:
        b = _bits(x[rows])
        k = np.minimum(np.searchsorted(verts, b), len(verts) - 1)
        assert np.all(verts[k] == b), "a vertex that is not gmsh's"
        return k

    def edge_keys(v) -> np.ndarray:
        return np.minimum(v[..., 0], v[..., 1]) * len(verts) + np.maximum(v[..., 0], v[..., 1])

    turn = [[0, 1], [1, 2], [2, 0]]
    ref_keys = edge_keys(vert_of_tag[:, turn])  # (m, 3): edges 01, 12, 20
    ref_key, first = np.unique(ref_keys.ravel(), return_index=True)
    ref_mid = xyz[tri[:, 3:].ravel()[first]]

    # the same cells (as vertex sets)
    v = vertex(cells[:, :3].ravel()).reshape(-1, 3)
    assert len(v) == len(tri)
    assert np.array_equal(np.unique(np.sort(v, axis=1), axis=0), np.unique(np.sort(vert_of_tag, axis=1), axis=0))

    # every edge's mid node (cells', boundary's, cracks') where gmsh put it, one node an edge
    edges = [(edge_keys(v[:, turn]).ravel(), cells[:, 3:].ravel())]
    for e in (raw.boundary_edges, raw.crack_edges):
        edges.append((edge_keys(vertex(e[:, :2].ravel()).reshape(-1, 2)), e[:, 2]))
    key = np.concatenate([k for k, _ in edges])
    mid = np.concatenate([m for _, m in edges])
    j = np.searchsorted(ref_key, key)
    assert np.all(ref_key[np.minimum(j, len(ref_key) - 1)] == key), "an edge that is not gmsh's"
    a, b = raw_ends(raw, cells)
    off = np.linalg.norm(x[mid] - ref_mid[j], axis=1) / scale
    # gmsh's straight edges' mids are on their chords to round-off; a curved one's is not
    curved = np.linalg.norm(ref_mid[j] - 0.5 * (x[a] + x[b]), axis=1) / scale > ROUND_OFF
    err = float(np.max(off[~curved]))
    assert err <= ROUND_OFF, f"straight edges' mid nodes off gmsh's by {err:.3g} of the domain"
    if curved.any():
        edge = np.linalg.norm(x[a] - x[b], axis=1) / scale
        arc = float(np.max(off[curved] / edge[curved]))
        assert arc <= GMSH_ARC, f"curved edges' mid nodes off gmsh's by {arc:.3g} of their length"
        # the middle of a circle arc is as far from both ends, to round-off
        skew = np.abs(np.linalg.norm(x[mid] - x[a], axis=1) - np.linalg.norm(x[mid] - x[b], axis=1)) / scale
        assert float(np.max(skew[curved])) <= ROUND_OFF
    uk, first = np.unique(key, return_index=True)
    assert np.array_equal(mid, mid[first][np.searchsorted(uk, key)]), "an edge with two mid nodes"
    assert len(np.unique(cells)) == len(np.unique(tri)), "not gmsh's node count"
    sagitta = np.linalg.norm(x[mid] - 0.5 * (x[a] + x[b]), axis=1)  # how far mids are off their chords
    return {"error": err, "cells": len(cells), "curved": float(sagitta.max()) / scale}


def raw_ends(raw, cells):
    """The two vertex rows of every edge: the cells' (01, 12, 20), then the boundary's and the cracks'."""
    a = [cells[:, [0, 1, 2]].ravel(), raw.boundary_edges[:, 0], raw.crack_edges[:, 0]]
    b = [cells[:, [1, 2, 0]].ravel(), raw.boundary_edges[:, 1], raw.crack_edges[:, 1]]
    return np.concatenate(a), np.concatenate(b)


@pytest.fixture
def reference(monkeypatch):
    ref = Reference()
    # where extract is looked up: the whole domain's meshing and the patched one's
    monkeypatch.setattr(gmsh_geometry, "extract", ref)
    monkeypatch.setattr(patch_module, "extract", ref)
    far_cache.FarCache.clear()  # every far field meshed: gmsh's setOrder then sees all cells
    yield ref
    far_cache.FarCache.clear()


@pytest.mark.parametrize("path", CASES, ids=lambda p: p.stem)
def test_first_mesh_of_each_case(path, reference):
    case = Case.from_toml(path)
    m = case.mesh
    crack_mesh(case.domain, [np.asarray(f.points, float) for f in case.fractures], case.bc_points(), m.size, m.tip_size,
               sectors=m.sectors)
    (one,) = reference.meshes
    if case.domain.shape == "disc":
        # the rim's mids are off the chords by far more than the tolerance: the
        # comparison sees where a curved edge's mid goes
        assert one["curved"] > 1e3 * ROUND_OFF


R = 0.042
DISC = Domain("disc", center=[0.0, 0.0], radius=R)
DISC_POINTS = [np.array(p, float) for p in ([0, R], [0, -R], [-R, 0], [R, 0])]


def crack(phi_deg, half, at=(0.0, 0.0)):
    d = half * np.array([np.cos(np.radians(phi_deg)), np.sin(np.radians(phi_deg))])
    return np.array([np.asarray(at) + d, np.asarray(at) - d])


def test_patched_rectangle(reference):
    """A patch circle in a plate (as tests/unit/test_meshing_patch.py's), one
    fracture inside, one outside: the circle's one-edge arcs get
    patch.Circle.mids, which must be gmsh's arc middles too."""
    rect = Domain("rectangle", corner=[0.0, 0.0], size=[0.1, 0.06])
    points = [np.array([0.05, 0.0]), np.array([0.0, 0.0]), np.array([0.1, 0.06])]
    patch = (np.array([0.066, 0.033]), 0.016)
    outside = np.array([[0.015, 0.02], [0.03, 0.026]])
    mesh = crack_mesh(rect, [crack(10, 0.003, patch[0]), outside], points, size=0.002, tip_size=0.0005,
                      sectors=16, patch=patch)
    assert mesh.far is not None and mesh.far.any() and not mesh.far.all()
    assert not mesh.stats["symmetric"]
    (one,) = reference.meshes
    assert one["curved"] > 1e3 * ROUND_OFF  # the arcs' mids are off their chords


def test_patched_symmetric_disc(reference):
    """A centred crack in the disc with a centred patch: the half meshed,
    with the rim and the patch circle."""
    mesh = crack_mesh(DISC, [crack(135, 0.005)], DISC_POINTS, size=0.002, tip_size=0.0005, sectors=32,
                      patch=(np.zeros(2), 0.02))
    assert mesh.stats["symmetric"] and mesh.far is not None and mesh.far.any()
    (one,) = reference.meshes
    assert one["curved"] > 1e3 * ROUND_OFF


def test_symmetric_disc(reference):
    """A centred crack in the disc: meshed point-symmetrically (gmsh meshes
    the half, the divider's mids too)."""
    d = 0.005 * np.array([np.cos(0.7), np.sin(0.7)])
    mesh = crack_mesh(DISC, [np.array([-d, d])], DISC_POINTS, size=0.003, tip_size=0.0006, sectors=16)
    assert mesh.stats["symmetric"]
    (one,) = reference.meshes
    assert one["curved"] > 1e3 * ROUND_OFF
