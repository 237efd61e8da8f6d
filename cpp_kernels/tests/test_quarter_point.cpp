// Quarter points and the P2 Jacobian against closed-form references.
#include <gtest/gtest.h>

#include <cmath>

#include "wingcrack/quarter_point.hpp"

using namespace wingcrack;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kA2 = 0.091576213509771;  // the Dunavant point closest to a vertex

// A rosette of `sectors` straight P2 triangles of radius r around (cx, cy):
// node 0 the tip, 1..s the ring, then s spoke mid nodes, then s chord mid nodes.
struct Rosette {
  Coords2 x;
  P2Cells cells;
  Rosette(int sectors, double r, double cx, double cy) {
    x.resize(1 + 3 * sectors, 2);
    x.row(0) << cx, cy;
    for (int k = 0; k < sectors; ++k) {
      const double t = 0.3 + 2.0 * kPi * k / sectors;
      x.row(1 + k) << cx + r * std::cos(t), cy + r * std::sin(t);
    }
    cells.resize(sectors, 6);
    for (int k = 0; k < sectors; ++k) {
      const int a = 1 + k, b = 1 + (k + 1) % sectors;
      const int spoke = 1 + sectors + k, chord = 1 + 2 * sectors + k;
      x.row(spoke) = 0.5 * (x.row(0) + x.row(a));
      x.row(chord) = 0.5 * (x.row(a) + x.row(b));
      cells.row(k) << 0, a, b, spoke, chord, 1 + sectors + (k + 1) % sectors;
    }
  }
  double cell_area(Eigen::Index c) const {
    const Eigen::Vector2d p = x.row(cells(c, 0)), q = x.row(cells(c, 1)), s = x.row(cells(c, 2));
    return 0.5 * ((q - p).x() * (s - p).y() - (q - p).y() * (s - p).x());
  }
};

}  // namespace

TEST(QuarterPoints, SpokeMidNodesMoveToOneQuarter) {
  const Rosette r(16, 0.5e-3, 0.01, -0.02);
  IndexVector tips(1);
  tips << 0;
  const Coords2 q = quarter_points(r.x, r.cells, tips);
  for (int k = 0; k < 16; ++k) {
    const Eigen::Vector2d expected = 0.75 * r.x.row(0) + 0.25 * r.x.row(1 + k);
    // One rounding in each of 0.75 a + 0.25 b: 1 ulp of |x| ~ 0.02 is 3.5e-18.
    EXPECT_NEAR((q.row(1 + 16 + k).transpose() - expected).norm(), 0.0, 1e-17);
    EXPECT_NEAR((q.row(1 + 16 + k) - r.x.row(0)).norm(), 0.25 * 0.5e-3, 1e-15);
    EXPECT_EQ(q.row(1 + 32 + k), r.x.row(1 + 32 + k));  // chord mids stay
  }
  EXPECT_EQ(q.row(0), r.x.row(0));
}

TEST(QuarterPoints, TipAtOriginExactQuarter) {
  // Tip at the origin and ring coordinates exact binary fractions: 0.25 b is exact.
  Coords2 x(6, 2);
  x << 0, 0, 1, 0, 0, 1, 0.5, 0, 0.5, 0.5, 0, 0.5;
  P2Cells c(1, 6);
  c << 0, 1, 2, 3, 4, 5;
  IndexVector tips(1);
  tips << 0;
  const Coords2 q = quarter_points(x, c, tips);
  EXPECT_EQ(q(3, 0), 0.25);
  EXPECT_EQ(q(3, 1), 0.0);
  EXPECT_EQ(q(5, 0), 0.0);
  EXPECT_EQ(q(5, 1), 0.25);
  EXPECT_EQ(q(4, 0), 0.5);
  EXPECT_EQ(q(4, 1), 0.5);
}

TEST(MinJacobian, StraightCellsGiveTwiceTheArea) {
  const Rosette r(16, 2.0, 0.3, 0.1);
  const Eigen::VectorXd j = min_jacobian(r.x, r.cells);
  for (Eigen::Index c = 0; c < r.cells.rows(); ++c) {
    // det J is constant = 2A; only rounding of sums of 6 terms ~ 1e-15 relative.
    EXPECT_NEAR(j(c), 2.0 * r.cell_area(c), 1e-14 * r.cell_area(c));
  }
}

TEST(MinJacobian, QuarterPointCellsStayValid) {
  // With mid nodes at 1/4 on both tip edges the P2 map is x = s (xi v1 + eta v2)
  // (tip at 0, s = xi + eta), so det J = 4 A s^2: zero only at the tip, and at
  // the 6 Dunavant points smallest where s = 2 a2.
  const Rosette r(16, 0.5e-3, 0.0, 0.0);
  IndexVector tips(1);
  tips << 0;
  const Coords2 q = quarter_points(r.x, r.cells, tips);
  const Eigen::VectorXd j = min_jacobian(q, r.cells);
  for (Eigen::Index c = 0; c < r.cells.rows(); ++c) {
    const double area = r.cell_area(c);
    EXPECT_GT(j(c), 0.0);
    EXPECT_NEAR(j(c), 4.0 * area * (2 * kA2) * (2 * kA2), 1e-12 * area);
  }
}

TEST(QuarterPoints, RejectsBadTip) {
  const Rosette r(16, 1.0, 0.0, 0.0);
  IndexVector tips(1);
  tips << 1000;
  EXPECT_THROW(quarter_points(r.x, r.cells, tips), std::invalid_argument);
}
