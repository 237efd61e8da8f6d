"""The patch circle of crack_mesh (`patch`; meshing/patch.py).

What it is for: the far field's stiffness is factorised once and condensed
onto the circle, so the cells outside it must come out the same, bit for
bit, in every call whose geometry outside the circle is the same, whatever
the fractures inside. The reference of each identity test is therefore the
other call's far field, compared with no tolerance (as raw float64 bits):
cells as sorted rows of their 6 nodes' coordinates (node numbering may
differ), the outer boundary's edges with their tags, the bc points' nodes.
A control (test_a_tip_within_reach_changes_the_far_field) shows that the
comparison does see a change when a tip comes nearer the circle than the
rule allows.

Validity of a patched mesh against independent references: the far flags
against the cells' centroids and the circle, min det J > 0, a symmetric
geometry's mesh against its half-turn image (as tests/unit/test_meshing_symmetry.py),
and the tips, rosettes and face pairs against the mesh of the same geometry
without a patch. A patch that does not fit is ignored: the mesh is then
the one without a patch, array for array.

The mesher keeps the last far field it meshed and does not mesh it again
when a call's far field is the same (far_cache.FarCache). The identity
tests switch that off (every call meshes its far field: they compare two
meshings, not a cache with itself); the reuse tests compare the mesh made
with a reused far field against the one made meshing it, every array
bit for bit.
"""

import numpy as np
import pytest
from scipy.spatial import cKDTree

from meshing import Domain, crack_mesh
from meshing import far_cache
from meshing import clearance as clearance_module
from meshing.mesher import triangle_quality

R = 0.042
DISC = Domain("disc", center=[0.0, 0.0], radius=R)
DISC_POINTS = [np.array(p, float) for p in ([0, R], [0, -R], [-R, 0], [R, 0])]
# size 2 mm, tip 0.5 mm: a tip must stay 10.8 mm off the circle (meshing.clearance.clearance_of)
DISC_MESH = dict(size=0.002, tip_size=0.0005, sectors=32)
DISC_PATCH = (np.zeros(2), 0.02)

RECT = Domain("rectangle", corner=[0.0, 0.0], size=[0.1, 0.06])
RECT_POINTS = [np.array([0.05, 0.0]), np.array([0.0, 0.0]), np.array([0.1, 0.06])]
RECT_MESH = dict(size=0.002, tip_size=0.0005, sectors=16)
RECT_PATCH = (np.array([0.066, 0.033]), 0.016)
OUTSIDE = np.array([[0.015, 0.02], [0.03, 0.026]])  # a fracture wholly outside RECT_PATCH

ROUND_OFF = 1e-12  # of the domain's size, as tests/unit/test_meshing_symmetry.py


@pytest.fixture(autouse=True)
def mesh_every_far_field(request, monkeypatch):
    """No far field reused, but in the tests of the reuse (test_reuse_*)."""
    far_cache.FarCache.clear()
    if not request.function.__name__.startswith("test_reuse"):
        monkeypatch.setattr(far_cache.FarCache, "get", classmethod(lambda cls, key: None))
    yield
    far_cache.FarCache.clear()


def crack(phi_deg, half=0.005, at=(0.0, 0.0)):
    d = half * np.array([np.cos(np.radians(phi_deg)), np.sin(np.radians(phi_deg))])
    return np.array([np.asarray(at) + d, np.asarray(at) - d])


def winged(phi_deg, wing, kink_deg=-70.0, half=0.005):
    """The crack at phi with a kinked wing of length `wing` at each tip (two
    segments), point-symmetric about the centre."""
    tip = crack(phi_deg, half)[0]
    d1 = np.array([np.cos(np.radians(phi_deg + kink_deg)), np.sin(np.radians(phi_deg + kink_deg))])
    d2 = np.array([np.cos(np.radians(phi_deg + 0.8 * kink_deg)), np.sin(np.radians(phi_deg + 0.8 * kink_deg))])
    w = np.array([tip, tip + 0.5 * wing * d1, tip + 0.5 * wing * (d1 + d2)])
    return np.concatenate([(-w)[::-1], w])


def bits(a) -> np.ndarray:
    return np.ascontiguousarray(a, dtype=np.float64).view(np.uint64)


