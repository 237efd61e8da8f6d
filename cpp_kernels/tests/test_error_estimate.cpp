// The Zienkiewicz-Zhu estimator and its size field against hand-computed and
// closed-form references. References: Zienkiewicz & Zhu (1987), Int. J.
// Numer. Meth. Eng. 24, 337-357 (recovery by nodal averaging, equidistribution
// remeshing rule); paper eqs. (35)-(36). Exact integral of a linear field
// squared on a triangle: int (sum e_i l_i)^2 = A/6 (sum e_i^2 + sum_{i<j} e_i e_j).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

#include "wingcrack/error_estimate.hpp"

using namespace wingcrack;

namespace {

// [0, L]^2 cut into N x N squares, each split along its (0,0)-(1,1) diagonal
// into a lower and an upper P2 triangle. Nodes live on a (2N+1)^2 grid of
// spacing L/(2N); vertices are the even-even grid nodes. Cell 2 (b N + a) is
// the lower triangle of square (a, b), cell 2 (b N + a) + 1 the upper one.
struct UniformMesh {
  int N;
  double L;
  Coords2 x;
  P2Cells cells;
  UniformMesh(int N_, double L_) : N(N_), L(L_) {
    const int g = 2 * N + 1;
    x.resize(g * g, 2);
    for (int j = 0; j < g; ++j)
      for (int i = 0; i < g; ++i) x.row(j * g + i) << L * i / (2.0 * N), L * j / (2.0 * N);
    auto id = [g](int i, int j) { return static_cast<std::int64_t>(j * g + i); };
    cells.resize(2 * N * N, 6);
    for (int b = 0; b < N; ++b)
      for (int a = 0; a < N; ++a) {
        const int i = 2 * a, j = 2 * b, c = 2 * (b * N + a);
        cells.row(c) << id(i, j), id(i + 2, j), id(i + 2, j + 2), id(i + 1, j), id(i + 2, j + 1), id(i + 1, j + 1);
        cells.row(c + 1) << id(i, j), id(i + 2, j + 2), id(i, j + 2), id(i + 1, j + 1), id(i + 1, j + 2),
            id(i, j + 1);
      }
  }
  std::int64_t vertex(int I, int J) const { return (2 * J) * (2 * N + 1) + 2 * I; }
  // Moves every interior vertex randomly (by up to `frac` of a square) and
  // puts the mid nodes back at the edge midpoints: cells of unequal areas.
  void jitter(double frac, unsigned seed) {
    std::mt19937 gen(seed);
    std::uniform_real_distribution<double> u(-frac, frac);
    const double h = L / N;
    for (int J = 1; J < N; ++J)
      for (int I = 1; I < N; ++I) x.row(vertex(I, J)) += h * Eigen::RowVector2d(u(gen), u(gen));
    for (Eigen::Index c = 0; c < cells.rows(); ++c)
      for (int k = 0; k < 3; ++k) x.row(cells(c, 3 + k)) = 0.5 * (x.row(cells(c, k)) + x.row(cells(c, (k + 1) % 3)));
  }
};

double tri_area(const Coords2& x, const P2Cells& cells, Eigen::Index c) {
  const Eigen::Vector2d a = x.row(cells(c, 0)), b = x.row(cells(c, 1)), d = x.row(cells(c, 2));
  return 0.5 * std::abs((b - a).x() * (d - a).y() - (b - a).y() * (d - a).x());
}

// A cell stress set from a function of position evaluated per vertex.
template <class F>
CellStress sample_at_vertices(const Coords2& x, const P2Cells& cells, F sigma) {
  CellStress s(cells.rows(), 9);
  for (Eigen::Index c = 0; c < cells.rows(); ++c)
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d v = sigma(x(cells(c, k), 0), x(cells(c, k), 1));
      for (int q = 0; q < 3; ++q) s(c, 3 * k + q) = v(q);
    }
  return s;
}

double total(const Eigen::VectorXd& eta) { return eta.norm(); }  // sqrt(sum eta_c^2)

