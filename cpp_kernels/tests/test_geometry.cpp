// Polyline geometry: tip frames (the contract of docs/architecture.md),
// segment intersection in every configuration, distances.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "wingcrack/geometry.hpp"

using namespace wingcrack;

namespace {

Points2 poly(std::initializer_list<std::pair<double, double>> xy) {
  Points2 p(static_cast<Eigen::Index>(xy.size()), 2);
  Eigen::Index i = 0;
  for (const auto& [x, y] : xy) p.row(i++) << x, y;
  return p;
}

// Hit, point and the swapped parameters must not depend on which segment is
// first; the formulas are exactly antisymmetric, so equality is exact.
SegmentHit both_orders(const Point2& p0, const Point2& p1, const Point2& q0, const Point2& q1, double tol = 1e-12) {
  const SegmentHit a = segment_intersection(p0, p1, q0, q1, tol);
  const SegmentHit b = segment_intersection(q0, q1, p0, p1, tol);
  EXPECT_EQ(a.hit, b.hit);
  EXPECT_EQ(a.t, b.s);
  EXPECT_EQ(a.s, b.t);
  EXPECT_EQ(a.point, b.point);
  EXPECT_TRUE(a.point.allFinite());
  EXPECT_GE(a.t, 0.0);
  EXPECT_LE(a.t, 1.0);
  EXPECT_GE(a.s, 0.0);
  EXPECT_LE(a.s, 1.0);
  return a;
}

void expect_point(const Point2& a, const Point2& b, double tol = 1e-15) { EXPECT_LT((a - b).norm(), tol) << a.transpose(); }

}  // namespace

TEST(SegmentIntersection, Crossing) {
  const SegmentHit h = both_orders({0, 0}, {2, 2}, {0, 2}, {2, 0});
  EXPECT_TRUE(h.hit);
  EXPECT_DOUBLE_EQ(h.t, 0.5);
  EXPECT_DOUBLE_EQ(h.s, 0.5);
  expect_point(h.point, Point2(1, 1));
  // Reversing a segment maps t to 1 - t.
  const SegmentHit r = both_orders({2, 2}, {0, 0}, {0, 2}, {2, 0});
  EXPECT_TRUE(r.hit);
  EXPECT_NEAR(r.t, 0.5, 1e-15);
  const SegmentHit g = both_orders({0, 0}, {4, 1}, {1, -1}, {2, 3});
  EXPECT_TRUE(g.hit);
  expect_point(g.point, Point2(0, 0) + g.t * Point2(4, 1), 1e-14);
  expect_point(g.point, Point2(1, -1) + g.s * Point2(1, 4), 1e-14);
}

TEST(SegmentIntersection, TouchingAtAnEndAndT) {
  const SegmentHit v = both_orders({0, 0}, {1, 0}, {1, 0}, {2, 3});  // V: shared end
  EXPECT_TRUE(v.hit);
  EXPECT_EQ(v.t, 1.0);
  EXPECT_EQ(v.s, 0.0);
  expect_point(v.point, Point2(1, 0));
  const SegmentHit t = both_orders({0, 0}, {2, 0}, {1, 0}, {1, 1});  // T: end on the interior
  EXPECT_TRUE(t.hit);
  EXPECT_DOUBLE_EQ(t.t, 0.5);
  EXPECT_EQ(t.s, 0.0);
  expect_point(t.point, Point2(1, 0));
  // A gap of 1e-3 on segments of length 2: a miss at tol 1e-12, a touch at
  // tol 1e-3 (eps = tol * 2 = 2e-3 >= gap), the touch point half-way.
  EXPECT_FALSE(both_orders({0, 0}, {2, 0}, {1, 1e-3}, {1, 1}).hit);
  const SegmentHit near = both_orders({0, 0}, {2, 0}, {1, 1e-3}, {1, 1}, 1e-3);
  EXPECT_TRUE(near.hit);
  expect_point(near.point, Point2(1, 0.5e-3));
}