def far_field(mesh):
    """(far cells, outer boundary, bc points) as raw bits, in an order of their own."""
    cells = bits(mesh.x[mesh.cells[mesh.far]].reshape(-1, 12))
    cells = cells[np.lexsort(cells.T[::-1])]
    edges = np.concatenate([bits(mesh.x[mesh.boundary_edges].reshape(-1, 6)),
                            mesh.boundary_tags[:, None].astype(np.uint64)], axis=1)
    edges = edges[np.lexsort(edges.T[::-1])]
    return cells, edges, bits(mesh.x[mesh.point_nodes])


def assert_same_far_field(a, b):
    assert a.stats["patch"] and b.stats["patch"]
    assert not a.stats["far_reused"] and not b.stats["far_reused"]
    for what, p, q in zip(("far cells", "boundary edges", "bc points"), far_field(a), far_field(b)):
        assert p.shape == q.shape, what
        assert np.array_equal(p, q), what


def assert_valid(mesh, patch):
    c, r = np.asarray(patch[0], float), patch[1]
    assert mesh.stats["patch"] and mesh.far is not None and mesh.far.dtype == bool
    assert mesh.far.shape == (len(mesh.cells),)
    centroid = mesh.x[mesh.cells[:, :3]].mean(axis=1)
    outside = np.linalg.norm(centroid - c, axis=1) > r
    assert np.array_equal(mesh.far, outside)
    assert 0 < mesh.far.sum() < len(mesh.far)
    assert mesh.stats["min_jacobian"] > 0
    # the circle is a curve of the mesh: the nodes that far and near cells share lie on it
    shared = np.intersect1d(mesh.cells[mesh.far].ravel(), mesh.cells[~mesh.far].ravel())
    assert len(shared) >= 16
    assert np.allclose(np.linalg.norm(mesh.x[shared] - c, axis=1), r, rtol=1e-12)
    # the circle's fixed nodes leave the cells on it as good as the unstructured cells elsewhere
    # (4 sqrt(3) area / sum of squared edges, 1 equilateral): without a patch those go down to 0.9 in
    # these tests' uniform fields, to 0.77 in the graded RECT sizes; a circle whose spacing fitted the
    # field nowhere gave 0.6
    on = np.isin(mesh.cells[:, :3], shared).any(axis=1)
    assert triangle_quality(mesh.x, mesh.cells[on]).min() > 0.7


def assert_point_symmetric(mesh, scale):
    x = mesh.x
    d_nodes, _ = cKDTree(x).query(-x)
    cen = x[mesh.cells].mean(axis=1)
    d_cells, j = cKDTree(cen).query(-cen)
    assert len(np.unique(j)) == len(cen)
    assert max(d_nodes.max(), d_cells.max()) / scale < ROUND_OFF
    assert np.array_equal(mesh.far, mesh.far[j])  # the image of a far cell is far


def assert_same_tips(mesh, plain, sectors):
    """Tips, rosettes and face pairs as without the patch: the same tips at
    the same points with the same rosette radius, `sectors` cells at each,
    the quarter points at h/4, the pairs' copies on top of each other."""
    assert len(mesh.tips) == len(plain.tips)
    for t, s in zip(mesh.tips, plain.tips):
        assert (t.fracture, t.end) == (s.fracture, s.end)
        assert np.array_equal(t.x, s.x) and t.h == s.h and np.array_equal(t.ex, s.ex)
        assert np.count_nonzero(np.any(mesh.cells[:, :3] == t.node, axis=1)) == sectors
        for quarter, corner in (t.upper, t.lower):
            assert np.linalg.norm(mesh.x[corner] - t.x) == pytest.approx(t.h, rel=1e-12)
            assert np.linalg.norm(mesh.x[quarter] - t.x) == pytest.approx(t.h / 4, rel=1e-9)
    assert np.array_equal(np.unique(mesh.pair_fracture), np.unique(plain.pair_fracture))
    assert np.max(np.linalg.norm(mesh.x[mesh.pairs[:, 0]] - mesh.x[mesh.pairs[:, 1]], axis=1)) == 0.0
    # as many pairs to the crack length as without the patch (the same size field along the cracks)
    for f in np.unique(plain.pair_fracture):
        n, m = np.count_nonzero(mesh.pair_fracture == f), np.count_nonzero(plain.pair_fracture == f)
        assert abs(n - m) <= 0.1 * m


# -- the far field is the same --------------------------------------------------------


DISC_PAIRS = {
    "longer crack": ([crack(135)], [crack(135, half=0.0065)]),
    "other angle": ([crack(135)], [crack(30)]),
    "wings": ([crack(135)], [winged(135, 0.0012)]),
    "wings of other lengths": ([winged(135, 0.0006)], [winged(135, 0.002)]),
}


