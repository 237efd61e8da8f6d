"""Point-symmetric meshes (meshing/point_symmetry.py).

Reference: the half turn R(x) = 2c - x. A geometry that R maps onto itself
(domain, fractures, tips) is meshed as one half plus its image, so R maps the
mesh onto itself: every node and every cell has an image within round-off
(gmsh places the divider's second half by the same affine map; 1e-12 of the
domain is ~1e4 ulps of it), tips map onto tips with the same rosette, bc
points onto nodes. A geometry without that symmetry is meshed whole, as
before.
"""
import numpy as np
import pytest
from scipy.spatial import cKDTree

from meshing import Domain, crack_mesh
from meshing.point_symmetry import fracture_images, find_half

ROUND_OFF = 1e-12  # of the domain's size


def mirrored(mesh, c, scale):
    """(node images, cell centroid images) as distances, both (n,)."""
    x = np.asarray(mesh.x)
    d_nodes, _ = cKDTree(x).query(2 * c - x)
    cen = x[mesh.cells].mean(axis=1)
    d_cells, j = cKDTree(cen).query(2 * c - cen)
    assert len(np.unique(j)) == len(cen)  # one-to-one
    return d_nodes.max() / scale, d_cells.max() / scale


def disc_with_wings():
    """The 45-degree disc's crack with two symmetric kinked wings."""
    a = 0.005 / np.sqrt(2)
    wing = np.array([[-a, a], [-a - 0.0004, a + 0.0004], [-a - 0.0006, a + 0.0011]])
    pts = np.concatenate([(-wing)[::-1], wing])
    return Domain("disc", center=[0, 0], radius=0.042), [pts]


def test_disc_with_wings_mesh_mirrors_node_for_node():
    domain, fractures = disc_with_wings()
    points = [np.array(p) for p in ([0, 0.042], [0, -0.042], [-0.042, 0], [0.042, 0])]
    mesh = crack_mesh(domain, fractures, points, 0.004, 0.0005, sectors=32)
    assert mesh.stats["symmetric"]
    assert max(mirrored(mesh, np.zeros(2), 0.084)) < ROUND_OFF
    a, b = mesh.tips
    assert np.allclose(a.x, -b.x, atol=ROUND_OFF * 0.084) and np.allclose(a.ex, -b.ex, atol=1e-12)
    assert a.h == pytest.approx(b.h, rel=1e-12)
    x = np.asarray(mesh.x)
    assert np.allclose(x[mesh.point_nodes], np.array(points), atol=ROUND_OFF * 0.084)
    # the faces: pairs sit on the crack, as many on each half
    assert len(mesh.pairs) % 2 == 1   # the centre's pair is its own image
    assert mesh.stats["min_jacobian"] > 0


def test_rectangle_three_fractures_maps_boundaries_and_points():
    """The paper's 4.3 layout (as in cases/three_fractures_slip.toml): the
    bc points (a corner and a bottom point) are not symmetric; their images
    become nodes too, and bottom edges map onto top edges."""
    domain = Domain("rectangle", corner=[0, 0], size=[7, 6])
    fractures = [np.array(p, float) for p in ([[1, 4], [3, 4]], [[2.5, 3], [4.5, 3]], [[4, 2], [6, 2]])]
    points = [np.array([0.0, 0.0]), np.array([7.0, 0.0])]
    mesh = crack_mesh(domain, fractures, points, 0.4, 0.05, sectors=16)
    c = np.array([3.5, 3.0])
    assert mesh.stats["symmetric"]
    assert max(mirrored(mesh, c, 7.0)) < ROUND_OFF
    assert len(mesh.tips) == 6
    x = np.asarray(mesh.x)
    names = {v: k for k, v in mesh.boundary_names.items()}
    mids = x[mesh.boundary_edges[:, 2]]
    tree = cKDTree(mids)
    d, j = tree.query(2 * c - mids)
    assert d.max() < ROUND_OFF * 7
    swap = {"bottom": "top", "top": "bottom", "left": "right", "right": "left"}
    for k in range(len(mids)):
        assert names[mesh.boundary_tags[j[k]]] == swap[names[mesh.boundary_tags[k]]]
    assert np.allclose(x[mesh.point_nodes], np.array(points))


