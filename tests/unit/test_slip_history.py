"""contact/slip_history: the converged slip of the faces carried from mesh to
mesh by arc length (issue 14: friction is path dependent, and every step
remeshes).

References, computed here without the module: arc lengths from the straight
segments' own formula (x - origin).d; a quadratic in arc length, which the P2
field of straight edges with mid nodes in the middle reproduces exactly; on
the quarter-point edges next to a tip the P2 field is exactly
beta sqrt(rho) + gamma rho (rho the distance from the tip, zero jump at the
tip), fitted here to the quarter-point and corner values; for any other
profile (the elliptic one) the old P2 field found in the plane, xi by
bisection on the edge's isoparametric map (a second method); zero on a wing
that did not exist when the slip was recorded. The same mesh must give back
what was recorded, whatever it was (random values, a T-junction's two host
pairs with different slips, fractures linked end to end).

Tolerances: every reference is reproduced exactly by the interpolation, so
what remains is round-off: arc lengths to ~1e-16 of the fracture length,
times slopes of O(slip / length) (steeper next to a tip, where sqrt(rho) is
read at rho >= h/4 of the old nodes or snapped onto an old node), shape
functions to ~1e-16. 1e-12 of the slip scale keeps three orders of margin
and still catches an arc-length shift of 1e-11 of the length (an origin off
by that much, an edge read on the wrong side). The issue's own criterion at
coinciding arc lengths, 1e-10 of the slip, is checked as written.
"""
import numpy as np
import pytest

from meshing import crack_mesh
from meshing.domain import Domain
from wingcrack.contact.slip_history import KEYS, SlipHistory, pair_arc_lengths
from wingcrack.face_law import FaceLaw
from wingcrack.propagation.fracture_set import GrowingFracture

DOMAIN = Domain("rectangle", corner=[-1.0, -1.0], size=[2.0, 2.0])
D = np.array([np.cos(0.5), np.sin(0.5)])   # not along an axis: projections are not trivial
P0, P1 = -0.3 * D, 0.3 * D
LENGTH = 0.6
SCALE = 1e-4   # slip scale (m)
RTOL = 1e-12   # see the module docstring


def fracture(points, pre=None) -> GrowingFracture:
    points = np.array(points, float)
    return GrowingFracture(points, pre or (0, len(points) - 1), ["tip", "tip"], FaceLaw("coulomb"))


def mesh(polylines, size=0.2, tip_size=0.02):
    return crack_mesh(DOMAIN, polylines, [], size=size, tip_size=tip_size)


def q(s):
    """A quadratic in arc length, of order SCALE, nonzero at the tips."""
    t = s / LENGTH
    return SCALE * (0.7 + 2.0 * t - 3.0 * t * t)


def elliptic(s):
    """The slip of a frictional crack under shear (issue 14, verification 1),
    zero at both tips of the straight crack P0-P1 (s from P0)."""
    a = LENGTH / 2
    return SCALE * np.sqrt(np.maximum(a * a - (s - a) ** 2, 0.0)) / a


def pair_arc(cm, origin, d, fracture_index=0):
    """(x - origin).d of the + node of every pair (the reference arc length
    on a straight piece), NaN for pairs of other fractures."""
    s = (cm.x[cm.pairs[:, 0]] - origin) @ d
    return np.where(cm.pair_fracture == fracture_index, s, np.nan)


def field(s, f, tips, lo, hi):
    """What P2 makes of the nodal values f(s) (0 at the tips): f itself on
    plain edges; within h of a tip (s_tip, inward +-1, h) the exact
    beta sqrt(rho) + gamma rho through the quarter-point and corner values;
    0 outside [lo, hi]."""
    out = f(s)
    for s_tip, inward, h in tips:
        rho = inward * (s - s_tip)
        near = (rho >= 0) & (rho < h)
        v_quarter, v_corner = f(s_tip + inward * h / 4), f(s_tip + inward * h)
        gamma = (2 * v_corner - 4 * v_quarter) / h
        beta = (v_corner - gamma * h) / np.sqrt(h)
        out = np.where(near, beta * np.sqrt(np.abs(rho)) + gamma * rho, out)
    return np.where((s >= lo) & (s <= hi), out, 0.0)


def tips_of(cm, origin, d, fracture_index=0):
    """(s_tip, inward, h) of each tip of the fracture on the straight line."""
    out = []
    for t in cm.tips:
        if t.fracture == fracture_index:
            s = float((t.x - origin) @ d)
            out.append((s, 1.0 if t.end == 0 else -1.0, t.h))
    return out


