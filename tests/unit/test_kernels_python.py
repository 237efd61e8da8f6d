"""The geometry and SIF kernels through the binding (wingcrack._kernels):
the key checks of cpp_kernels/tests/test_{geometry,sif}.cpp, plus shapes,
scalar/vector broadcasting and the ValueErrors of bad shapes.

References: the Williams near-tip field (Anderson, Fracture Mechanics, 4th
ed., Table 2.2), the MTS criterion (Erdogan & Sih 1963; paper eqs. 9-12),
eqs. (10), (14)-(16) and (32)-(33) of Dang-Trung, Keilegavlen & Berre (2020).
"""
from __future__ import annotations

import numpy as np
import pytest

from references import kinked_sifs
import wingcrack_kernels as K

RNG = np.random.default_rng(2020)


def williams(KI, KII, r, t, mu, kap):
    """Local (tip-frame) displacement of the K field at polar (r, t)."""
    a = np.sqrt(r / (2 * np.pi)) / (2 * mu)
    c, s = np.cos(t / 2), np.sin(t / 2)
    ux = KI * a * c * (kap - 1 + 2 * s**2) + KII * a * s * (kap + 1 + 2 * c**2)
    uy = KI * a * s * (kap + 1 - 2 * c**2) - KII * a * c * (kap - 1 - 2 * s**2)
    return np.stack([ux, uy], axis=-1)


def rosette_displacements(KI, KII, phi, tip, h, mu, kap, u0, omega):
    """Global displacements (k, 4, 2) of nodes b, c (upper face, theta = +pi,
    r = h/4, h) and d, e (lower face, theta = -pi) of k tips with frame angle
    phi, plus a rigid motion u0 + omega (-y, x)."""
    ex = np.stack([np.cos(phi), np.sin(phi)], axis=-1)
    ey = np.stack([-ex[:, 1], ex[:, 0]], axis=-1)
    u = np.empty((len(KI), 4, 2))
    for j, (f, t) in enumerate([(0.25, np.pi), (1.0, np.pi), (0.25, -np.pi), (1.0, -np.pi)]):
        r = f * h
        ul = williams(KI, KII, r, t, mu, kap)
        x = tip - r[:, None] * ex
        u[:, j] = ul[:, :1] * ex + ul[:, 1:] * ey + u0 + omega[:, None] * np.stack([-x[:, 1], x[:, 0]], axis=-1)
    return u, ex, ey


@pytest.mark.parametrize("plane", ["strain", "stress"])
def test_displacement_correlation_exact_on_williams_field(plane):
    k, E, nu, K0 = 50, 30e9, 0.25, 1e6
    mu, kap = E / (2 * (1 + nu)), K.kappa(nu, plane)
    KI, KII = K0 * RNG.uniform(-1, 1, k), K0 * RNG.uniform(-1, 1, k)
    KI[:3], KII[:3] = [K0, 0, 0], [0, K0, -K0]  # pure modes among them
    h = 10 ** RNG.uniform(-3, -1, k)
    scale = K0 * np.sqrt(h) / mu  # crack-face displacement size
    u, ex, ey = rosette_displacements(KI, KII, RNG.uniform(-np.pi, np.pi, k), RNG.uniform(-5, 5, (k, 2)), h, mu, kap,
                                      scale[:, None] * RNG.uniform(-1, 1, (k, 2)), scale / 5 * RNG.uniform(-1, 1, k))
    # Non-contiguous slices, as wingcrack.tip_sifs passes them.
    kI, kII = K.displacement_correlation(u[:, 0], u[:, 1], u[:, 2], u[:, 3], ex, ey, h, mu, kap)
    assert kI.shape == kII.shape == (k,)
    # Exact formula: rounding only (~1e-15); the rigid motion is kept as large
    # as the crack field so cancellation cannot eat more than a digit.
    err = np.max(np.maximum(abs(kI - KI), abs(kII - KII)) / np.hypot(KI, KII))
    assert err < 1e-10, err


def test_displacement_correlation_single_tip_and_broadcast():
    mu, kap, h = 1.0, 2.0, 0.01
    u, ex, ey = rosette_displacements(np.array([1.0]), np.array([-0.5]), np.array([0.3]), np.zeros((1, 2)),
                                      np.array([h]), mu, kap, np.zeros(2), np.zeros(1))
    kI, kII = K.displacement_correlation(u[0, 0], u[0, 1], u[0, 2], u[0, 3], ex[0], ey[0], h, mu, kap)
    assert isinstance(kI, float) and isinstance(kII, float)
    assert kI == pytest.approx(1.0, rel=1e-12) and kII == pytest.approx(-0.5, rel=1e-12)
    # One shared frame for three tips given as (k, 2) displacements.
    U = np.repeat(u, 3, axis=0)
    kI3, kII3 = K.displacement_correlation(U[:, 0], U[:, 1], U[:, 2], U[:, 3], ex[0], ey[0], [h] * 3, mu, kap)
    assert kI3.shape == (3,) and np.allclose(kI3, 1.0, rtol=1e-12) and np.allclose(kII3, -0.5, rtol=1e-12)