TEST(SegmentIntersection, CollinearOverlapIsAHit) {
  const SegmentHit o = both_orders({0, 0}, {2, 0}, {1, 0}, {3, 0});
  EXPECT_TRUE(o.hit);
  expect_point(o.point, Point2(1.5, 0));  // middle of the shared stretch [1, 2]
  EXPECT_DOUBLE_EQ(o.t, 0.75);
  EXPECT_DOUBLE_EQ(o.s, 0.25);
  const SegmentHit in = both_orders({0, 0}, {2, 0}, {1, 0}, {0.5, 0});  // contained, reversed
  EXPECT_TRUE(in.hit);
  expect_point(in.point, Point2(0.75, 0));
  const SegmentHit end = both_orders({0, 0}, {1, 0}, {1, 0}, {2, 0});  // end to end
  EXPECT_TRUE(end.hit);
  expect_point(end.point, Point2(1, 0));
  EXPECT_FALSE(both_orders({0, 0}, {1, 0}, {1.5, 0}, {3, 0}).hit);  // collinear, apart
  // Same on a slanted line whose points are not representable exactly.
  const Point2 d(0.1, 0.3);
  EXPECT_TRUE(both_orders(Point2(0.7, 0.2), Point2(0.7, 0.2) + 3 * d, Point2(0.7, 0.2) + 2 * d, Point2(0.7, 0.2) + 7 * d).hit);
  EXPECT_FALSE(both_orders(Point2(0.7, 0.2), Point2(0.7, 0.2) + 3 * d, Point2(0.7, 0.2) + 4 * d, Point2(0.7, 0.2) + 7 * d).hit);
}

TEST(SegmentIntersection, ParallelDisjoint) {
  EXPECT_FALSE(both_orders({0, 0}, {2, 0}, {0, 1e-6}, {2, 1e-6}).hit);
  EXPECT_TRUE(both_orders({0, 0}, {2, 0}, {0, 1e-6}, {2, 1e-6}, 1e-6).hit);  // eps = 2e-6
  EXPECT_FALSE(both_orders({0, 0}, {2, 0}, {0, 1}, {2, 1}).hit);
}

TEST(SegmentIntersection, TiesResolveAlikeInBothOrders) {
  // Found by the hypothesis tests: with several equally close ends the first
  // one in argument order won, so for antiparallel segments the two orders
  // gave (t, s) = (0, 1) and point (0, 0.5) versus (1, 0) swapped and (1, 0.5).
  const SegmentHit anti = both_orders({0, 0}, {1, 0}, {1, 1}, {0, 1});
  EXPECT_FALSE(anti.hit);
  EXPECT_NEAR(anti.point.y(), 0.5, 1e-15);
  // a tiny segment against a point: equally close within rounding
  both_orders({0, 1.9e-141}, {0, 0}, {0, -1e-6}, {0, -1e-6});
  // a V junction whose two touching contacts agree in distance and point and
  // differ only in s = 3.6e-45 against 0 (t + s rounds to 1 for both)
  EXPECT_TRUE(both_orders({0, 0}, {1e-6, 0}, {1e-6, 5.96544755080558e-29}, {2e-6, 0}, 1e-9).hit);
  // a point against a point: both parameters 0, whichever end is asked
  const SegmentHit pts = both_orders({0, 0}, {0, 0}, {0, 1}, {0, 1});
  EXPECT_EQ(pts.t, 0.0);
  EXPECT_EQ(pts.s, 0.0);
  // ties inside the tolerance band: a collinear overlap of antiparallel segments
  const SegmentHit overlap = both_orders({0, 0}, {2, 0}, {3, 0}, {1, 0});
  EXPECT_TRUE(overlap.hit);
  expect_point(overlap.point, Point2(1.5, 0));
  // NaN input gives no hit and no out-of-bounds read (the sanitizer build checks)
  const double nan = std::nan("");
  EXPECT_FALSE(segment_intersection({nan, 0}, {1, 0}, {0, 1}, {1, nan}).hit);
}