def p2_in_plane(cm, slip, points):
    """The P2 field of the + face edges of `cm` with nodal values `slip`
    (per pair; 0 at a tip) at `points` on the fracture: the edge whose
    segment holds the point, xi with x(xi) = sum N_i(xi) x_i by bisection
    (x(xi) runs monotonically from a to b), then sum N_i(xi) slip_i."""
    node_slip = np.zeros(len(cm.x))
    node_slip[cm.pairs[:, 0]] = slip   # one fracture, no junction: the + copy names the pair
    shape = lambda xi: np.array([(1 - xi) * (1 - 2 * xi), xi * (2 * xi - 1), 4 * xi * (1 - xi)])
    out = []
    for p in points:
        for a, b, m in cm.crack_edges:
            xa, xb = cm.x[a], cm.x[b]
            t = (p - xa) @ (xb - xa) / ((xb - xa) @ (xb - xa))
            if -1e-12 <= t <= 1 + 1e-12:
                break
        X = cm.x[[a, b, m]]
        if min(abs(t), abs(1 - t)) < 1e-9:   # an old node (sqrt(round-off) next to a tip otherwise)
            out.append(node_slip[a if abs(t) < 0.5 else b])
            continue
        lo, hi = 0.0, 1.0
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            if (shape(mid) @ X - xa) @ (xb - xa) < (p - xa) @ (xb - xa):
                lo = mid
            else:
                hi = mid
        out.append(shape(0.5 * (lo + hi)) @ node_slip[[a, b, m]])
    return np.array(out)


def test_same_mesh_returns_what_was_recorded():
    f = fracture([P0, P1])
    cm = mesh([f.points])
    s = pair_arc(cm, P0, D)
    np.testing.assert_allclose(pair_arc_lengths(cm, [f]), s, rtol=0, atol=1e-14 * LENGTH)
    slip = elliptic(s)
    h = SlipHistory.record(cm, [f], slip)
    np.testing.assert_allclose(h.at(cm, [f]), slip, rtol=0, atol=RTOL * SCALE)
    # any values at all, signs mixed
    rand = SCALE * np.random.default_rng(14).uniform(-1, 1, len(cm.pairs))
    np.testing.assert_allclose(SlipHistory.record(cm, [f], rand).at(cm, [f]), rand, rtol=0, atol=RTOL * SCALE)


def test_same_mesh_at_a_t_junction_keeps_both_host_pairs():
    # the wing ends inside the host: three copies at the junction, two host
    # pairs there (left and right of the wing) that may slip differently
    host = fracture([[-0.2, 0.0], [0.2, 0.0]])
    wing = fracture([[0.05, 0.15], [0.05, 0.0]])
    cm = mesh([host.points, wing.points], size=0.1, tip_size=0.01)
    at_junction = np.flatnonzero(np.linalg.norm(cm.x[cm.pairs[:, 0]] - [0.05, 0.0], axis=1) < 1e-14)
    assert sorted(cm.pair_fracture[at_junction].tolist()) == [0, 0, 1]
    rand = SCALE * np.random.default_rng(3).uniform(-1, 1, len(cm.pairs))
    back = SlipHistory.record(cm, [host, wing], rand).at(cm, [host, wing])
    np.testing.assert_allclose(back, rand, rtol=0, atol=RTOL * SCALE)


@pytest.mark.parametrize("polylines", [
    [[[-0.2, 0.0], [0.0, 0.0]], [[0.0, 0.0], [0.2, 0.05]]],    # linked end to end, the same direction
    [[[-0.2, 0.0], [0.0, 0.0]], [[0.2, 0.05], [0.0, 0.0]]],    # end to end, opposite directions
    [[[0.0, 0.0], [0.3, 0.0], [0.3, 0.1], [0.1, 0.1], [0.1, 0.0]]],   # ends on its own first segment
], ids=["end-to-end", "end-to-end-opposite", "own-segment"])
def test_same_mesh_where_fractures_meet(polylines):
    # the junction node lies on two pieces of fracture (or twice on one): its
    # pairs take the arc of their own fracture's edge, not the nearest piece
    fractures = [fracture(p) for p in polylines]
    cm = mesh([f.points for f in fractures], size=0.1, tip_size=0.01)
    rand = SCALE * np.random.default_rng(5).uniform(-1, 1, len(cm.pairs))
    back = SlipHistory.record(cm, fractures, rand).at(cm, fractures)
    np.testing.assert_allclose(back, rand, rtol=0, atol=RTOL * SCALE)


