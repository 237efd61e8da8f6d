"""Properties of the geometry and SIF kernels (wingcrack._kernels), checked
with hypothesis on generated input rather than on chosen examples.

Geometry: segment intersection is symmetric in its two segments and in the
direction of each, and agrees with the orientation (cross-product) tests.
SIFs: displacement correlation (paper eqs. 32-33) is linear in the four
displacements and blind to rigid motions of the whole configuration
(translation, finite rotation of the frame and the displacements together,
infinitesimal rotation field); the MTS angle (eq. 11) is the maximum of
sigma_theta (eq. 9), so K_eq (eq. 10) >= max(KI, 0) whenever KII != 0, and
|theta| <= arccos(1/3) = 70.53 deg < pi/2 whenever KI >= 0.

Each test runs a bounded number of examples with no deadline, so the file
stays under ~15 s on the 2-core machine; the example database is off, so
a run does not depend on earlier ones and a failure is reported with its
inputs (hypothesis still keeps a self-ignored cache in .hypothesis/).
"""
from __future__ import annotations

import math
import os

import numpy as np
from hypothesis import HealthCheck, assume, example, given, settings
from hypothesis import strategies as st

from references import kinked_sifs
import wingcrack_kernels as K

# WINGCRACK_HYPOTHESIS_EXAMPLES=20000 for a long search; 300 in make test.
PROFILE = settings(
    max_examples=int(os.environ.get("WINGCRACK_HYPOTHESIS_EXAMPLES", "300")), deadline=None, database=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much],
)

TOL = 1e-9  # the relative tolerance wingcrack.case uses (REL_TOL)
MTS_PURE_II = math.acos(1.0 / 3.0)  # |theta| for pure mode II, 70.5288 deg

# ---------------------------------------------------------------- strategies

coord = st.floats(min_value=-1e3, max_value=1e3, allow_nan=False, allow_infinity=False)
point = st.tuples(coord, coord).map(lambda p: np.array(p, dtype=float))
# A whole configuration is drawn in [-1e3, 1e3] and then scaled, so that
# millimetre cracks and kilometre faults are both tried.
length_scale = st.sampled_from([1e-6, 1e-3, 1.0, 1e3])
angle = st.floats(min_value=-math.pi, max_value=math.pi, allow_nan=False)
# SIFs over many decades and both signs, plus exact zeros.
K_value = st.one_of(
    st.just(0.0),
    st.builds(lambda m, e: m * 10.0**e, st.floats(-1.0, 1.0, allow_nan=False), st.integers(-6, 12)),
)


def cross(a, b) -> float:
    return float(a[0] * b[1] - a[1] * b[0])


def side(a, b, c) -> float:
    """Signed distance of c from the line a -> b (> 0 on its left)."""
    return cross(b - a, c - a) / float(np.linalg.norm(b - a))


def seg_distance(p, a, b) -> float:
    d = b - a
    dd = float(d @ d)
    t = 0.0 if dd == 0.0 else min(1.0, max(0.0, float((p - a) @ d) / dd))
    return float(np.linalg.norm(p - (a + t * d)))


def segments_distance_if_apart(p0, p1, q0, q1) -> float:
    """Distance between two segments that do not cross: the least end-to-segment distance."""
    return min(seg_distance(p0, q0, q1), seg_distance(p1, q0, q1), seg_distance(q0, p0, p1), seg_distance(q1, p0, p1))


# ---------------------------------------------------------------- segment intersection


