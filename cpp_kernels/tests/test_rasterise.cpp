// rasterise_p1 against closed-form references: a linear field is its own
// P1 interpolant, so every covered node must carry it exactly (to round-off);
// nodes on shared edges and outside every triangle by construction.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

#include "wingcrack/rasterise.hpp"

using namespace wingcrack;

namespace {

double linear(double x, double y) { return 0.3 + 1.7 * x - 0.9 * y; }

// [0, 1]^2 as N x N squares, each cut along a diagonal into two triangles,
// the interior vertices jittered (so that grid nodes fall anywhere in the
// triangles), with the values of `linear` at the vertices.
struct Square {
  Triangles2 tri;
  VertexValues val;
  Square(int N, double jitter, unsigned seed) {
    std::mt19937 gen(seed);
    std::uniform_real_distribution<double> u(-jitter, jitter);
    Eigen::MatrixXd px(N + 1, N + 1), py(N + 1, N + 1);
    for (int i = 0; i <= N; ++i)
      for (int j = 0; j <= N; ++j) {
        const bool inner = i > 0 && i < N && j > 0 && j < N;
        px(i, j) = (i + (inner ? u(gen) : 0.0)) / N;
        py(i, j) = (j + (inner ? u(gen) : 0.0)) / N;
      }
    tri.resize(2 * N * N, 6);
    val.resize(2 * N * N, 3);
    Eigen::Index c = 0;
    auto add = [&](int i0, int j0, int i1, int j1, int i2, int j2) {
      tri.row(c) << px(i0, j0), py(i0, j0), px(i1, j1), py(i1, j1), px(i2, j2), py(i2, j2);
      for (int k = 0; k < 3; ++k) val(c, k) = linear(tri(c, 2 * k), tri(c, 2 * k + 1));
      ++c;
    };
    for (int i = 0; i < N; ++i)
      for (int j = 0; j < N; ++j) {
        add(i, j, i + 1, j, i + 1, j + 1);
        add(i, j, i + 1, j + 1, i, j + 1);
      }
  }
};

}  // namespace

TEST(Rasterise, LinearFieldExactAtEveryCoveredNode) {
  const Square sq(7, 0.3, 17);
  // the grid overhangs the square by 2 steps on every side: those nodes are
  // covered by no triangle; every node of [0, 1]^2 is covered (the square's
  // boundary vertices are not jittered)
  const int n = 41;
  const double h = 1.0 / (n - 1 - 4);
  const Grid2 grid{{-2.0 * h, -2.0 * h}, {h, h}, {n, n}};
  const GridValues g = rasterise_p1(sq.tri, sq.val, grid, -1.0);
  int inside = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double x = -2.0 * h + i * h, y = -2.0 * h + j * h;
      if (i < 2 || j < 2 || i > n - 3 || j > n - 3) continue;
      ++inside;
      // round-off of the barycentric sums: a few ulps of the field's range (~3)
      EXPECT_NEAR(g(i, j), linear(x, y), 1e-14) << i << " " << j;
    }
  EXPECT_EQ(inside, 37 * 37);
}

TEST(Rasterise, UncoveredNodesTakeTheNearestCoveredValue) {
  const Square sq(4, 0.2, 3);
  const int n = 25;
  const double h = 1.0 / 20;
  const Grid2 grid{{-2.0 * h, -2.0 * h}, {h, h}, {n, n}};
  const GridValues g = rasterise_p1(sq.tri, sq.val, grid, -1.0);
  const auto cov = [&](int i, int j) { return linear((i - 2) * h, (j - 2) * h); };
  // straight out of an edge node: the edge's value
  EXPECT_NEAR(g(0, 10), cov(2, 10), 1e-14);
  EXPECT_NEAR(g(1, 10), cov(2, 10), 1e-14);
  EXPECT_NEAR(g(10, n - 1), cov(10, n - 3), 1e-14);
  // off a corner: (0, 0) is 4 steps from the corner node (2, 2) and 5 or
  // more from every other covered node; (1, 0) 3 from (2, 2), 4 from (3, 2)
  EXPECT_NEAR(g(0, 0), cov(2, 2), 1e-14);
  EXPECT_NEAR(g(1, 0), cov(2, 2), 1e-14);
  // (0, 3) is 2 steps from (2, 3) and 3 from (2, 2) and (2, 4)
  EXPECT_NEAR(g(0, 3), cov(2, 3), 1e-14);
}

TEST(Rasterise, TiesInTheDilationTakeTheSmallest) {
  // two separate triangles; node (2, 0) of a 5 x 1 grid is 2 steps from the
  // node (0, 0) in the first and (4, 0) in the second
  Triangles2 tri(2, 6);
  tri.row(0) << -0.5, -0.5, 0.5, -0.5, 0.0, 0.5;
  tri.row(1) << 3.5, -0.5, 4.5, -0.5, 4.0, 0.5;
  VertexValues val(2, 3);
  val.row(0) << 5.0, 5.0, 5.0;
  val.row(1) << 2.0, 2.0, 2.0;
  const GridValues g = rasterise_p1(tri, val, Grid2{{0.0, 0.0}, {1.0, 1.0}, {5, 1}}, -1.0);
  EXPECT_EQ(g(0, 0), 5.0);
  EXPECT_EQ(g(1, 0), 5.0);
  EXPECT_EQ(g(2, 0), 2.0);
  EXPECT_EQ(g(3, 0), 2.0);
  EXPECT_EQ(g(4, 0), 2.0);
}