def test_displacement_correlation_rejects_bad_shapes_and_values():
    z2, z3 = np.zeros((2, 2)), np.zeros((3, 2))
    ex, ey = np.array([1.0, 0.0]), np.array([0.0, 1.0])
    with pytest.raises(ValueError, match="u_c has 3 tips but u_b has 2"):
        K.displacement_correlation(z2, z3, z2, z2, ex, ey, 0.1, 1.0, 2.0)
    with pytest.raises(ValueError, match=r"u_b must have shape \(k, 2\)"):
        K.displacement_correlation(np.zeros((2, 3)), z2, z2, z2, ex, ey, 0.1, 1.0, 2.0)
    with pytest.raises(ValueError, match="h must be a scalar or have shape"):
        K.displacement_correlation(z2, z2, z2, z2, ex, ey, np.ones((2, 1)), 1.0, 2.0)
    with pytest.raises(ValueError, match="h must be > 0"):
        K.displacement_correlation(z2, z2, z2, z2, ex, ey, 0.0, 1.0, 2.0)
    with pytest.raises(ValueError, match="right-handed orthonormal"):
        K.displacement_correlation(z2, z2, z2, z2, ex, -ey, 0.1, 1.0, 2.0)


def test_kappa():
    assert K.kappa(0.25, "strain") == 2.0
    assert K.kappa(0.25, "stress") == pytest.approx(2.2, rel=1e-15)
    with pytest.raises(ValueError, match="plane must be"):
        K.kappa(0.25, "plane_strain")


def test_mts_angle_pure_modes_and_continuity():
    assert K.mts_angle(1.0, 0.0) == 0.0
    assert np.degrees(K.mts_angle(0.0, 1.0)) == pytest.approx(-70.5288, abs=1e-4)
    assert K.mts_angle(0.0, 1.0) == pytest.approx(-2 * np.arctan(1 / np.sqrt(2)), abs=1e-15)
    assert np.degrees(K.mts_angle(0.0, -1.0)) == pytest.approx(70.5288, abs=1e-4)
    KII = 10.0 ** -np.arange(1, 300, 7.0)
    theta = K.mts_angle(np.ones_like(KII), KII)
    assert theta.shape == KII.shape and np.all(np.isfinite(theta))
    # theta = -2 KII + (14/3) KII^3 + ... for KI = 1 (plus 1e-15 rounding).
    assert np.all(abs(theta + 2 * KII) <= KII * (10 * KII**2 + 1e-15))


def test_mts_angle_maximises_hoop_stress_eq9():
    phi = RNG.uniform(-np.pi, np.pi, 2000)
    KI, KII = np.cos(phi), np.sin(phi)
    keep = KI > -0.95  # near pure compression sigma_theta flattens to 0: no curvature to check
    KI, KII = KI[keep], KII[keep]
    t = K.mts_angle(KI, KII)
    assert np.all((t > -np.pi) & (t < np.pi))

    def f(a):  # eq. (9) times sqrt(2 pi r)
        return KI * np.cos(a / 2) ** 3 - 1.5 * KII * np.cos(a / 2) * np.sin(a)

    # Central differences: slope error ~1e-10, curvature error ~1e-7 (|K| = 1).
    d1 = (f(t + 1e-5) - f(t - 1e-5)) / 2e-5
    d2 = (f(t + 1e-3) - 2 * f(t) + f(t - 1e-3)) / 1e-6
    assert np.max(abs(d1)) < 1e-8
    assert np.max(d2) < -1e-3
    grid = np.linspace(-np.pi, np.pi, 4001)[:, None]
    assert np.all(f(grid) <= f(t) + 1e-12)  # the global maximum


def test_equivalent_k_and_kinked_sifs():
    assert K.equivalent_k(2.0, 0.0, 0.0) == 2.0
    for KII in (1.0, -1.0, 3e6):
        assert K.equivalent_k(0.0, KII, K.mts_angle(0.0, KII)) == pytest.approx(2 / np.sqrt(3) * abs(KII), rel=1e-14)
    KI, KII = RNG.uniform(-1e6, 1e6, (2, 500))
    t = K.mts_angle(KI, KII)
    kI, kII = kinked_sifs(KI, KII, t)
    keq = K.equivalent_k(KI, KII, t)
    assert kI.shape == kII.shape == keq.shape == (500,)
    # Eqs. (15)-(16) are coded independently of eq. (10): rounding only.
    assert np.max(abs(kII) / np.hypot(KI, KII)) < 1e-12
    assert np.max(abs(kI - keq) / np.hypot(KI, KII)) < 1e-12


def test_energy_release_rate():
    E, nu = 20e9, 0.27
    KI, KII = np.array([1.2e6, 0.0]), np.array([-0.7e6, 1e6])
    G = K.energy_release_rate(KI, KII, E, nu, K.kappa(nu, "strain"))
    assert np.allclose(G, (1 - nu**2) * (KI**2 + KII**2) / E, rtol=1e-14, atol=0)
    G = K.energy_release_rate(KI, KII, E, nu, K.kappa(nu, "stress"))
    assert np.allclose(G, (KI**2 + KII**2) / E, rtol=1e-14, atol=0)
    assert isinstance(K.energy_release_rate(1e6, 0.0, E, nu, 2.0), float)
    with pytest.raises(ValueError, match="KII has 3 tips but KI has 2"):
        K.energy_release_rate(KI, np.zeros(3), E, nu, 2.0)