// Smooth quadratic stress (Pa, x in m): curvature, mixed and linear terms in every component.
Eigen::Vector3d quadratic_stress(double x, double y) {
  return {1.0 + 2.0 * x - y + 3.0 * x * x - 1.5 * x * y + 0.5 * y * y,
          -0.5 + x + 4.0 * y + 1.2 * x * x + 2.0 * x * y - 2.5 * y * y,
          0.3 - x + 0.7 * y - 0.8 * x * x + 1.1 * x * y + 1.9 * y * y};
}
Eigen::Matrix<double, 3, 2> quadratic_stress_gradient(double x, double y) {
  Eigen::Matrix<double, 3, 2> g;
  g << 2.0 + 6.0 * x - 1.5 * y, -1.0 - 1.5 * x + 1.0 * y,  //
      1.0 + 2.4 * x + 2.0 * y, 4.0 + 2.0 * x - 5.0 * y,     //
      -1.0 - 1.6 * x + 1.1 * y, 0.7 + 1.1 * x + 3.8 * y;
  return g;
}

}  // namespace

TEST(ZZError, GloballyLinearStressIsRecoveredExactlyWithZeroError) {
  UniformMesh mesh(6, 1.0);
  mesh.jitter(0.3, 7);  // unequal areas: the weights do matter, the result must not
  const auto sigma = [](double x, double y) {
    return Eigen::Vector3d(0.4 + 1.3 * x - 0.7 * y, -1.1 + 0.2 * x + 0.9 * y, 0.25 - 0.6 * x + 1.7 * y);
  };
  const ZZError r = zz_error(mesh.x, mesh.cells, sample_at_vertices(mesh.x, mesh.cells, sigma));
  // A weighted mean of equal values: a few roundings of O(1) numbers.
  for (int J = 0; J <= mesh.N; ++J)
    for (int I = 0; I <= mesh.N; ++I) {
      const auto v = mesh.vertex(I, J);
      const Eigen::Vector3d expected = sigma(mesh.x(v, 0), mesh.x(v, 1));
      EXPECT_NEAR((r.recovered.row(v).transpose() - expected).norm(), 0.0, 1e-12) << I << " " << J;
    }
  EXPECT_LT(r.eta.maxCoeff(), 1e-12);
  // Mid-edge nodes carry no recovered value.
  EXPECT_TRUE(std::isnan(r.recovered(mesh.cells(0, 3), 0)));
}

TEST(ZZError, PiecewiseConstantOnTwoByTwoPatchHandValues) {
  // Cells L00=1, U00=2, L10=3, U10=4, L01=5, U01=6, L11=7, U11=8 (sxx); equal
  // areas, so sigma*_i is the plain mean of the cells at vertex i:
  //   (0,0): L00 U00 -> 3/2          (1,0): L00 L10 U10 -> 8/3     (2,0): L10 -> 3
  //   (0,1): U00 L01 U01 -> 13/3     (1,1): 1,2,4,5,7,8 -> 9/2     (2,1): L10 U10 L11 -> 14/3
  //   (0,2): U01 -> 6                (1,2): L01 U01 U11 -> 19/3    (2,2): L11 U11 -> 15/2
  // syy = 10 - sxx (an affine map commutes with the mean), sxy = 3 everywhere.
  UniformMesh mesh(2, 1.0);
  CellStress s(8, 9);
  for (int c = 0; c < 8; ++c)
    for (int k = 0; k < 3; ++k) s.block<1, 3>(c, 3 * k) << c + 1.0, 10.0 - (c + 1.0), 3.0;
  const ZZError r = zz_error(mesh.x, mesh.cells, s);
  const double expected[3][3] = {{1.5, 8.0 / 3, 3.0}, {13.0 / 3, 4.5, 14.0 / 3}, {6.0, 19.0 / 3, 7.5}};
  for (int J = 0; J < 3; ++J)
    for (int I = 0; I < 3; ++I) {
      const auto v = mesh.vertex(I, J);
      EXPECT_NEAR(r.recovered(v, 0), expected[J][I], 1e-14) << I << " " << J;
      EXPECT_NEAR(r.recovered(v, 1), 10.0 - expected[J][I], 1e-14);
      EXPECT_NEAR(r.recovered(v, 2), 3.0, 1e-14);
    }
  // eta of cell L00 (vertices (0,0), (1,0), (1,1), area 1/8): e = 1 - sigma* =
  // (-1/2, -5/3, -7/2) in sxx and the negatives in syy, 0 in sxy.
  const double e0 = -0.5, e1 = -5.0 / 3, e2 = -3.5;
  const double one = 0.125 / 6 * (e0 * e0 + e1 * e1 + e2 * e2 + e0 * e1 + e0 * e2 + e1 * e2);
  EXPECT_NEAR(r.eta(0), std::sqrt(2.0 * one), 1e-14);
}

