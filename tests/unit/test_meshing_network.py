"""meshing: pre-existing fractures that meet (meshing/network.py and the
mesher): X crossings, several fractures through one point, T's on X's,
closed loops, fractures from boundary to boundary.

References computed here by hand: the node copies at a junction are the
sectors between the fracture rays there (4 at an X, 6 where three
fractures cross, 5 where an end meets an X); the pairs there are one per
half-edge, with that fracture's left normal; the cells around a junction
fall into as many components as it has sectors (and into one when the
pairs are glued back); the area of the mesh is the domain's (straight
boundaries: exact); a closed loop cuts the cell graph in two. The search
is checked against brute force over every pair.
"""
from __future__ import annotations

import numpy as np
import pytest
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from meshing import Domain, crack_mesh, network
from test_meshing import p2_area

H = 0.01
DOMAIN = Domain("rectangle", corner=[-0.5, -0.5], size=[1.0, 1.0])


def mesh_of(fractures, **kw):
    return crack_mesh(DOMAIN, [np.asarray(f, float) for f in fractures], [], size=0.1, tip_size=H, **kw)


def nodes_of(fractures) -> np.ndarray:
    """The points where the fractures meet, as the mesher joins them (the
    ends inside the domain free)."""
    free = [(f, e) for f in range(len(fractures)) for e in (0, 1)]
    return network.join([np.asarray(f, float) for f in fractures], free, 1e-9).node_points()


def copies(mesh, p):
    return np.flatnonzero(np.all(mesh.x == np.asarray(p), axis=1))


def components(cells, n_nodes) -> int:
    rows = np.repeat(np.arange(len(cells)), cells.shape[1])
    inc = coo_matrix((np.ones(rows.size), (rows, cells.ravel())), shape=(len(cells), n_nodes))
    return connected_components(inc @ inc.T, directed=False)[0]


def glued(mesh) -> np.ndarray:
    """Node map that identifies every pair's copies (chains settle in a few passes)."""
    g = np.arange(len(mesh.x))
    for _ in range(4):
        for a, b in mesh.pairs:
            r = min(g[a], g[b])
            g[a] = g[b] = r
        g = g[g]
    return g


def left(d):
    d = np.asarray(d, float) / np.linalg.norm(d)
    return np.array([-d[1], d[0]])


def sectors_around(mesh, p, r):
    """(components of the cells within r of p, the same with the pairs glued)."""
    c = mesh.x[mesh.cells[:, :3]].mean(axis=1)
    near = mesh.cells[np.linalg.norm(c - p, axis=1) < r]
    return components(near, len(mesh.x)), components(glued(mesh)[near], len(mesh.x))


A = np.array([[-0.2, 0.013], [0.2, 0.013]])      # horizontal
B = np.array([[-0.06, -0.187], [0.08, 0.213]])   # crosses A at about 70 degrees


def test_an_x_of_two_straight_fractures():
    """Four node copies at the crossing, one per sector; each of the four
    half-edges has its pair there, with its own fracture's left normal; no
    tip at the crossing (four tips at the four ends); the crack edges of each
    fracture run on through it."""
    mesh = mesh_of([A, B])
    x = network.join([A, B], [(0, 0), (0, 1), (1, 0), (1, 1)], 1e-9).polylines[0][1]
    assert abs(x[1] - 0.013) < 1e-15 and np.linalg.norm(x - B[0]) > 0.1   # on both, inside both
    at = copies(mesh, x)
    assert len(at) == 4
    assert sorted((t.fracture, t.end) for t in mesh.tips) == [(0, 0), (0, 1), (1, 0), (1, 1)]
    assert all(np.linalg.norm(t.x - x) > 0.1 for t in mesh.tips)
    here = [p for p, (a, b) in enumerate(mesh.pairs) if a in at]
    assert all(mesh.pairs[p, 1] in at for p in here)
    assert sorted(mesh.pair_fracture[here].tolist()) == [0, 0, 1, 1]
    for p in here:   # one half-edge each side of the crossing: the normal of the fracture's one segment
        f = mesh.pair_fracture[p]
        np.testing.assert_allclose(mesh.pair_normal[p], left([A, B][f][1] - [A, B][f][0]), atol=1e-14)
    assert len({tuple(mesh.pairs[p]) for p in here}) == 4   # four different copy pairs
    # pairs: 2k + 1 nodes on each fracture of k edges, tips excluded, and at the
    # crossing two pairs of each fracture (one per half-edge) where a plain node has one
    k = np.bincount(mesh.crack_fracture, minlength=2)
    assert len(mesh.pairs) == int(np.sum(2 * k + 1)) - len(mesh.tips) + 2
    for f in (0, 1):   # edges in order along f, through the crossing (an edge ends and one starts there)
        e = mesh.crack_edges[mesh.crack_fracture == f]
        np.testing.assert_array_equal(mesh.x[e[1:, 0]], mesh.x[e[:-1, 1]])
        assert np.any(np.all(mesh.x[e[:, 0]] == x, axis=1)) and np.any(np.all(mesh.x[e[:, 1]] == x, axis=1))
    assert sectors_around(mesh, x, 2 * H) == (4, 1)
    assert p2_area(mesh.x, mesh.cells) == pytest.approx(1.0, rel=1e-12)


