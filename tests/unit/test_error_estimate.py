"""The Zienkiewicz-Zhu estimator (paper section 3.3.1, eqs. 35-36) through the
binding and the wrapper wingcrack.error_estimate: the key checks of
cpp_kernels/tests/test_error_estimate.cpp, plus shapes and ValueErrors.

References: Zienkiewicz & Zhu (1987), Int. J. Numer. Meth. Eng. 24, 337-357
(nodal averaging recovery, equidistribution rule h' = h (e*/eta)^(1/p));
int_T (sum e_i l_i)^2 dA = A/6 (sum e_i^2 + sum_{i<j} e_i e_j) for the
hand-computed values.
"""
from __future__ import annotations

import numpy as np
import pytest

import wingcrack_kernels as K
from wingcrack import error_estimate as ee

RNG = np.random.default_rng(35)


def uniform_mesh(N, L=1.0, jitter=0.0, seed=0):
    """[0, L]^2 in N x N squares, each split along its (0,0)-(1,1) diagonal:
    cell 2 (b N + a) is the lower, 2 (b N + a) + 1 the upper P2 triangle of
    square (a, b). Nodes on a (2N+1)^2 grid; vertex (I, J) is node 2J(2N+1) + 2I.
    `jitter` moves interior vertices by up to that fraction of a square (mid
    nodes follow to the edge midpoints)."""
    g = 2 * N + 1
    i, j = np.meshgrid(np.arange(g), np.arange(g))
    x = np.stack([i.ravel(), j.ravel()], axis=1) * (L / (2 * N))
    a, b = np.meshgrid(np.arange(N), np.arange(N))
    I, J = 2 * a.ravel(), 2 * b.ravel()
    n = lambda di, dj: (J + dj) * g + I + di  # noqa: E731
    lower = np.stack([n(0, 0), n(2, 0), n(2, 2), n(1, 0), n(2, 1), n(1, 1)], axis=1)
    upper = np.stack([n(0, 0), n(2, 2), n(0, 2), n(1, 1), n(1, 2), n(0, 1)], axis=1)
    cells = np.stack([lower, upper], axis=1).reshape(-1, 6).astype(np.int64)
    if jitter:
        rng = np.random.default_rng(seed)
        Iv, Jv = np.meshgrid(np.arange(1, N), np.arange(1, N))
        v = (2 * Jv * g + 2 * Iv).ravel()
        x[v] += rng.uniform(-jitter, jitter, (len(v), 2)) * (L / N)
        for k in range(3):
            x[cells[:, 3 + k]] = 0.5 * (x[cells[:, k]] + x[cells[:, (k + 1) % 3]])
    return x, cells


def vertex(N, I, J):
    return 2 * J * (2 * N + 1) + 2 * I


def vertex_edges(cells):
    return np.concatenate([cells[:, [k, (k + 1) % 3]] for k in range(3)])


def quadratic_stress(p):
    x, y = p[..., 0], p[..., 1]
    return np.stack([1 + 2 * x - y + 3 * x * x - 1.5 * x * y + 0.5 * y * y,
                     -0.5 + x + 4 * y + 1.2 * x * x + 2 * x * y - 2.5 * y * y,
                     0.3 - x + 0.7 * y - 0.8 * x * x + 1.1 * x * y + 1.9 * y * y], axis=-1)


def test_linear_stress_recovered_exactly_with_zero_error():
    x, cells = uniform_mesh(6, jitter=0.3, seed=7)
    A = RNG.uniform(-2, 2, (3, 3))  # sigma = A [1, x, y]
    sigma = lambda p: A[:, 0] + p[..., :1] * A[:, 1] + p[..., 1:] * A[:, 2]  # noqa: E731
    rec, eta = K.zz_error(x, cells, sigma(x[cells[:, :3]]))
    v = np.unique(cells[:, :3])
    # Weighted means of equal O(1) values: a few roundings.
    np.testing.assert_allclose(rec[v], sigma(x[v]), rtol=0, atol=1e-12)
    assert eta.shape == (len(cells),) and eta.max() < 1e-12
    assert np.isnan(rec[cells[:, 3:]]).all()  # mid nodes get no value
    np.testing.assert_allclose(ee.recovered_stress_error(x, cells, sigma(x[cells[:, :3]])), eta, rtol=0, atol=0)