@settings(PROFILE)
@given(point, point, point, point, length_scale)
@example(*(np.array(v, dtype=float) for v in ([0, 0], [2, 0], [1, 0], [3, 0])), 1.0)  # collinear overlap
@example(*(np.array(v, dtype=float) for v in ([0, 0], [1, 1], [1, 1], [2, 0])), 1.0)  # V junction
@example(*(np.array(v, dtype=float) for v in ([0, 0], [2, 0], [1, 0], [1, 1])), 1.0)  # T junction
@example(*(np.array(v, dtype=float) for v in ([0, 0], [0, 0], [0, 0], [1, 0])), 1.0)  # a point segment
def test_segment_intersection_is_symmetric(p0, p1, q0, q1, scale):
    p0, p1, q0, q1 = (scale * v for v in (p0, p1, q0, q1))
    hit, t, s, x = K.segment_intersection(p0, p1, q0, q1, TOL)
    hit2, t2, s2, x2 = K.segment_intersection(q0, q1, p0, p1, TOL)
    # Documented: swapping the segments swaps t and s and changes nothing else.
    assert hit2 == hit
    assert (t2, s2) == (s, t), (p0.tolist(), p1.tolist(), q0.tolist(), q1.tolist(), t, s, t2, s2)
    assert np.array_equal(x2, x)
    # Reversing a segment's direction is the same segment: same answer.
    hit3, t3, s3, x3 = K.segment_intersection(p1, p0, q1, q0, TOL)
    assert hit3 == hit
    if hit:
        ext = scale * 1e3
        # the contact point lies on both segments (within the tolerance)
        eps = TOL * max(np.linalg.norm(p1 - p0), np.linalg.norm(q1 - q0)) + 1e-12 * ext
        assert seg_distance(x, p0, p1) <= eps + 1e-9 * ext
        assert seg_distance(x, q0, q1) <= eps + 1e-9 * ext
        assert 0.0 <= t <= 1.0 and 0.0 <= s <= 1.0


@settings(PROFILE)
@given(point, point, point, point, length_scale)
def test_segment_intersection_agrees_with_orientation_tests(p0, p1, q0, q1, scale):
    p0, p1, q0, q1 = (scale * v for v in (p0, p1, q0, q1))
    lp, lq = float(np.linalg.norm(p1 - p0)), float(np.linalg.norm(q1 - q0))
    assume(lp > 0 and lq > 0)
    eps = TOL * max(lp, lq)
    hit = K.segment_intersection(p0, p1, q0, q1, TOL)[0]
    # Away from the tolerance band (a margin of 1e-6 of the longer segment,
    # far above rounding), the classical orientation predicate decides.
    margin = 1e-6 * max(lp, lq)
    a0, a1 = side(p0, p1, q0), side(p0, p1, q1)
    b0, b1 = side(q0, q1, p0), side(q0, q1, p1)
    if min(abs(a0), abs(a1), abs(b0), abs(b1)) > margin:
        crossing = a0 * a1 < 0 and b0 * b1 < 0
        assert hit == crossing, (a0, a1, b0, b1)
    # Both ends of q strictly on one side of p's line: never a hit.
    if (a0 > margin and a1 > margin) or (a0 < -margin and a1 < -margin):
        assert not hit
    # Not hit means apart by more than the tolerance; hit and no crossing
    # means touching within it.
    d = segments_distance_if_apart(p0, p1, q0, q1)
    if not hit:
        assert d > eps * (1 - 1e-9) - 1e-12 * scale
    elif not (a0 * a1 < 0 and b0 * b1 < 0):
        assert d <= eps * (1 + 1e-9) + 1e-12 * scale * 1e3


@settings(PROFILE)
@given(point, point, point, point, st.integers(-1000, 1000))
def test_segment_intersection_is_exactly_scale_invariant(p0, p1, q0, q1, e):
    # A power-of-two scale is exact in binary floating point, so the verdict
    # and the parameters must be identical and the point scaled exactly: the
    # same tol works for a micrometre crack and a kilometre fault.
    f = 2.0**e
    assume(all(np.all(np.isfinite(f * v)) and np.array_equal((f * v) / f, v) for v in (p0, p1, q0, q1)))
    ref = K.segment_intersection(p0, p1, q0, q1, TOL)
    got = K.segment_intersection(f * p0, f * p1, f * q0, f * q1, TOL)
    assert got[:3] == ref[:3]
    assert np.array_equal(got[3], f * ref[3])