def test_three_fractures_through_one_point():
    """Six rays: six copies; a T whose end is on an X: five."""
    c = np.array([0.0, 0.013])
    star = [c + 0.2 * np.array([[-np.cos(a), -np.sin(a)], [np.cos(a), np.sin(a)]]) for a in np.radians([0, 60, 120])]
    mesh = mesh_of(star)
    (x,) = nodes_of(star)   # the three crossings, computed each from its pair, are one point
    assert np.linalg.norm(x - c) < 1e-15
    assert len(copies(mesh, x)) == 6 and len(mesh.tips) == 6
    assert sectors_around(mesh, x, 2 * H) == (6, 1)
    t_on_x = star[:2] + [np.array([c + [0.05, -0.2], c])]   # ends on the X, between its rays
    mesh = mesh_of(t_on_x)
    (x,) = nodes_of(t_on_x)
    assert len(copies(mesh, x)) == 5
    assert sorted((t.fracture, t.end) for t in mesh.tips) == [(0, 0), (0, 1), (1, 0), (1, 1), (2, 0)]


def test_an_x_on_a_kink_and_a_t_plus_x_network():
    """A fracture crossing another at the other's kink vertex: inserted into
    the straight one only, four copies; a network of a T and an X on one
    host: three and four copies."""
    kinked = np.array([[-0.3, 0.013], [0.0, 0.013], [0.3, 0.1]])
    mesh = mesh_of([kinked, np.array([[0.0, -0.25], [0.0, 0.25]])])
    assert len(copies(mesh, kinked[1])) == 4 and len(mesh.tips) == 4
    host = np.array([[-0.3, 0.0], [0.3, 0.0]])
    mesh = mesh_of([host, np.array([[0.1, -0.2], [0.1, 0.2]]), np.array([[-0.1, 0.25], [-0.1, 0.0]])])
    assert len(copies(mesh, [0.1, 0.0])) == 4 and len(copies(mesh, [-0.1, 0.0])) == 3
    assert sorted((t.fracture, t.end) for t in mesh.tips) == [(0, 0), (0, 1), (1, 0), (1, 1), (2, 0)]


@pytest.mark.parametrize("loop", ["three fractures", "one polyline"])
def test_a_closed_loop(loop):
    """A triangle of fractures met end to end (or one polyline closed on
    itself): no tips, two copies at each corner, and the cells fall into
    two pieces, inside and outside (the pairs glue them into one)."""
    p = np.array([[-0.2, -0.1], [0.2, -0.1], [0.0, 0.25]])
    fractures = [np.array([p[i], p[(i + 1) % 3]]) for i in range(3)] if loop == "three fractures" \
        else [np.array([p[0], p[1], p[2], p[0]])]
    mesh = mesh_of(fractures)
    assert mesh.tips == []
    for q in p:
        assert len(copies(mesh, q)) == 2
    assert components(mesh.cells, len(mesh.x)) == 2
    assert components(glued(mesh)[mesh.cells], len(mesh.x)) == 1
    assert p2_area(mesh.x, mesh.cells) == pytest.approx(1.0, rel=1e-12)


def test_a_fracture_from_boundary_to_boundary_crossing_another():
    """Both mouths split in two (one copy ends each boundary edge there), the
    crossing in four; the body is cut in two pieces."""
    through, other = np.array([[-0.5, 0.1], [0.5, -0.1]]), np.array([[0.1, -0.3], [-0.05, 0.3]])
    mesh = mesh_of([through, other])
    for mouth in through:   # projected onto the boundary by the mesher: within round-off
        at = np.flatnonzero(np.linalg.norm(mesh.x - mouth, axis=1) < 1e-15)
        assert len(at) == 2 and len(np.intersect1d(at, mesh.boundary_edges[:, :2])) == 2
    x = network.join([through, other], [(1, 0), (1, 1)], 1e-9, mouths=[(0, 0), (0, 1)]).polylines[0][1]
    assert len(copies(mesh, x)) == 4
    assert sorted((t.fracture, t.end) for t in mesh.tips) == [(1, 0), (1, 1)]
    assert components(mesh.cells, len(mesh.x)) == 2