def test_piecewise_constant_two_by_two_patch_hand_values():
    # sxx of the cells: L00=1, U00=2, L10=3, U10=4, L01=5, U01=6, L11=7, U11=8;
    # equal areas -> plain means of the cells at each vertex (see the C++ test).
    x, cells = uniform_mesh(2)
    c = np.arange(1.0, 9.0)
    s = np.repeat(np.stack([c, 10 - c, np.full(8, 3.0)], axis=1)[:, None, :], 3, axis=1)
    rec, eta = K.zz_error(x, cells, s)
    expected = np.array([[1.5, 8 / 3, 3], [13 / 3, 4.5, 14 / 3], [6, 19 / 3, 7.5]])  # [J, I]
    for J in range(3):
        for I in range(3):
            np.testing.assert_allclose(rec[vertex(2, I, J)], [expected[J, I], 10 - expected[J, I], 3.0],
                                       rtol=0, atol=1e-14)
    e = 1 - np.array([1.5, 8 / 3, 4.5])  # cell L00, area 1/8; syy errors are the negatives
    one = 0.125 / 6 * (e @ e + e[0] * e[1] + e[0] * e[2] + e[1] * e[2])
    assert eta[0] == pytest.approx(np.sqrt(2 * one), abs=1e-14)


def test_area_weights_on_two_unequal_cells():
    # Areas 1 and 3 sharing the edge (2,0)-(0,1): sxx 1 | 5 -> 4 there, sxy 0 | 2 -> 1.5;
    # eta^2 = 4.5 + 2 * 1.125 and 1.5 + 2 * 0.375 (sxy counted twice).
    x = np.array([[0, 0], [2, 0], [0, 1], [2, 3], [1, 0.5], [0, 0], [0, 0]], float)
    cells = np.array([[0, 1, 2, 5, 4, 6], [1, 3, 2, 5, 6, 4]])
    s = np.zeros((2, 3, 3))
    s[0, :, 0], s[1, :, 0], s[1, :, 2] = 1, 5, 2
    rec, eta = K.zz_error(x, cells, s)
    np.testing.assert_allclose(rec[[0, 1, 2, 3], 0], [1, 4, 4, 5], rtol=0, atol=1e-15)
    np.testing.assert_allclose(rec[[1, 2], 2], [1.5, 1.5], rtol=0, atol=1e-15)
    np.testing.assert_allclose(eta, np.sqrt([6.75, 2.25]), rtol=0, atol=1e-14)


def test_rates_of_smooth_stress_sampled_per_cell():
    # Centroid value per cell (P1-like): total eta ~ h; linear Taylor
    # expansion about the centroid (P2-like): ~ h^2. Rates within 0.15.
    totals = []
    for N in (8, 16, 32):
        x, cells = uniform_mesh(N)
        v = x[cells[:, :3]]
        g = v.mean(axis=1)
        s0 = quadratic_stress(g)
        d = 1e-6  # central differences are exact for a quadratic up to roundings ~1e-10
        grad = np.stack([(quadratic_stress(g + [d, 0]) - quadratic_stress(g - [d, 0])) / (2 * d),
                         (quadratic_stress(g + [0, d]) - quadratic_stress(g - [0, d])) / (2 * d)], axis=-1)
        const = np.repeat(s0[:, None], 3, axis=1)
        lin = s0[:, None] + np.einsum("cqj,ckj->ckq", grad, v - g[:, None])
        totals.append([np.linalg.norm(ee.recovered_stress_error(x, cells, s)) for s in (const, lin)])
    rates = np.log2(np.array(totals)[:-1] / np.array(totals)[1:])
    np.testing.assert_allclose(rates[:, 0], 1.0, atol=0.15)
    np.testing.assert_allclose(rates[:, 1], 2.0, atol=0.15)


def test_zz_sizes_equidistribution_and_clamps():
    N, h = 10, 0.1
    x, cells = uniform_mesh(N)
    m = len(cells)
    hc = np.full(m, h)
    v = np.unique(cells[:, :3])
    for p in (0.5, 1.0, 2.0):
        s = K.zz_sizes(x, cells, np.full(m, 2.0 / np.sqrt(m)), hc, 2.0, p, 1e-3, 1.0)
        np.testing.assert_allclose(s[v], h, rtol=0, atol=1e-15)
        assert np.isnan(s[cells[:, 3:]]).all()
    s = K.zz_sizes(x, cells, np.full(m, 4 / np.sqrt(m)), hc, 1.0, h_min=1e-3, h_max=1.0)  # p = 1 by default
    np.testing.assert_allclose(s[v], h / 4, rtol=0, atol=1e-15)
    s = K.zz_sizes(x, cells, np.full(m, 4 / np.sqrt(m)), hc, 1.0, p=2.0, h_min=1e-3, h_max=1.0)
    np.testing.assert_allclose(s[v], h / 2, rtol=0, atol=1e-15)
    assert (K.zz_sizes(x, cells, np.full(m, 1e9), hc, 1.0, h_min=0.01, h_max=0.5)[v] == 0.01).all()
    assert (K.zz_sizes(x, cells, np.zeros(m), hc, 1.0, h_min=0.01, h_max=0.5)[v] == 0.5).all()