TEST(ZZError, AreaWeightsOnTwoUnequalCells) {
  // A = (0,0),(2,0),(0,1), area 1; B = (2,0),(2,3),(0,1), area 3; shared edge (2,0)-(0,1).
  // sxx: A 1, B 5 -> shared vertices (1*1 + 3*5)/4 = 4; sxy: A 0, B 2 -> 6/4 = 1.5.
  // eta_A^2 = 1/6 (0 + 9 + 9 + 9) + 2 * 1/6 (0 + 2.25 + 2.25 + 2.25) = 4.5 + 2.25 = 6.75
  // eta_B^2 = 3/6 (1 + 1 + 0 + 1) + 2 * 3/6 (0.25 + 0.25 + 0 + 0.25) = 1.5 + 0.75 = 2.25
  Coords2 x(7, 2);
  x << 0, 0, 2, 0, 0, 1, 2, 3, 1, 0.5, 0, 0, 0, 0;  // 4: shared mid; 5, 6: unused stand-ins for mids
  P2Cells cells(2, 6);
  cells << 0, 1, 2, 5, 4, 6, 1, 3, 2, 5, 6, 4;
  CellStress s(2, 9);
  for (int k = 0; k < 3; ++k) {
    s.block<1, 3>(0, 3 * k) << 1.0, 0.0, 0.0;
    s.block<1, 3>(1, 3 * k) << 5.0, 0.0, 2.0;
  }
  const ZZError r = zz_error(x, cells, s);
  EXPECT_NEAR(r.recovered(0, 0), 1.0, 1e-15);
  EXPECT_NEAR(r.recovered(3, 0), 5.0, 1e-15);
  for (int v : {1, 2}) {
    EXPECT_NEAR(r.recovered(v, 0), 4.0, 1e-15);
    EXPECT_NEAR(r.recovered(v, 2), 1.5, 1e-15);
  }
  EXPECT_NEAR(r.eta(0), std::sqrt(6.75), 1e-14);
  EXPECT_NEAR(r.eta(1), std::sqrt(2.25), 1e-14);
}

TEST(ZZError, RateOfSmoothStressSampledPerCell) {
  // A quadratic stress sampled per cell (1) as a constant, its centroid value
  // (a P1-like stress): the error is O(h) pointwise and the total
  // sqrt(sum eta_c^2) goes like h; (2) as its linear Taylor expansion about the
  // centroid (a P2-like, discontinuous linear stress): O(h^2). Meshes N = 8,
  // 16, 32; the two observed rates must be within 0.15 of 1 and 2.
  double prev_const = 0, prev_lin = 0;
  for (int N : {8, 16, 32}) {
    UniformMesh mesh(N, 1.0);
    CellStress sc(mesh.cells.rows(), 9), sl(mesh.cells.rows(), 9);
    for (Eigen::Index c = 0; c < mesh.cells.rows(); ++c) {
      Eigen::Vector2d g = Eigen::Vector2d::Zero();
      for (int k = 0; k < 3; ++k) g += mesh.x.row(mesh.cells(c, k)).transpose() / 3.0;
      const Eigen::Vector3d s0 = quadratic_stress(g.x(), g.y());
      const auto grad = quadratic_stress_gradient(g.x(), g.y());
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector2d d = mesh.x.row(mesh.cells(c, k)).transpose() - g;
        sc.block<1, 3>(c, 3 * k) = s0.transpose();
        sl.block<1, 3>(c, 3 * k) = (s0 + grad * d).transpose();
      }
    }
    const double ec = total(zz_error(mesh.x, mesh.cells, sc).eta);
    const double el = total(zz_error(mesh.x, mesh.cells, sl).eta);
    if (N > 8) {
      const double rc = std::log2(prev_const / ec), rl = std::log2(prev_lin / el);
      std::printf("N=%d  eta const %.4e rate %.3f   eta linear %.4e rate %.3f\n", N, ec, rc, el, rl);
      EXPECT_NEAR(rc, 1.0, 0.15);
      EXPECT_NEAR(rl, 2.0, 0.15);
    }
    prev_const = ec;
    prev_lin = el;
  }
}

TEST(ZZError, RejectsBadInput) {
  UniformMesh mesh(2, 1.0);
  EXPECT_THROW(zz_error(mesh.x, mesh.cells, CellStress::Zero(7, 9)), std::invalid_argument);
  P2Cells bad = mesh.cells;
  bad(0, 2) = 1000;
  EXPECT_THROW(zz_error(mesh.x, bad, CellStress::Zero(8, 9)), std::invalid_argument);
  bad = mesh.cells;
  bad(0, 2) = bad(0, 1);  // zero area
  EXPECT_THROW(zz_error(mesh.x, bad, CellStress::Zero(8, 9)), std::invalid_argument);
}