@pytest.mark.parametrize("name", list(DISC_PAIRS))
def test_disc_far_field_is_the_same_whatever_the_crack_inside(name):
    first, second = (crack_mesh(DISC, f, DISC_POINTS, **DISC_MESH, patch=DISC_PATCH) for f in DISC_PAIRS[name])
    for m in (first, second):
        assert m.stats["symmetric"]  # the patch with the half-meshing, not instead of it
        assert_valid(m, DISC_PATCH)
        assert_point_symmetric(m, 2 * R)
    assert first.stats["divider_angle"] == second.stats["divider_angle"]
    assert_same_far_field(first, second)


def test_disc_inner_divider_follows_the_crack_and_the_far_field_does_not():
    """A crack that turns makes the divider inside the circle turn with it
    (it must keep off the tips and cross at a good angle); the outer one and
    the far field stay."""
    meshes = [crack_mesh(DISC, [crack(phi)], DISC_POINTS, **DISC_MESH, patch=DISC_PATCH) for phi in (135, 60, 0.3)]
    assert len({m.stats["inner_divider_angle"] for m in meshes}) == 3
    assert len({m.stats["divider_angle"] for m in meshes}) == 1
    for m in meshes[1:]:
        assert_same_far_field(meshes[0], m)


def test_disc_fine_mesh_far_field_is_the_same():
    """At the fine uniform disc's sizes (size 0.8 mm, patch 12 mm)."""
    kw = dict(size=0.0008, tip_size=0.0005, sectors=32)
    a = crack_mesh(DISC, [crack(135)], DISC_POINTS, **kw, patch=(np.zeros(2), 0.012))
    b = crack_mesh(DISC, [winged(135, 0.0015)], DISC_POINTS, **kw, patch=(np.zeros(2), 0.012))
    assert a.stats["symmetric"] and b.stats["symmetric"]
    assert_valid(a, (np.zeros(2), 0.012))
    assert_same_far_field(a, b)


def test_disc_with_fractures_outside_the_circle():
    """A symmetric pair of fractures outside: part of the far field, as are
    their rosettes (and the outer divider keeps clear of their tips)."""
    out = np.array([[0.031, 0.006], [0.034, 0.012]])
    pair = [out, -out[::-1]]
    a = crack_mesh(DISC, [crack(135)] + pair, DISC_POINTS, **DISC_MESH, patch=DISC_PATCH)
    b = crack_mesh(DISC, [winged(135, 0.0015)] + pair, DISC_POINTS, **DISC_MESH, patch=DISC_PATCH)
    for m in (a, b):
        assert m.stats["symmetric"] and len(m.tips) == 6
        assert_valid(m, DISC_PATCH)
        assert_point_symmetric(m, 2 * R)
    assert_same_far_field(a, b)
    outer_tips = [t for t in a.tips if np.linalg.norm(t.x) > DISC_PATCH[1]]
    assert len(outer_tips) == 4
    for t in outer_tips:  # the rosette is far: it is the same in every call
        assert np.all(a.far[np.any(a.cells[:, :3] == t.node, axis=1)])


def test_symmetric_rectangle_off_the_origin():
    """A centre crack in a plate: the centre is not gmsh's origin, so 2c - x
    rounds, and the circle's nodes must still come out the same bits
    whichever half of the circle gmsh meshes (the inner divider turns)."""
    c = np.array([0.05, 0.03])
    points = [np.array([0.05, 0.0]), np.array([0.05, 0.06])]
    kw = dict(size=0.002, tip_size=0.0005, sectors=16)
    patch = (c, 0.02)
    meshes = [crack_mesh(RECT, f, points, **kw, patch=patch)
              for f in ([crack(20, 0.004, c)], [winged(20, 0.002) + c], [crack(100, 0.004, c)])]
    assert len({m.stats["inner_divider_angle"] for m in meshes}) >= 2
    for m in meshes:
        assert m.stats["symmetric"]
        assert_valid(m, patch)
        d, _ = cKDTree(m.x).query(2 * c - m.x)
        assert d.max() / 0.1 < ROUND_OFF
    for m in meshes[1:]:
        assert_same_far_field(meshes[0], m)