def test_zz_sizes_grading_holds_on_every_edge():
    x, cells = uniform_mesh(20, jitter=0.3, seed=11)
    m, g = len(cells), 0.5
    r = np.linalg.norm(x[cells[:, :3]].mean(axis=1) - [0.3, 0.6], axis=1)
    eta = 10 ** RNG.uniform(-1, 1, m) * 0.05 * (0.05 / (r + 0.01)) ** 2
    hc = np.full(m, 0.05)
    raw = K.zz_sizes(x, cells, eta, hc, 1.0, 1.0, 1e-4, 0.3, grading=1e30)
    s = K.zz_sizes(x, cells, eta, hc, 1.0, 1.0, 1e-4, 0.3, grading=g)
    a, b = vertex_edges(cells).T
    L = np.linalg.norm(x[a] - x[b], axis=1)
    # A few ulps of sizes <= 0.3 (ulp 5.6e-17).
    assert np.all(np.abs(s[a] - s[b]) <= g * L + 1e-15)
    v = np.unique(cells[:, :3])
    assert np.all(s[v] <= raw[v]) and np.all(s[v] >= 1e-4) and np.all(s[v] <= 0.3)
    assert np.count_nonzero(s[v] < raw[v]) > 20
    assert np.count_nonzero(np.abs(raw[a] - raw[b]) > g * L) > 20  # the ungraded field does break it


def test_size_field_wrapper():
    # Uniform mesh, stress sigma0 constant on the unit square: ||sigma|| = |sigma0|,
    # target = f |sigma0|. Equal eta_c = target / sqrt(m) keeps every cell's size,
    # the mean vertex-edge length h (2 + sqrt 2) / 3 of the right triangles.
    N, f = 8, 0.05
    x, cells = uniform_mesh(N)
    m = len(cells)
    s0 = np.array([2e6, -1e6, 0.5e6])
    stress = np.broadcast_to(s0, (m, 3, 3))
    norm = np.sqrt(s0[0] ** 2 + s0[1] ** 2 + 2 * s0[2] ** 2)
    assert ee.stress_norm(x, cells, stress) == pytest.approx(norm, rel=1e-14)
    h = (2 + np.sqrt(2)) / 3 / N
    np.testing.assert_allclose(ee.cell_sizes(x, cells), h, rtol=1e-14)
    pts, vals = ee.size_field(x, cells, np.full(m, f * norm / np.sqrt(m)), 1e-4, 1.0, f, cell_stress=stress)
    assert pts.shape == ((N + 1) ** 2, 2) and vals.shape == ((N + 1) ** 2,)
    np.testing.assert_allclose(vals, h, rtol=1e-13)
    np.testing.assert_array_equal(pts, x[np.unique(cells[:, :3])])
    # Half the fraction with p = 1: half the sizes.
    _, vals = ee.size_field(x, cells, np.full(m, f * norm / np.sqrt(m)), 1e-4, 1.0, f / 2, cell_stress=stress)
    np.testing.assert_allclose(vals, h / 2, rtol=1e-13)
    with pytest.raises(ValueError):
        ee.size_field(x, cells, np.ones(m), 1e-4, 1.0, cell_stress=np.zeros((m, 3, 3)))


def test_bad_shapes_and_values_raise():
    x, cells = uniform_mesh(2)
    with pytest.raises(ValueError, match=r"\(m, 3, 3\)"):
        K.zz_error(x, cells, np.zeros((8, 9)))
    with pytest.raises(ValueError):
        K.zz_error(x, cells, np.zeros((7, 3, 3)))
    with pytest.raises(ValueError):
        K.zz_sizes(x, cells, np.ones(7), np.ones(8), 1.0, 1.0, 0.1, 1.0)
    with pytest.raises(ValueError):
        K.zz_sizes(x, cells, np.ones(8), np.ones(8), 1.0, 1.0, 0.5, 0.1)
    with pytest.raises(TypeError):
        K.zz_sizes(x, cells, np.ones(8), np.ones(8), 1.0, h_min=0.1)  # h_max has no default