@settings(PROFILE)
@given(point, point, st.floats(0.0, 1.0), st.floats(0.0, 1.0), angle, length_scale)
def test_crossing_segments_meet_at_the_crossing(c, _unused, t, s, phi, scale):
    # Two segments through a common point c at parameters t and s, at angle phi
    # apart (away from parallel): hit, and the point is c.
    assume(abs(math.sin(phi)) > 1e-2)
    c = scale * c
    d1 = scale * np.array([1.0, 0.3])
    d2 = np.array([[math.cos(phi), -math.sin(phi)], [math.sin(phi), math.cos(phi)]]) @ d1
    p0, p1 = c - t * d1, c + (1 - t) * d1
    q0, q1 = c - s * d2, c + (1 - s) * d2
    hit, _, _, x = K.segment_intersection(p0, p1, q0, q1, TOL)
    assert hit
    assert np.linalg.norm(x - c) <= 1e-9 * scale * 1e3


# ---------------------------------------------------------------- displacement correlation

frame_angle = angle
disp = st.tuples(*[st.floats(-1.0, 1.0, allow_nan=False)] * 8).map(lambda v: np.array(v).reshape(4, 2))
material = st.tuples(
    st.floats(1e-4, 1.0),  # h (m)
    st.floats(1e6, 1e11),  # mu (Pa)
    st.floats(1.0, 3.0),  # kappa: (1, 3) covers plane strain and stress for nu in [0, 0.5]
)


def frame(phi):
    ex = np.array([math.cos(phi), math.sin(phi)])
    return ex, np.array([-ex[1], ex[0]])


def dc(u, ex, ey, h, mu, kap):
    return np.array(K.displacement_correlation(u[0], u[1], u[2], u[3], ex, ey, h, mu, kap))


def coefficient(h, mu, kap):
    """The factor mu / (3 (1 + kappa)) sqrt(2 pi / h) of eqs. (32)-(33)."""
    return mu / (3 * (1 + kap)) * math.sqrt(2 * math.pi / h)


def rot(phi):
    return np.array([[math.cos(phi), -math.sin(phi)], [math.sin(phi), math.cos(phi)]])


@settings(PROFILE)
@given(disp, disp, st.floats(-1e3, 1e3), st.floats(-1e3, 1e3), frame_angle, material)
def test_displacement_correlation_is_linear(u, v, a, b, phi, mat):
    ex, ey = frame(phi)
    w = a * u + b * v
    got = dc(w, ex, ey, *mat)
    want = a * dc(u, ex, ey, *mat) + b * dc(v, ex, ey, *mat)
    # each K is c [8 (q_b - q_d) - (q_c - q_e)]: rounding of a few ulps of
    # c 18 max|w|, with c the formula's factor
    bound = coefficient(*mat) * 18 * (abs(a) * np.abs(u).max() + abs(b) * np.abs(v).max())
    assert np.all(np.abs(got - want) <= 1e-14 * bound + 1e-300), (got, want)


@settings(PROFILE)
@given(disp, point, frame_angle, angle, st.floats(-1e-3, 1e-3), point, material)
def test_displacement_correlation_ignores_rigid_motions(u, u0, phi, psi, omega, tip, mat):
    h, mu, kap = mat
    ex, ey = frame(phi)
    ref = dc(u, ex, ey, *mat)
    size = coefficient(*mat) * 18  # |K| for displacements of size 1
    # 1) a rigid translation of every node: the face differences cancel it
    #    (u0 up to 1e3 against u up to 1: cancellation costs 3 digits)
    got = dc(u + u0, ex, ey, *mat)
    assert np.all(np.abs(got - ref) <= 1e-12 * size * (1 + np.abs(u0).max()))
    # 2) an infinitesimal rigid rotation omega (-y, x) about the origin: the
    #    face nodes b/d and c/e sit at the same places, h/4 and h behind the tip
    xb = tip - 0.25 * h * ex
    xc = tip - h * ex
    field = lambda x: omega * np.array([-x[1], x[0]])  # noqa: E731
    got = dc(u + np.array([field(xb), field(xc), field(xb), field(xc)]), ex, ey, *mat)
    assert np.all(np.abs(got - ref) <= 1e-12 * size * (1 + 1e3 * abs(omega) * 1e3))
    # 3) the whole configuration turned by psi: frame and displacements
    #    rotated together leave the local SIFs unchanged
    R = rot(psi)
    got = dc(u @ R.T, R @ ex, R @ ey, *mat)
    assert np.all(np.abs(got - ref) <= 1e-13 * size * 8)