TEST(SegmentIntersection, ExactlyScaleInvariantAcrossPowersOfTwo) {
  // Found by the hypothesis tests: at 1e-180 m the cross products underflow,
  // and reversing a segment turned a touch into a miss. The points are now
  // scaled by a power of two first, so any power-of-two scale gives the same
  // verdict and parameters, and the point scaled exactly.
  const Point2 a0(0, 2.74917508e-174), a1(2.74917508e-174, 0), b0(0, 0), b1(2.74917508e-174, 0);
  EXPECT_EQ(segment_intersection(a0, a1, b0, b1, 1e-9).hit, segment_intersection(a1, a0, b1, b0, 1e-9).hit);
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  for (int i = 0; i < 2000; ++i) {
    // every fourth case a touch: q0 placed on p
    const Point2 p0(U(rng), U(rng)), p1(U(rng), U(rng)), q1(U(rng), U(rng));
    const Point2 q0 = i % 4 ? Point2(U(rng), U(rng)) : Point2(p0 + 0.375 * (p1 - p0));
    const SegmentHit ref = segment_intersection(p0, p1, q0, q1, 1e-9);
    for (const int e : {-1000, -600, -300, -170, 170, 300, 600}) {
      const double f = std::ldexp(1.0, e);
      const SegmentHit h = both_orders(f * p0, f * p1, f * q0, f * q1, 1e-9);
      ASSERT_EQ(h.hit, ref.hit) << "case " << i << ", scale 2^" << e;
      EXPECT_EQ(h.t, ref.t);
      EXPECT_EQ(h.s, ref.s);
      EXPECT_EQ(h.point, f * ref.point);
    }
  }
}

TEST(SegmentIntersection, ZeroLengthSegmentsAreNaNFree) {
  EXPECT_TRUE(both_orders({1, 0}, {1, 0}, {0, 0}, {2, 0}).hit);
  const SegmentHit miss = both_orders({1, 1}, {1, 1}, {0, 0}, {2, 0});
  EXPECT_FALSE(miss.hit);
  EXPECT_TRUE(std::isfinite(miss.t) && std::isfinite(miss.s));
  EXPECT_TRUE(both_orders({1, 1}, {1, 1}, {1, 1}, {1, 1}).hit);
  EXPECT_FALSE(both_orders({1, 1}, {1, 1}, {1, 2}, {1, 2}).hit);
}

TEST(SegmentIntersection, ScaleInvariantTolerance) {
  // tol is relative to the segment length: the verdicts are the same for a
  // configuration in micrometres and in kilometres.
  for (const double L : {1e-6, 1.0, 1e3}) {
    EXPECT_TRUE(both_orders(Point2(0, 0), L * Point2(2, 0), L * Point2(1, 1e-7), L * Point2(1, 1), 1e-7).hit);
    EXPECT_FALSE(both_orders(Point2(0, 0), L * Point2(2, 0), L * Point2(1, 1e-6), L * Point2(1, 1), 1e-7).hit);
    EXPECT_TRUE(both_orders(Point2(0, 0), L * Point2(2, 2), L * Point2(0, 2), L * Point2(2, 0)).hit);
  }
}

TEST(SegmentIntersection, RandomSymmetryAndConsistency) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  int hits = 0;
  for (int i = 0; i < 5000; ++i) {
    const Point2 p0(U(rng), U(rng)), p1(U(rng), U(rng)), q0(U(rng), U(rng)), q1(U(rng), U(rng));
    const SegmentHit h = both_orders(p0, p1, q0, q1);
    // A reported crossing lies on both segments at its parameters.
    if (h.hit) {
      ++hits;
      expect_point(h.point, p0 + h.t * (p1 - p0), 1e-12);
      expect_point(h.point, q0 + h.s * (q1 - q0), 1e-12);
    }
    // Reversing a segment changes no verdict.
    EXPECT_EQ(h.hit, segment_intersection(p1, p0, q0, q1).hit);
    EXPECT_EQ(h.hit, segment_intersection(p0, p1, q1, q0).hit);
  }
  EXPECT_GT(hits, 500);
}