TEST(Rasterise, NodeOnASharedEdgeTakesTheSmallerSide) {
  // the unit square's two triangles share the diagonal (0,0)-(1,1); the
  // field jumps across it: 1 on the lower triangle, 2 + x on the upper one.
  // Grid spacing 1/4 puts nodes (0,0), (1,1), (2,2), (3,3), (4,4) on it, in
  // binary floating point exactly (and (1,1) off 0.1 steps would not be).
  Triangles2 tri(2, 6);
  tri.row(0) << 0.0, 0.0, 1.0, 0.0, 1.0, 1.0;
  tri.row(1) << 0.0, 0.0, 1.0, 1.0, 0.0, 1.0;
  VertexValues val(2, 3);
  val.row(0) << 1.0, 1.0, 1.0;
  val.row(1) << 2.0, 3.0, 2.0;
  const GridValues g = rasterise_p1(tri, val, Grid2{{0.0, 0.0}, {0.25, 0.25}, {5, 5}}, -1.0);
  for (int k = 0; k < 5; ++k) EXPECT_EQ(g(k, k), 1.0) << k;
  EXPECT_EQ(g(3, 1), 1.0);                   // below the diagonal
  EXPECT_NEAR(g(1, 3), 2.0 + 0.25, 1e-15);   // above it: 2 + x
  // the other order of the triangles gives the same
  Triangles2 swapped(2, 6);
  swapped << tri.row(1), tri.row(0);
  VertexValues sval(2, 3);
  sval << val.row(1), val.row(0);
  EXPECT_EQ(rasterise_p1(swapped, sval, Grid2{{0.0, 0.0}, {0.25, 0.25}, {5, 5}}, -1.0), g);
}

TEST(Rasterise, SharedEdgeOffTheBinaryGrid) {
  // A shared edge at an angle whose nodes are not exact in binary: the two
  // triangles (0,0),(0.3,0),(0.3,0.7) and (0,0),(0.3,0.7),(0,0.7) share the
  // diagonal, grid nodes of spacing 0.1 x 0.1 with j = 7 i / 3 lie on it for
  // i = 0, 3. With a continuous field every node must be covered (not filled).
  Triangles2 tri(2, 6);
  tri.row(0) << 0.0, 0.0, 0.3, 0.0, 0.3, 0.7;
  tri.row(1) << 0.0, 0.0, 0.3, 0.7, 0.0, 0.7;
  VertexValues val(2, 3);
  for (Eigen::Index c = 0; c < 2; ++c)
    for (int k = 0; k < 3; ++k) val(c, k) = linear(tri(c, 2 * k), tri(c, 2 * k + 1));
  const GridValues g = rasterise_p1(tri, val, Grid2{{0.0, 0.0}, {0.1, 0.1}, {4, 8}}, -100.0);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 8; ++j) EXPECT_NEAR(g(i, j), linear(0.1 * i, 0.1 * j), 1e-14) << i << " " << j;
}

TEST(Rasterise, NothingCoveredGivesFill) {
  Triangles2 tri(1, 6);
  tri.row(0) << 10.0, 10.0, 11.0, 10.0, 10.0, 11.0;  // off the grid
  VertexValues val(1, 3);
  val.row(0) << 1.0, 1.0, 1.0;
  const GridValues g = rasterise_p1(tri, val, Grid2{{0.0, 0.0}, {1.0, 1.0}, {3, 2}}, 7.5);
  EXPECT_TRUE((g.array() == 7.5).all());
  // no triangles at all, and a degenerate one
  EXPECT_TRUE((rasterise_p1(Triangles2(0, 6), VertexValues(0, 3), Grid2{{0.0, 0.0}, {1.0, 1.0}, {2, 2}}, 3.0)
                   .array() == 3.0)
                  .all());
  tri.row(0) << 0.0, 0.0, 1.0, 1.0, 2.0, 2.0;
  EXPECT_TRUE((rasterise_p1(tri, val, Grid2{{0.0, 0.0}, {1.0, 1.0}, {3, 3}}, 3.0).array() == 3.0).all());
}

TEST(Rasterise, ClockwiseTrianglesCountAlike) {
  const Square sq(3, 0.2, 5);
  Triangles2 cw = sq.tri;
  VertexValues cwv = sq.val;
  cw.col(2).swap(cw.col(4));
  cw.col(3).swap(cw.col(5));
  cwv.col(1).swap(cwv.col(2));
  const Grid2 grid{{0.0, 0.0}, {0.1, 0.1}, {11, 11}};
  EXPECT_TRUE(rasterise_p1(cw, cwv, grid, 0.0).isApprox(rasterise_p1(sq.tri, sq.val, grid, 0.0), 1e-15));
}

TEST(Rasterise, RejectsBadInput) {
  const Square sq(2, 0.0, 1);
  const Grid2 ok{{0.0, 0.0}, {0.5, 0.5}, {3, 3}};
  EXPECT_THROW(rasterise_p1(sq.tri, sq.val.topRows(1), ok, 0.0), std::invalid_argument);
  EXPECT_THROW(rasterise_p1(sq.tri, sq.val, Grid2{{0.0, 0.0}, {0.0, 0.5}, {3, 3}}, 0.0), std::invalid_argument);
  EXPECT_THROW(rasterise_p1(sq.tri, sq.val, Grid2{{0.0, 0.0}, {0.5, 0.5}, {3, 0}}, 0.0), std::invalid_argument);
  EXPECT_THROW(rasterise_p1(sq.tri, sq.val, ok, std::numeric_limits<double>::quiet_NaN()), std::invalid_argument);
  VertexValues bad = sq.val;
  bad(1, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(rasterise_p1(sq.tri, bad, ok, 0.0), std::invalid_argument);
}
