#pragma once
// Crack-path geometry on polylines: segment intersection and distances. Plain value types in and out, no state.
//
// Conventions (docs/architecture.md): a polyline `points` (n, 2) runs from
// point 0 to point n-1, its direction d.
//
// Tolerances are relative: `tol` is a fraction of the longer of the two
// segments compared, so the same tol works for a millimetre crack and a
// kilometre fault. Zero-length segments are valid input (they behave as a
// point) and never produce NaN.
#include <Eigen/Core>

namespace wingcrack {

using Point2 = Eigen::Vector2d;
// Row-major (n, 2): the layout of a C-contiguous numpy array of points.
using Points2 = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;
using PointsRef = Eigen::Ref<const Points2>;

struct SegmentHit {
  bool hit = false;
  double t = 0.0;  // parameter of `point` on [p0, p1], in [0, 1]
  double s = 0.0;  // parameter of `point` on [q0, q1], in [0, 1]
  Point2 point = Point2::Zero();
};

// Proper or touching intersection of the closed segments [p0, p1] and
// [q0, q1]: they hit when their distance is <= tol * max(|p1-p0|, |q1-q0|).
// A crossing returns the crossing point; a touch (an end on the other
// segment, T or V junction) the touching point; a collinear overlap the
// midpoint of the overlap. hit and point do not depend on the argument order
// (swapping the segments swaps t and s), ties between equally close ends
// included. When hit is false, t and s locate the closest pair of points and
// `point` is the middle between them. Scaling all four points by a power of
// two changes neither hit nor t nor s (no underflow at 1e-200 m either).
SegmentHit segment_intersection(const Point2& p0, const Point2& p1, const Point2& q0, const Point2& q1,
                                double tol = 1e-12);

struct SegmentDistance {
  double distance = 0.0;
  double t = 0.0;  // parameter of the closest point on [a, b], in [0, 1]; 0 if a == b
};

SegmentDistance point_segment_distance(const Point2& p, const Point2& a, const Point2& b);

struct PolylineDistance {
  double distance = 0.0;
  Point2 point = Point2::Zero();  // closest point of the polyline
  Eigen::Index segment = 0;       // segment [segment, segment+1] holding it (0 for n == 1)
  double t = 0.0;                 // parameter on that segment
};

// Closest point of a polyline with n >= 1 points (n == 1: the point itself).
// Throws std::invalid_argument for n == 0.
PolylineDistance closest_point_on_polyline(const Point2& p, const PointsRef& points);
double point_polyline_distance(const Point2& p, const PointsRef& points);

// True when two non-adjacent segments of the open polyline hit (cross or
// touch), or two adjacent ones overlap (the path folds back on itself). A
// zero-length segment therefore counts as a self-intersection. Meant for open
// paths: a polygon's closing segment is not implied, and repeating its first
// point at the end makes the first and last segments touch (true).
bool polyline_self_intersects(const PointsRef& points, double tol = 1e-12);

// True when any segment of a hits any segment of b (both n >= 1; a single
// point is a zero-length segment).
bool polylines_intersect(const PointsRef& a, const PointsRef& b, double tol = 1e-12);

}  // namespace wingcrack