def disc_sizes(symmetric: bool):
    """A size field on the triangles of a coarse mesh of the disc: finer
    towards a point (off the centre unless `symmetric`), asking for less
    than `size` on part of the far field."""
    coarse = crack_mesh(DISC, [], DISC_POINTS, size=0.006, tip_size=0.001)
    tri = coarse.x[coarse.cells[:, :3]]
    if symmetric:
        vals = 0.0012 + 0.05 * np.abs(np.linalg.norm(tri, axis=2) - 0.03)
    else:
        vals = 0.001 + 0.02 * np.linalg.norm(tri - np.array([0.03, 0.01]), axis=2)
    return tri, vals


@pytest.mark.parametrize("symmetric", [True, False], ids=["symmetric sizes", "unsymmetric sizes"])
def test_disc_far_field_with_a_size_field(symmetric):
    sizes = disc_sizes(symmetric)
    a = crack_mesh(DISC, [crack(135)], DISC_POINTS, **DISC_MESH, sizes=sizes, patch=DISC_PATCH)
    b = crack_mesh(DISC, [winged(135, 0.0015)], DISC_POINTS, **DISC_MESH, sizes=sizes, patch=DISC_PATCH)
    plain = crack_mesh(DISC, [crack(135)], DISC_POINTS, **DISC_MESH, patch=DISC_PATCH)
    assert a.stats["symmetric"] and b.stats["symmetric"]
    assert len(a.cells) > 1.2 * len(plain.cells)  # the field does refine the far field
    assert_valid(a, DISC_PATCH)
    assert_same_far_field(a, b)


RECT_PAIRS = {
    "other angle": ([crack(10, 0.003, RECT_PATCH[0])], [crack(40, 0.003, RECT_PATCH[0])]),
    "kinked": ([crack(10, 0.003, RECT_PATCH[0])],
               [np.concatenate([crack(10, 0.003, RECT_PATCH[0]), [RECT_PATCH[0] + [-0.0035, -0.002]]])]),
}


@pytest.mark.parametrize("sized", [False, True], ids=["no sizes", "sizes"])
@pytest.mark.parametrize("name", list(RECT_PAIRS))
def test_rectangle_off_centre_crack_with_a_fracture_outside(name, sized):
    sizes = None
    if sized:
        g = np.linspace(0.0, 0.1, 11)
        h = np.linspace(0.0, 0.06, 7)
        quads = [((g[i], h[j]), (g[i + 1], h[j]), (g[i + 1], h[j + 1]), (g[i], h[j + 1]))
                 for i in range(10) for j in range(6)]
        tri = np.array([t for q in quads for t in ((q[0], q[1], q[2]), (q[0], q[2], q[3]))], float)
        sizes = (tri, 0.001 + 0.04 * np.abs(tri[..., 1] - 0.012))  # finer along a line under the crack outside
    meshes = [crack_mesh(RECT, f + [OUTSIDE], RECT_POINTS, **RECT_MESH, sizes=sizes, patch=RECT_PATCH)
              for f in RECT_PAIRS[name]]
    for m in meshes:
        assert not m.stats["symmetric"]
        assert_valid(m, RECT_PATCH)
    assert_same_far_field(*meshes)


def test_a_tip_just_beyond_the_clearance_keeps_the_far_field():
    """The crack grown until its tips are 1.001 clearances off the circle
    (the nearest the rule lets them come) against a short one."""
    size, tip = DISC_MESH["size"], DISC_MESH["tip_size"]
    reach = clearance_module.clearance_of(size, tip, tip, DISC_MESH["sectors"])
    half = DISC_PATCH[1] - 1.001 * reach
    a = crack_mesh(DISC, [crack(135, 0.002)], DISC_POINTS, **DISC_MESH, patch=DISC_PATCH)
    b = crack_mesh(DISC, [crack(135, half)], DISC_POINTS, **DISC_MESH, patch=DISC_PATCH)
    assert_same_far_field(a, b)


def test_a_tip_within_reach_changes_the_far_field(monkeypatch):
    """The control: with the clearance rule switched off, a tip 2 mm off the
    circle (the tip's size field reaches 2.8 mm further) changes the far
    field, and the comparison sees it."""
    monkeypatch.setattr(clearance_module, "clearance_of", lambda *args: 0.0)
    a = crack_mesh(DISC, [crack(135, 0.005)], DISC_POINTS, **DISC_MESH, patch=DISC_PATCH)
    b = crack_mesh(DISC, [crack(135, 0.018)], DISC_POINTS, **DISC_MESH, patch=DISC_PATCH)
    assert a.stats["patch"] and b.stats["patch"]
    with pytest.raises(AssertionError, match="far cells"):
        assert_same_far_field(a, b)