@pytest.mark.parametrize(
    "p0, p1, q0, q1, hit, point",
    [
        ((0, 0), (2, 2), (0, 2), (2, 0), True, (1, 1)),  # crossing
        ((0, 0), (1, 0), (1, 0), (2, 3), True, (1, 0)),  # touching at an end
        ((0, 0), (2, 0), (1, 0), (1, 1), True, (1, 0)),  # T
        ((0, 0), (2, 0), (1, 0), (3, 0), True, (1.5, 0)),  # collinear overlap: its middle
        ((0, 0), (2, 0), (0, 1e-6), (2, 1e-6), False, None),  # parallel, disjoint
        ((0, 0), (1, 0), (1.5, 0), (3, 0), False, None),  # collinear, disjoint
        ((1, 0), (1, 0), (0, 0), (2, 0), True, (1, 0)),  # zero-length on a segment
    ],
)
def test_segment_intersection(p0, p1, q0, q1, hit, point):
    a = K.segment_intersection(p0, p1, q0, q1)
    b = K.segment_intersection(q0, q1, p0, p1)
    assert a[0] is hit and b[0] is hit
    assert (a[1], a[2]) == (b[2], b[1]) and np.array_equal(a[3], b[3])  # symmetric
    assert np.all(np.isfinite(a[3])) and 0 <= a[1] <= 1 and 0 <= a[2] <= 1
    if hit:
        assert np.allclose(a[3], point, atol=1e-15)


def test_distances_and_polylines():
    pts = np.array([[0.0, 0.0], [3.0, 0.0], [3.0, 4.0]])
    assert K.point_segment_distance([1, 1], [0, 0], [2, 0]) == (1.0, 0.5)
    assert K.point_polyline_distance(np.array([4.0, 3.0]), pts) == 1.0
    d, x, seg, t = K.closest_point_on_polyline([4.0, 3.0], pts)
    assert (d, seg, t) == (1.0, 1, 0.75) and np.allclose(x, [3, 3])
    assert not K.polyline_self_intersects(np.array([[0, 0], [1, 0], [2, 1], [3, 0.0]]), 1e-9)
    assert K.polyline_self_intersects(np.array([[0, 0], [2, 0], [2, 1], [1, -1.0]]), 1e-9)
    assert K.polyline_self_intersects(np.array([[0, 0], [2, 0], [1, 0.0]]), 1e-9)  # folds back
    assert K.polylines_intersect(pts, np.array([[4.0, 1.0], [2.0, 1.0]]), 1e-9)
    assert not K.polylines_intersect(pts, np.array([[4.0, 1.0], [5.0, 1.0]]), 1e-9)
    with pytest.raises(ValueError, match=r"points must be points of shape \(n, 2\)"):
        K.point_polyline_distance([0.0, 0.0], np.zeros((3, 3)))
    with pytest.raises(ValueError, match=r"p must be a point of shape \(2,\)"):
        K.point_polyline_distance(np.zeros(3), pts)
    with pytest.raises(ValueError, match=r"q1 must be a point"):
        K.segment_intersection([0, 0], [1, 1], [0, 1], [[1, 0]])


def test_the_batch_kernels_give_each_row_what_the_one_row_kernels_give():
    """segment_intersections and point_polyline_distances run the same C++
    functions row by row: equal bit for bit to the one-row kernels (the
    crossing test and the constraint rows switched to them with results
    unchanged), touches, collinear and zero-length segments included."""
    rng = np.random.default_rng(3)
    p0, p1, q0, q1 = (rng.integers(-3, 4, size=(400, 2)).astype(float) / 2 for _ in range(4))
    hit, t, s, point = K.segment_intersections(p0, p1, q0, q1, 1e-9)
    one = [K.segment_intersection(*row, 1e-9) for row in zip(p0, p1, q0, q1)]
    assert hit.dtype == bool and hit.any() and not hit.all()   # the rows hold hits and misses
    assert np.array_equal(hit, [h for h, *_ in one])
    assert np.array_equal(t, [r[1] for r in one]) and np.array_equal(s, [r[2] for r in one])
    assert np.array_equal(point, np.array([r[3] for r in one]))
    pts = rng.normal(size=(7, 2))
    p = rng.normal(size=(50, 2))
    assert np.array_equal(K.point_polyline_distances(p, pts), [K.point_polyline_distance(x, pts) for x in p])
    assert K.point_polyline_distances(np.zeros((0, 2)), pts).shape == (0,)
    assert K.segment_intersections(*(np.zeros((0, 2)),) * 4)[0].shape == (0,)
    with pytest.raises(ValueError, match=r"q0 must be points of shape \(400, 2\), got shape \(399, 2\)"):
        K.segment_intersections(p0, p1, q0[1:], q1)
    with pytest.raises(ValueError, match=r"p must be points of shape"):
        K.point_polyline_distances(np.zeros(2), pts)