namespace {

// Every vertex edge a-b of the mesh.
std::vector<std::pair<std::int64_t, std::int64_t>> vertex_edges(const P2Cells& cells) {
  std::vector<std::pair<std::int64_t, std::int64_t>> e;
  for (Eigen::Index c = 0; c < cells.rows(); ++c)
    for (int k = 0; k < 3; ++k) e.emplace_back(cells(c, k), cells(c, (k + 1) % 3));
  return e;
}

}  // namespace

TEST(ZZSizes, EqualErrorsKeepTheSizes) {
  // eta_c = e* = target / sqrt(m) everywhere: h_c' = h_c, for any p; the
  // uniform field passes the grading untouched. Only pow(1, 1/p) roundings.
  UniformMesh mesh(10, 2.0);
  const Eigen::Index m = mesh.cells.rows();
  const double target = 3.7, h = 0.2;
  const Eigen::VectorXd eta = Eigen::VectorXd::Constant(m, target / std::sqrt(double(m)));
  for (double p : {0.5, 1.0, 2.0}) {
    const Eigen::VectorXd s = zz_sizes(mesh.x, mesh.cells, eta, Eigen::VectorXd::Constant(m, h), target, p, 1e-3, 1.0);
    for (int J = 0; J <= mesh.N; ++J)
      for (int I = 0; I <= mesh.N; ++I) EXPECT_NEAR(s(mesh.vertex(I, J)), h, 1e-15);
    EXPECT_TRUE(std::isnan(s(mesh.cells(0, 3))));  // mid nodes get no size
  }
}

TEST(ZZSizes, ScalingRuleAndClamps) {
  UniformMesh mesh(4, 1.0);
  const Eigen::Index m = mesh.cells.rows();
  const double target = 1.0, e_star = target / std::sqrt(double(m)), h = 0.25;
  const Eigen::VectorXd hc = Eigen::VectorXd::Constant(m, h);
  // 4x the allowed error with p = 2 -> half the size; p = 1 -> a quarter.
  Eigen::VectorXd s = zz_sizes(mesh.x, mesh.cells, Eigen::VectorXd::Constant(m, 4 * e_star), hc, target, 2.0, 1e-3, 1.0);
  EXPECT_NEAR(s(mesh.vertex(2, 2)), h / 2, 1e-15);
  s = zz_sizes(mesh.x, mesh.cells, Eigen::VectorXd::Constant(m, 4 * e_star), hc, target, 1.0, 1e-3, 1.0);
  EXPECT_NEAR(s(mesh.vertex(2, 2)), h / 4, 1e-15);
  // Huge error -> h_min; zero error -> h_max; tiny error -> h_max.
  s = zz_sizes(mesh.x, mesh.cells, Eigen::VectorXd::Constant(m, 1e9), hc, target, 1.0, 0.01, 0.5);
  EXPECT_EQ(s(mesh.vertex(1, 3)), 0.01);
  s = zz_sizes(mesh.x, mesh.cells, Eigen::VectorXd::Zero(m), hc, target, 1.0, 0.01, 0.5);
  EXPECT_EQ(s(mesh.vertex(1, 3)), 0.5);
  s = zz_sizes(mesh.x, mesh.cells, Eigen::VectorXd::Constant(m, 1e-300), hc, target, 1.0, 0.01, 0.5);
  EXPECT_EQ(s(mesh.vertex(1, 3)), 0.5);
  // A vertex takes the smallest size its cells ask for: one cell (the lower
  // triangle of square (1,1), vertices (1,1), (2,1), (2,2)) at 2x error, p = 1.
  Eigen::VectorXd eta = Eigen::VectorXd::Constant(m, e_star);
  eta(2 * (1 * 4 + 1)) = 2 * e_star;
  s = zz_sizes(mesh.x, mesh.cells, eta, hc, target, 1.0, 1e-3, 1.0, 10.0);  // grading 10: inactive here
  EXPECT_NEAR(s(mesh.vertex(1, 1)), h / 2, 1e-15);
  EXPECT_NEAR(s(mesh.vertex(2, 2)), h / 2, 1e-15);
  EXPECT_NEAR(s(mesh.vertex(0, 0)), h, 1e-15);
}