# -- the patch changes nothing else --------------------------------------------------


def test_tips_rosettes_and_pairs_as_without_the_patch():
    for domain, fractures, points, kw, patch in (
        (DISC, [winged(135, 0.0015)], DISC_POINTS, DISC_MESH, DISC_PATCH),
        (RECT, [crack(10, 0.003, RECT_PATCH[0]), OUTSIDE], RECT_POINTS, RECT_MESH, RECT_PATCH),
    ):
        mesh = crack_mesh(domain, fractures, points, **kw, patch=patch)
        plain = crack_mesh(domain, fractures, points, **kw)
        assert mesh.stats["symmetric"] == plain.stats["symmetric"]
        assert_same_tips(mesh, plain, kw["sectors"])
        assert np.array_equal(mesh.x[mesh.point_nodes], plain.x[plain.point_nodes])
        assert np.array_equal(np.unique(mesh.boundary_tags), np.unique(plain.boundary_tags))
        # about as many cells: the same size field, only the circle added
        assert abs(len(mesh.cells) - len(plain.cells)) < 0.1 * len(plain.cells)


@pytest.mark.parametrize("patch", [
    (np.zeros(2), 0.004),          # crosses the crack
    (np.zeros(2), 0.015),          # the crack inside, but its tips 10 mm off the circle (10.8 mm needed)
    (np.zeros(2), 0.0385),         # 3.5 mm off the rim (4 mm needed)
    (np.array([0.001, 0.0]), 0.02),  # off the centre of a symmetric geometry: the symmetry wins
    (np.zeros(2), -0.02),
    (np.array([np.nan, 0.0]), 0.02),
    ("not a point", 0.02),
], ids=["crossing", "tip within reach", "near the rim", "off centre", "negative", "nan", "garbage"])
def test_a_patch_that_does_not_fit_is_ignored(patch):
    plain = crack_mesh(DISC, [crack(135)], DISC_POINTS, **DISC_MESH)
    mesh = crack_mesh(DISC, [crack(135)], DISC_POINTS, **DISC_MESH, patch=patch)
    assert mesh.stats["patch"] is False and mesh.far is None
    assert mesh.stats["symmetric"]
    for name in ("x", "cells", "boundary_edges", "boundary_tags", "pairs", "crack_edges", "point_nodes"):
        assert np.array_equal(getattr(mesh, name), getattr(plain, name)), name


def test_no_patch_says_so():
    mesh = crack_mesh(DISC, [crack(135)], DISC_POINTS, **DISC_MESH)
    assert mesh.stats["patch"] is False and mesh.far is None