def test_vertex_at_the_centre_and_fallback():
    domain = Domain("rectangle", corner=[-1, -1], size=[2, 2])
    through = [np.array([[-0.3, -0.1], [0.0, 0.0], [0.3, 0.1]])]
    mesh = crack_mesh(domain, through, [], 0.2, 0.02)
    assert mesh.stats["symmetric"] and max(mirrored(mesh, np.zeros(2), 2.0)) < ROUND_OFF
    off_centre = [np.array([[-0.3, -0.1], [0.31, 0.1]])]
    mesh = crack_mesh(domain, off_centre, [], 0.2, 0.02)
    assert not mesh.stats["symmetric"]


def test_what_counts_as_symmetric():
    c = np.zeros(2)
    one = [np.array([[-1.0, 0.0], [1.0, 0.0]])]
    assert fracture_images(one, c, 1e-12) == [(0, True)]
    two = [np.array([[1.0, 1.0], [2.0, 1.0]]), np.array([[-1.0, -1.0], [-2.0, -1.0]])]
    assert fracture_images(two, c, 1e-12) == [(1, False), (0, False)]
    assert fracture_images([np.array([[1.0, 1.0], [2.0, 1.0]])], c, 1e-12) is None
    # no line through the centre keeps 3 tip sizes from every tip: tips ring the centre
    domain = Domain("disc", center=[0, 0], radius=1.0)
    ring = [np.array([[0.1 * np.cos(t), 0.1 * np.sin(t)], [0.12 * np.cos(t), 0.12 * np.sin(t)]])
            for t in np.linspace(0, 2 * np.pi, 16, endpoint=False)]
    tips = [(p[k], 0.01) for p in ring for k in (0, 1)]
    assert find_half(domain, ring, tips, [], 0.01) is None


def test_size_field_of_a_symmetric_mesh_is_made_symmetric_and_halved():
    """sizes_for_half: the previous step's size field (linear on the previous
    mesh's triangles) becomes min(h(x), h(R x)), exactly, on the triangles
    that reach the meshed half; every vertex on that side stays covered."""
    from meshing.point_symmetry import find_half, rotate, sizes_for_half

    domain, fractures = disc_with_wings()
    mesh = crack_mesh(domain, fractures, [], 0.004, 0.0005, sectors=32)
    x = np.asarray(mesh.x)
    tri = x[mesh.cells[:, :3]]
    vals = 0.001 + 0.01 * (tri[..., 0] + 0.3 * tri[..., 1] + 0.1)   # not symmetric: h(R x) != h(x)
    a, b = (t for t in mesh.tips)
    half = find_half(domain, fractures, [(a.x, a.h), (b.x, b.h)], [], 0.0005)
    kept, sym = sizes_for_half(tri, vals, half, 1e-12)
    # min(h(x), h(-x)) = 0.001 + 0.01 (0.1 - |x + 0.3 y|)
    np.testing.assert_allclose(sym, 0.001 + 0.01 * (0.1 - np.abs(kept[..., 0] + 0.3 * kept[..., 1])), rtol=1e-12)
    assert len(tri) / 2 <= len(kept) < 0.6 * len(tri)
    side = lambda p: half.u[0] * p[..., 1] - half.u[1] * p[..., 0]   # noqa: E731
    on_side = tri[side(tri) > 0]
    covered = {tuple(v) for v in kept.reshape(-1, 2).round(15)}
    assert all(tuple(v) in covered for v in on_side.round(15))
    # a field on triangles that do not mirror is refused (the caller bounds by both)
    assert sizes_for_half(tri[: len(tri) // 3], vals[: len(tri) // 3], half, 1e-12) is None
    assert rotate(np.array([1.0, 2.0]), [0.5, 0.5]).tolist() == [0.0, -1.0]