def test_remesh_reproduces_a_quadratic_and_the_tip_sqrt():
    f = fracture([P0, P1])
    old = mesh([f.points])
    h = SlipHistory.record(old, [f], field(pair_arc(old, P0, D), q, [], 0.0, LENGTH))
    new = mesh([f.points], size=0.15, tip_size=0.013)
    s = pair_arc(new, P0, D)
    want = field(s, q, tips_of(old, P0, D), 0.0, LENGTH)
    got = h.at(new, [f])
    assert len(new.pairs) != len(old.pairs)   # another mesh, nodes elsewhere
    np.testing.assert_allclose(got, want, rtol=0, atol=RTOL * SCALE)
    # the check reaches into the old quarter-point edges (the xi inversion)
    h_old = old.tips[0].h
    assert np.sum(np.minimum(s, LENGTH - s) < h_old) >= 4


def test_wing_at_end_0_keeps_the_pre_existing_slip_and_starts_at_zero():
    f = fracture([P0, P1])
    old = mesh([f.points])
    s_old = pair_arc(old, P0, D)
    ell = SlipHistory.record(old, [f], elliptic(s_old))
    quad = SlipHistory.record(old, [f], field(s_old, q, [], 0.0, LENGTH))

    w = np.array([np.cos(0.5 + np.pi - 1.2), np.sin(0.5 + np.pi - 1.2)])   # kinked 69 degrees off -d
    f.extend(0, P0 + 0.06 * w)
    assert f.pre == (1, 2) and np.array_equal(f.points[f.pre[0]], P0)
    new = mesh([f.points])
    on_wing = ((new.x[new.pairs[:, 0]] - P0) @ w) > 1e-12 * LENGTH
    s = np.where(on_wing, -np.linalg.norm(new.x[new.pairs[:, 0]] - P0, axis=1), pair_arc(new, P0, D))
    np.testing.assert_allclose(pair_arc_lengths(new, [f]), s, rtol=0, atol=1e-14 * LENGTH)

    got = ell.at(new, [f])
    assert np.sum(on_wing) >= 5 and np.all(got[on_wing] == 0.0)
    # the criterion: where old and new pairs share an arc length (the
    # rosette nodes of the unchanged tip at end 1, at h/4 and h from it),
    # the new slip is the recorded one
    match = np.abs(s[:, None] - s_old[None, :]) < 1e-12 * LENGTH
    i, j = np.nonzero(match)
    assert len(i) >= 2
    np.testing.assert_allclose(got[i], elliptic(s_old)[j], rtol=0, atol=1e-10 * SCALE)
    # everywhere else on the pre-existing part: the old P2 field, here found
    # in the plane (a second method: xi of the point by bisection on the
    # edge's isoparametric map, not arc lengths)
    pre = ~on_wing
    np.testing.assert_allclose(got[pre], p2_in_plane(old, elliptic(s_old), new.x[new.pairs[pre, 0]]),
                               rtol=0, atol=RTOL * SCALE)
    # and with a quadratic the old field is known in closed form
    want = field(s, q, tips_of(old, P0, D), 0.0, LENGTH)
    np.testing.assert_allclose(quad.at(new, [f]), want, rtol=0, atol=RTOL * SCALE)


def test_tip_moved_straight_on_at_end_0_keeps_the_material_coordinate():
    # move_tip at end 0 of a fracture without a wing moves points[pre[0]]
    # itself; the recorded origin still marks the same material point
    f = fracture([P0, P1])
    old = mesh([f.points])
    h = SlipHistory.record(old, [f], field(pair_arc(old, P0, D), q, [], 0.0, LENGTH))
    f.move_tip(0, P0 - 0.01 * D)
    new = mesh([f.points])
    s = pair_arc(new, P0, D)   # from the old P0, which the mesh no longer has as a vertex
    assert np.sum(s < 0) >= 1
    want = field(s, q, tips_of(old, P0, D), 0.0, LENGTH)
    np.testing.assert_allclose(h.at(new, [f]), want, rtol=0, atol=RTOL * SCALE)