def test_patch_centre_within_round_off_of_the_centre_is_snapped():
    a = crack_mesh(DISC, [crack(135)], DISC_POINTS, **DISC_MESH, patch=DISC_PATCH)
    b = crack_mesh(DISC, [crack(135)], DISC_POINTS, **DISC_MESH, patch=(np.array([1e-13, -1e-13]), 0.02))
    assert b.stats["symmetric"] and b.stats["patch"]
    for name in ("x", "cells", "far"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name


# -- the far field reused -------------------------------------------------------------

ARRAYS = ("x", "cells", "far", "boundary_edges", "boundary_tags", "pairs", "pair_normal", "pair_fracture",
          "crack_edges", "crack_edges_minus", "crack_fracture", "point_nodes")


def assert_same_mesh(a, b):
    for name in ARRAYS:
        p, q = getattr(a, name), getattr(b, name)
        assert np.shape(p) == np.shape(q) and np.array_equal(bits(p) if p.dtype == np.float64 else p,
                                                             bits(q) if q.dtype == np.float64 else q), name
    assert len(a.tips) == len(b.tips)
    for t, s in zip(a.tips, b.tips):
        assert (t.node, t.upper, t.lower, t.h) == (s.node, s.upper, s.lower, s.h)
        assert np.array_equal(t.x, s.x) and np.array_equal(t.ex, s.ex)


OUT = np.array([[0.031, 0.006], [0.034, 0.012]])
REUSE_CASES = {
    "disc": (DISC, [crack(135)], [winged(135, 0.0015, kink_deg=50)], DISC_POINTS, DISC_MESH, DISC_PATCH, False),
    "disc, fractures outside": (DISC, [crack(135), OUT, -OUT[::-1]], [crack(30), OUT, -OUT[::-1]], DISC_POINTS,
                                DISC_MESH, DISC_PATCH, False),
    "disc, sizes": (DISC, [crack(135)], [winged(135, 0.002)], DISC_POINTS, DISC_MESH, DISC_PATCH, True),
    "rectangle": (RECT, [crack(10, 0.003, RECT_PATCH[0]), OUTSIDE], [crack(40, 0.0035, RECT_PATCH[0]), OUTSIDE],
                  RECT_POINTS, RECT_MESH, RECT_PATCH, False),
}


@pytest.mark.parametrize("name", list(REUSE_CASES))
def test_reuse_of_the_far_field_gives_the_mesh_meshing_it_gives(name):
    domain, first, second, points, kw, patch, sized = REUSE_CASES[name]
    sizes = disc_sizes(False) if sized else None
    a = crack_mesh(domain, first, points, **kw, sizes=sizes, patch=patch)
    reused = crack_mesh(domain, second, points, **kw, sizes=sizes, patch=patch)
    far_cache.FarCache.clear()
    meshed = crack_mesh(domain, second, points, **kw, sizes=sizes, patch=patch)
    assert not a.stats["far_reused"] and reused.stats["far_reused"] and not meshed.stats["far_reused"]
    assert_same_mesh(reused, meshed)
    assert_valid(reused, patch)


def test_reuse_only_when_the_far_field_is_the_same():
    """Another size field, another fracture outside, another patch: meshed."""
    a = crack_mesh(RECT, [crack(10, 0.003, RECT_PATCH[0]), OUTSIDE], RECT_POINTS, **RECT_MESH, patch=RECT_PATCH)
    assert not a.stats["far_reused"]
    moved = OUTSIDE + [0.0, 0.001]
    for fractures, patch in (([crack(10, 0.003, RECT_PATCH[0]), moved], RECT_PATCH),
                             ([crack(10, 0.003, RECT_PATCH[0]), OUTSIDE], (RECT_PATCH[0], 0.0161))):
        crack_mesh(RECT, [crack(10, 0.003, RECT_PATCH[0]), OUTSIDE], RECT_POINTS, **RECT_MESH, patch=RECT_PATCH)
        b = crack_mesh(RECT, fractures, RECT_POINTS, **RECT_MESH, patch=patch)
        assert b.stats["patch"] and not b.stats["far_reused"]
    sizes = disc_sizes(False)
    crack_mesh(DISC, [crack(135)], DISC_POINTS, **DISC_MESH, sizes=sizes, patch=DISC_PATCH)
    b = crack_mesh(DISC, [crack(135)], DISC_POINTS, **DISC_MESH, sizes=(sizes[0], 1.01 * sizes[1]),
                   patch=DISC_PATCH)
    assert not b.stats["far_reused"]


def test_reuse_in_the_meshing_worker():
    """With a time limit gmsh runs in the meshing worker, which keeps the
    far field across calls: the same mesh as meshing it here."""
    kw = dict(DISC_MESH, patch=DISC_PATCH, timeout=60.0)
    crack_mesh(DISC, [crack(135)], DISC_POINTS, **kw)
    reused = crack_mesh(DISC, [winged(135, 0.0015)], DISC_POINTS, **kw)
    assert reused.stats["far_reused"]
    meshed = crack_mesh(DISC, [winged(135, 0.0015)], DISC_POINTS, **DISC_MESH, patch=DISC_PATCH)
    assert not meshed.stats["far_reused"]
    assert_same_mesh(reused, meshed)


def test_reuse_of_a_far_field_that_does_not_fit_meshes_it():
    """A kept far field whose boundary node is off by one ulp (as if gmsh
    had meshed a boundary curve otherwise): not glued, meshed instead."""
    crack_mesh(DISC, [crack(135)], DISC_POINTS, **DISC_MESH, patch=DISC_PATCH)
    key, (cells, interior) = far_cache.FarCache._last
    k = np.flatnonzero(~interior.ravel())[0]
    cells = cells.copy()
    cells.reshape(-1, 2)[k, 0] = np.nextafter(cells.reshape(-1, 2)[k, 0], np.inf)
    far_cache.FarCache._last = (key, (cells, interior))
    again = crack_mesh(DISC, [winged(135, 0.0015)], DISC_POINTS, **DISC_MESH, patch=DISC_PATCH)
    assert again.stats["patch"] and not again.stats["far_reused"]
    far_cache.FarCache.clear()
    meshed = crack_mesh(DISC, [winged(135, 0.0015)], DISC_POINTS, **DISC_MESH, patch=DISC_PATCH)
    assert_same_mesh(again, meshed)