# ---------------------------------------------------------------- MTS angle, K_eq


def sigma_theta(KI, KII, t):
    """sigma_theta sqrt(2 pi r) at angle t (paper eq. 9), vectorised over t."""
    c = np.cos(t / 2)
    return c * (KI * c**2 - 1.5 * KII * np.sin(t))


@settings(PROFILE)
@given(K_value, K_value)
@example(1.0, 0.0)
@example(0.0, 1.0)
@example(-1.0, 1e-300)
@example(-1.0, 5e-324)
@example(1e300, 1e300)
def test_mts_angle_is_the_maximum_of_sigma_theta(KI, KII):
    theta = K.mts_angle(KI, KII)
    Keq = K.equivalent_k(KI, KII, theta)
    assert math.isfinite(theta) and math.isfinite(Keq)
    # In (-pi, pi): for KI < 0 and |KII| << |KI| the maximum sits at
    # -sign(KII) (pi - O(KII/KI)), which rounds to the double nearest pi
    # (math.pi, itself just below pi) once KII/KI < 1e-16.
    assert -math.pi <= theta <= math.pi
    # tolerances relative to |K|, plus the smallest subnormal for K ~ 1e-310
    Kmax = max(abs(KI), abs(KII))
    tiny = 1e-320  # a few ulps of the subnormal range
    if KI >= 0:
        # opening or neutral tip: the kink turns at most 70.53 deg, inside (-pi/2, pi/2)
        assert abs(theta) <= MTS_PURE_II * (1 + 1e-15)
        assert abs(theta) < math.pi / 2
    if KII != 0:
        assert Keq >= max(KI, 0.0) - 1e-12 * Kmax - tiny
        # the global maximum of sigma_theta over (-pi, pi), by a fine grid
        grid = np.linspace(-math.pi, math.pi, 4001)
        assert Keq >= float(np.max(sigma_theta(KI, KII, grid))) - 1e-9 * Kmax - tiny
    else:
        # documented: no shear, no kink; K_eq = KI (negative: no growth)
        assert theta == 0.0 and Keq == KI
    # positive KII kinks clockwise
    # (-0.0 when |KII/KI| is below the smallest double)
    if KII > 0 and KI >= 0:
        assert theta <= 0 and math.copysign(1.0, theta) < 0
    if KII < 0 and KI >= 0:
        assert theta >= 0 and math.copysign(1.0, theta) > 0
    # at the MTS angle the kinked tip is in pure mode I (eqs. 15-16)
    kI, kII = kinked_sifs(KI, KII, theta)
    assert abs(kII) <= 1e-12 * Kmax + tiny
    assert abs(kI - Keq) <= 1e-12 * Kmax + tiny


@settings(PROFILE)
@given(K_value, K_value)
def test_mts_angle_is_odd_in_KII(KI, KII):
    assert K.mts_angle(KI, -KII) == -K.mts_angle(KI, KII)
    assert K.equivalent_k(KI, -KII, -K.mts_angle(KI, KII)) == K.equivalent_k(KI, KII, K.mts_angle(KI, KII))


@settings(PROFILE)
@given(st.lists(st.tuples(K_value, K_value), min_size=1, max_size=20))
def test_vectorised_forms_match_the_scalar_ones(pairs):
    KI, KII = np.array(pairs).T
    theta = K.mts_angle(KI, KII)
    assert np.array_equal(theta, [K.mts_angle(a, b) for a, b in pairs])
    Keq = K.equivalent_k(KI, KII, theta)
    assert np.array_equal(Keq, [K.equivalent_k(a, b, t) for (a, b), t in zip(pairs, theta)])