TEST(ZZSizes, GradingHoldsOnEveryEdgeAndIsTight) {
  // A point-singularity-like error, eta ~ r^-2 about (0.3, 0.6) times a random
  // factor in [0.1, 10], on a jittered mesh: sizes from h_min to h_max with
  // abrupt jumps between neighbours. After grading,
  // s_i <= s_j + g |x_i - x_j| on every edge, s never exceeds the ungraded
  // field (the same call with g = 1e30, which grades nothing), and every
  // lowered vertex is held down by a neighbour with equality (so s is the
  // largest admissible field, not merely an admissible one).
  UniformMesh mesh(20, 1.0);
  mesh.jitter(0.3, 11);
  const Eigen::Index m = mesh.cells.rows();
  std::mt19937 gen(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::VectorXd eta(m);
  for (Eigen::Index c = 0; c < m; ++c) {
    Eigen::Vector2d g = Eigen::Vector2d::Zero();
    for (int k = 0; k < 3; ++k) g += mesh.x.row(mesh.cells(c, k)).transpose() / 3.0;
    const double r = (g - Eigen::Vector2d(0.3, 0.6)).norm();
    eta(c) = std::pow(10.0, u(gen)) * 0.05 * std::pow(0.05 / (r + 0.01), 2);
  }
  const Eigen::VectorXd hc = Eigen::VectorXd::Constant(m, 0.05);
  const double g = 0.5, hmin = 1e-4, hmax = 0.3;
  const Eigen::VectorXd raw = zz_sizes(mesh.x, mesh.cells, eta, hc, 1.0, 1.0, hmin, hmax, 1e30);
  const Eigen::VectorXd s = zz_sizes(mesh.x, mesh.cells, eta, hc, 1.0, 1.0, hmin, hmax, g);
  const auto edges = vertex_edges(mesh.cells);
  int lowered = 0;
  for (const auto& [a, b] : edges) {
    const double L = (mesh.x.row(a) - mesh.x.row(b)).norm();
    // Roundings of s_j + g L and hypot vs norm: a few ulps of sizes <= 0.3 (ulp 5.6e-17).
    EXPECT_LE(s(a), s(b) + g * L + 1e-15);
    EXPECT_LE(s(b), s(a) + g * L + 1e-15);
  }
  for (int J = 0; J <= mesh.N; ++J)
    for (int I = 0; I <= mesh.N; ++I) {
      const auto v = mesh.vertex(I, J);
      EXPECT_LE(s(v), raw(v));
      EXPECT_GE(s(v), hmin);
      EXPECT_LE(s(v), hmax);
      if (s(v) < raw(v)) {
        ++lowered;
        double best = std::numeric_limits<double>::infinity();
        for (const auto& [a, b] : edges) {
          if (a == v) best = std::min(best, s(b) + g * (mesh.x.row(a) - mesh.x.row(b)).norm());
          if (b == v) best = std::min(best, s(a) + g * (mesh.x.row(a) - mesh.x.row(b)).norm());
        }
        EXPECT_NEAR(s(v), best, 1e-15);
      }
    }
  std::printf("grading lowered %d of %d vertices\n", lowered, (mesh.N + 1) * (mesh.N + 1));
  EXPECT_GT(lowered, 20);  // the test exercises the grading
}

TEST(ZZSizes, RejectsBadInput) {
  UniformMesh mesh(2, 1.0);
  const Eigen::VectorXd one = Eigen::VectorXd::Ones(8);
  EXPECT_THROW(zz_sizes(mesh.x, mesh.cells, Eigen::VectorXd::Ones(7), one, 1, 1, 0.1, 1), std::invalid_argument);
  EXPECT_THROW(zz_sizes(mesh.x, mesh.cells, one, one, 0, 1, 0.1, 1), std::invalid_argument);
  EXPECT_THROW(zz_sizes(mesh.x, mesh.cells, one, one, 1, 1, 0.0, 1), std::invalid_argument);
  EXPECT_THROW(zz_sizes(mesh.x, mesh.cells, one, one, 1, 1, 2.0, 1), std::invalid_argument);
  EXPECT_THROW(zz_sizes(mesh.x, mesh.cells, -one, one, 1, 1, 0.1, 1), std::invalid_argument);
  EXPECT_THROW(zz_sizes(mesh.x, mesh.cells, one, one, 1, 1, 0.1, std::numeric_limits<double>::infinity()),
               std::invalid_argument);
}