TEST(Distance, PointSegment) {
  SegmentDistance d = point_segment_distance({1, 1}, {0, 0}, {2, 0});
  EXPECT_DOUBLE_EQ(d.distance, 1.0);
  EXPECT_DOUBLE_EQ(d.t, 0.5);
  d = point_segment_distance({3, 4}, {0, 0}, {2, 0});
  EXPECT_DOUBLE_EQ(d.distance, std::sqrt(17.0));
  EXPECT_EQ(d.t, 1.0);
  d = point_segment_distance({-3, 4}, {0, 0}, {2, 0});
  EXPECT_DOUBLE_EQ(d.distance, 5.0);
  EXPECT_EQ(d.t, 0.0);
  d = point_segment_distance({3, 4}, {0, 0}, {0, 0});  // zero length
  EXPECT_DOUBLE_EQ(d.distance, 5.0);
  EXPECT_EQ(d.t, 0.0);
}

TEST(Distance, Polyline) {
  const Points2 p = poly({{0, 0}, {3, 0}, {3, 4}});
  const PolylineDistance c = closest_point_on_polyline({4, 3}, p);
  EXPECT_DOUBLE_EQ(c.distance, 1.0);
  EXPECT_EQ(c.segment, 1);
  EXPECT_DOUBLE_EQ(c.t, 0.75);
  expect_point(c.point, Point2(3, 3));
  EXPECT_DOUBLE_EQ(point_polyline_distance({1, -2}, p), 2.0);
  EXPECT_DOUBLE_EQ(point_polyline_distance({0, 0}, p), 0.0);
  EXPECT_DOUBLE_EQ(point_polyline_distance({4, 4}, poly({{1, 0}})), 5.0);  // a single point
  EXPECT_THROW(point_polyline_distance({0, 0}, Points2(0, 2)), std::invalid_argument);
}

TEST(Polyline, SelfIntersection) {
  EXPECT_FALSE(polyline_self_intersects(poly({{0, 0}, {1, 0}})));
  EXPECT_FALSE(polyline_self_intersects(poly({{0, 0}, {1, 0}, {2, 1}, {3, 0}})));      // zigzag
  EXPECT_FALSE(polyline_self_intersects(poly({{0, 0}, {1, 0}, {0, 0.1}})));            // sharp turn
  EXPECT_TRUE(polyline_self_intersects(poly({{0, 0}, {2, 0}, {2, 1}, {1, -1}})));      // crossing
  EXPECT_TRUE(polyline_self_intersects(poly({{0, 0}, {2, 0}, {2, 1}, {1, 0}})));       // T-touch
  EXPECT_TRUE(polyline_self_intersects(poly({{0, 0}, {2, 0}, {1, 0}})));               // folds back
  EXPECT_TRUE(polyline_self_intersects(poly({{0, 0}, {1, 0}, {1, 0}, {2, 1}})));       // zero-length segment
  EXPECT_TRUE(polyline_self_intersects(poly({{0, 0}, {1, 0}, {1, 1}, {0, 0}})));       // closed loop
  EXPECT_FALSE(polyline_self_intersects(poly({{0, 0}, {2, 0}, {2, 1}, {1, 1e-3}})));   // near miss
  EXPECT_TRUE(polyline_self_intersects(poly({{0, 0}, {2, 0}, {2, 1}, {1, 1e-3}}), 1e-3));
}

TEST(Polyline, TwoPolylines) {
  const Points2 a = poly({{0, 0}, {1, 0}, {1, 1}});
  EXPECT_TRUE(polylines_intersect(a, poly({{2, 0}, {0.5, 0.5}})));
  EXPECT_TRUE(polylines_intersect(poly({{2, 0}, {0.5, 0.5}}), a));
  EXPECT_FALSE(polylines_intersect(a, poly({{2, 0}, {3, 1}, {2, 2}})));
  EXPECT_TRUE(polylines_intersect(a, poly({{1, 0.5}, {3, 0.5}})));  // T-touch
  EXPECT_TRUE(polylines_intersect(a, poly({{0.5, 0}})));            // a point on a
}