def test_t_junction_remesh_keeps_the_jump_across_the_wing():
    host = fracture([[-0.2, 0.0], [0.2, 0.0]])
    wing = fracture([[0.05, 0.15], [0.05, 0.0]])
    ex, ey = np.array([1.0, 0.0]), np.array([0.0, -1.0])
    o_host, o_wing = host.points[0], wing.points[0]
    jump = 0.5 * SCALE

    def slips(cm):
        """host: q, plus `jump` right of the wing (x > 0.05), decided by the
        host edge each pair comes from; wing: q of its own arc length."""
        s = np.where(cm.pair_fracture == 0, pair_arc(cm, o_host, ex, 0), pair_arc(cm, o_wing, ey, 1))
        key = {(int(a), int(b)): p for p, (a, b) in enumerate(cm.pairs)}
        right = np.zeros(len(cm.pairs), bool)
        for e in np.flatnonzero(cm.crack_fracture == 0):
            plus, minus = cm.crack_edges[e], cm.crack_edges_minus[e]
            side = cm.x[plus[2], 0] > 0.05
            for a, b in zip(plus, minus):
                if (a, b) in key:
                    right[key[(a, b)]] = side
        return s, right

    old = mesh([host.points, wing.points], size=0.1, tip_size=0.01)
    s, right = slips(old)
    h = SlipHistory.record(old, [host, wing], q(s) + np.where(right, jump, 0.0))
    new = mesh([host.points, wing.points], size=0.08, tip_size=0.008)
    s, right = slips(new)
    host_pairs = new.pair_fracture == 0
    host_tips = tips_of(old, o_host, ex, 0)   # the end-1 tip lies right of the wing: its fit takes the jump
    want = np.where(host_pairs,
                    np.where(right, field(s, lambda s: q(s) + jump, host_tips, 0.0, 0.4),
                             field(s, q, host_tips, 0.0, 0.4)),
                    field(s, q, tips_of(old, o_wing, ey, 1), 0.0, 0.15))
    got = h.at(new, [host, wing])
    np.testing.assert_allclose(got, want, rtol=0, atol=RTOL * SCALE)
    at_junction = np.linalg.norm(new.x[new.pairs[:, 0]] - [0.05, 0.0], axis=1) < 1e-14
    assert np.sum(at_junction & host_pairs & right) == 1 and np.sum(at_junction & host_pairs & ~right) == 1


def test_checkpoint_round_trip(tmp_path):
    f = fracture([P0, P1])
    cm = mesh([f.points])
    h = SlipHistory.record(cm, [f], elliptic(pair_arc(cm, P0, D)))
    arrays = h.to_arrays()
    assert set(arrays) == set(KEYS) and all(k.startswith("slip_") for k in arrays)
    assert all(a.dtype in (np.float64, np.int64) for a in arrays.values())
    np.savez(tmp_path / "checkpoint.npz", other=np.arange(3), **arrays)
    with np.load(tmp_path / "checkpoint.npz", allow_pickle=False) as z:
        back = SlipHistory.from_arrays(z)
    for k in KEYS:
        np.testing.assert_array_equal(back.to_arrays()[k], arrays[k])
    assert np.array_equal(back.at(cm, [f]), h.at(cm, [f]))
    assert not back.is_zero()

    zero = SlipHistory.zero(2)
    assert zero.is_zero() and zero.n_fractures == 2
    np.savez(tmp_path / "zero.npz", **zero.to_arrays())
    with np.load(tmp_path / "zero.npz", allow_pickle=False) as z:
        zero = SlipHistory.from_arrays(z)
    g = fracture([[0.1, -0.5], [0.1, -0.3]])
    cm2 = mesh([f.points, g.points])
    assert np.array_equal(zero.at(cm2, [f, g]), np.zeros(len(cm2.pairs)))


def test_bad_input_names_what_is_wrong():
    f = fracture([P0, P1])
    cm = mesh([f.points])
    with pytest.raises(ValueError, match="slip_per_pair: shape"):
        SlipHistory.record(cm, [f], np.zeros(len(cm.pairs) + 1))
    with pytest.raises(ValueError, match="slip_per_pair: not finite"):
        SlipHistory.record(cm, [f], np.full(len(cm.pairs), np.nan))
    h = SlipHistory.record(cm, [f], np.zeros(len(cm.pairs)))
    with pytest.raises(ValueError, match="recorded on 1 fractures, given 2"):
        h.at(cm, [f, f])
    elsewhere = fracture([[0.0, -0.5], [0.3, -0.4]])   # not the fracture of this mesh
    with pytest.raises(ValueError, match="off its polyline"):
        h.at(cm, [elsewhere])
    with pytest.raises(ValueError, match="missing slip_edge_arc"):
        SlipHistory.from_arrays({k: v for k, v in h.to_arrays().items() if k != "slip_edge_arc"})