def test_a_point_symmetric_x_is_meshed_point_symmetrically():
    """Two straight fractures crossing at the plate's centre: the divider
    runs through the crossing, and the mesh is its own half-turn image."""
    domain = Domain("rectangle", corner=[-0.5, -0.5], size=[1.0, 1.0])
    fr = [np.array([[-0.2, 0.0], [0.2, 0.0]]), np.array([[-0.1, -0.2], [0.1, 0.2]])]
    mesh = crack_mesh(domain, fr, [], size=0.1, tip_size=H)
    assert mesh.stats["symmetric"]
    assert len(copies(mesh, [0.0, 0.0])) == 4
    # every node has an image within round-off (gmsh places the divider's
    # second half by an affine map: 1e-12 of the domain, as test_meshing_symmetry)
    from test_meshing_symmetry import ROUND_OFF, mirrored

    assert max(mirrored(mesh, np.zeros(2), 1.0)) < ROUND_OFF


# ---------------------------------------------------------------- network.join itself


def test_join_gives_a_crossing_the_same_bits_in_both_polylines():
    net = network.join([A, B], [(0, 0), (0, 1), (1, 0), (1, 1)], 1e-9)
    a, b = net.polylines
    assert len(a) == len(b) == 3 and np.array_equal(a[1], b[1])
    assert net.junction == {} and net.partner == {}
    assert list(net.nodes.values()) == [[(0, 1), (1, 1)]]
    np.testing.assert_array_equal(a[[0, 2]], A)   # the given points untouched
    np.testing.assert_array_equal(b[[0, 2]], B)


def test_join_reports_overlaps_and_mouths():
    a = np.array([[0.0, 0.0], [1.0, 0.0]])
    net = network.join([a, np.array([[0.5, 0.0], [1.5, 0.0]])], [(0, 0), (0, 1), (1, 0), (1, 1)], 1e-9)
    assert [(f, g) for f, g, _, _ in net.overlaps] == [(0, 1)]
    _, _, p, q = net.overlaps[0]
    assert sorted([p[0], q[0]]) == [0.5, 1.0]
    net = network.join([a, np.array([[0.0, 0.0], [0.3, 0.5]])], [(0, 1), (1, 1)], 1e-9,
                       mouths=[(0, 0), (1, 0)])
    assert {(f, e) for f, e, _ in net.mouths} == {(0, 0), (1, 0)}


def test_the_search_finds_every_near_pair():
    """near_segment_pairs and segments_near_points against brute force on
    random segments of lengths over two decades (a superset: every pair
    within pad is among them)."""
    rng = np.random.default_rng(3)
    n = 400
    c = rng.uniform(0, 1, (n, 2))
    L = np.exp(rng.uniform(np.log(0.005), np.log(0.5), n))
    phi = rng.uniform(0, np.pi, n)
    a = c - 0.5 * L[:, None] * np.stack([np.cos(phi), np.sin(phi)], 1)
    b = c + 0.5 * L[:, None] * np.stack([np.cos(phi), np.sin(phi)], 1)
    pad = 0.01

    def to_segments(p, s0, s1):   # (len(p), len(s0)) point-segment distances, by hand
        ab = s1 - s0
        t = np.clip(np.einsum("pqk,qk->pq", p[:, None] - s0[None], ab) / np.einsum("qk,qk->q", ab, ab), 0, 1)
        return np.linalg.norm(p[:, None] - s0[None] - t[..., None] * ab[None], axis=2)

    def cross(u, v):
        return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]

    r = b - a
    qp = a[None] - a[:, None]                         # a_j - a_i
    den = cross(r[:, None], r[None])
    with np.errstate(divide="ignore", invalid="ignore"):
        t, u = cross(qp, r[None]) / den, cross(qp, r[:, None]) / den
    crossing = (t >= 0) & (t <= 1) & (u >= 0) & (u <= 1)
    ends = np.minimum.reduce([to_segments(a, a, b), to_segments(b, a, b), to_segments(a, a, b).T,
                              to_segments(b, a, b).T])
    dist = np.where(crossing, 0.0, ends)
    truth = {(i, j) for i, j in zip(*np.nonzero(np.triu(dist <= pad, 1)))}
    i, j = network.near_segment_pairs(a, b, pad)
    found = set(zip(i.tolist(), j.tolist()))
    assert truth <= found and len(truth) > 100
    p = rng.uniform(0, 1, (300, 2))
    rad = rng.uniform(0, 0.05, 300)
    truth = set(zip(*np.nonzero(to_segments(p, a, b) <= rad[:, None])))
    pt, sg = network.segments_near_points(p, rad, a, b)
    assert truth <= set(zip(pt.tolist(), sg.tolist())) and len(truth) > 100
