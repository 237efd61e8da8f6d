#include "wingcrack/geometry.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <tuple>
#include <utility>

namespace wingcrack {

namespace {

double cross(const Point2& a, const Point2& b) { return a.x() * b.y() - a.y() * b.x(); }

// |v| without the underflow of v.norm() = sqrt(x^2 + y^2): below ~1e-154 the
// squares lose digits or vanish, which made tip frames of tiny (but valid)
// segments non-unit.
double length(const Point2& v) { return std::hypot(v.x(), v.y()); }

// The point at parameter t of [a, b], exactly an end at t = 0 and t = 1:
// a + 1 (b - a) may differ from b in the last bit, and then two equally close
// end-to-end contacts would give different points depending on the order.
Point2 at(const Point2& a, const Point2& b, double t) { return t == 1.0 ? b : Point2(a + t * (b - a)); }

// An end point of one segment against the other segment: the candidate
// contact is the midpoint between the end and its foot, so that it does not
// depend on which of the two segments is called p.
struct EndContact {
  double distance;
  Point2 point;
  double t;  // on p
  double s;  // on q
};

EndContact end_on_q(const Point2& end, double t_end, const Point2& q0, const Point2& q1) {
  const SegmentDistance d = point_segment_distance(end, q0, q1);
  const Point2 foot = at(q0, q1, d.t);
  return {d.distance, 0.5 * (end + foot), t_end, d.t};
}

EndContact end_on_p(const Point2& end, double s_end, const Point2& p0, const Point2& p1) {
  const SegmentDistance d = point_segment_distance(end, p0, p1);
  const Point2 foot = at(p0, p1, d.t);
  return {d.distance, 0.5 * (end + foot), d.t, s_end};
}

// Segment i of a polyline; a single point is a zero-length segment.
std::array<Point2, 2> segment(const PointsRef& pts, Eigen::Index i) {
  const Eigen::Index j = std::min<Eigen::Index>(i + 1, pts.rows() - 1);
  return {pts.row(i).transpose(), pts.row(j).transpose()};
}

Eigen::Index segment_count(const PointsRef& pts) { return std::max<Eigen::Index>(pts.rows() - 1, 1); }

// Cheap rejection before the exact test: boxes apart by more than eps.
bool boxes_apart(const std::array<Point2, 2>& a, const std::array<Point2, 2>& b, double eps) {
  const Point2 alo = a[0].cwiseMin(a[1]), ahi = a[0].cwiseMax(a[1]);
  const Point2 blo = b[0].cwiseMin(b[1]), bhi = b[0].cwiseMax(b[1]);
  return (alo.array() > bhi.array() + eps).any() || (blo.array() > ahi.array() + eps).any();
}

double relative_eps(const std::array<Point2, 2>& a, const std::array<Point2, 2>& b, double tol) {
  return tol * std::max(length(a[1] - a[0]), length(b[1] - b[0]));
}

}  // namespace

SegmentDistance point_segment_distance(const Point2& p, const Point2& a, const Point2& b) {
  const Point2 d = b - a;
  const double dd = d.squaredNorm();
  // A zero-length segment is its point; dividing by dd would give NaN.
  const double t = dd > 0.0 ? std::clamp((p - a).dot(d) / dd, 0.0, 1.0) : 0.0;
  return {length(p - at(a, b, t)), t};
}

namespace {

// segment_intersection on coordinates of order 1 (see below).
SegmentHit intersect_scaled(const Point2& p0, const Point2& p1, const Point2& q0, const Point2& q1, double tol) {
  const Point2 dp = p1 - p0, dq = q1 - q0;
  const double lp = length(dp), lq = length(dq);
  const double eps = tol * std::max(lp, lq);

  // Touches first: an end within eps of the other segment. This also decides
  // collinear overlaps and near-parallel cases, where the crossing formula
  // below divides by a vanishing cross product. A zero-length segment is a
  // point, at parameter 0 whichever of its ends is asked.
  std::array<EndContact, 4> ends = {end_on_q(p0, 0.0, q0, q1), end_on_q(p1, p0 == p1 ? 0.0 : 1.0, q0, q1),
                                    end_on_p(q0, 0.0, p0, p1), end_on_p(q1, q0 == q1 ? 0.0 : 1.0, p0, p1)};
  // Each contact is computed alike whichever segment comes first, so the
  // four are the same set in both argument orders (with t and s swapped).
  // Ordering them by values that do not depend on the order (distance, then
  // point, then the smaller and the larger of t and s) makes every tie, such
  // as the equally close ends of two parallel segments, resolve the same way
  // in both orders.
  // A sorting network rather than std::sort: with NaN input the comparison
  // is no strict weak order, and std::sort may then read out of bounds.
  const auto before = [](const EndContact& a, const EndContact& b) {
    return std::make_tuple(a.distance, a.point.x(), a.point.y(), std::min(a.t, a.s), std::max(a.t, a.s)) <
           std::make_tuple(b.distance, b.point.x(), b.point.y(), std::min(b.t, b.s), std::max(b.t, b.s));
  };
  for (const auto& [i, j] : {std::pair{0, 1}, {2, 3}, {0, 2}, {1, 3}, {1, 2}})
    if (before(ends[j], ends[i])) std::swap(ends[i], ends[j]);
  const auto closest = ends.begin();
  if (closest->distance <= eps) {
    // The touching ends span the overlap (one point for a touch, the two
    // ends of the shared stretch for a collinear overlap): return its middle.
    const EndContact* a = &*closest;
    const EndContact* b = a;
    double widest = 0.0;
    for (std::size_t i = 0; i < ends.size(); ++i)
      for (std::size_t j = i + 1; j < ends.size(); ++j) {
        if (ends[i].distance > eps || ends[j].distance > eps) continue;
        const double w = length(ends[i].point - ends[j].point);
        if (w > widest) {
          widest = w;
          a = &ends[i];
          b = &ends[j];
        }
      }
    // The parameters are affine along each segment: averaging them is exact.
    return {true, 0.5 * (a->t + b->t), 0.5 * (a->s + b->s), 0.5 * (a->point + b->point)};
  }

  // Every end is farther than eps from the other segment: only a proper
  // crossing is left, with each segment's ends strictly on both sides of the
  // other's line (an end within eps of the line lies beyond the segment and
  // cannot be a crossing, so it counts as "on the line", not as a side).
  if (lp > 0.0 && lq > 0.0) {
    const Point2 w = q0 - p0;
    const double a0 = cross(dp, w) / lp, a1 = cross(dp, q1 - p0) / lp;
    const double b0 = cross(dq, -w) / lq, b1 = cross(dq, p1 - q0) / lq;
    const auto straddles = [eps](double u, double v) { return (u > eps && v < -eps) || (u < -eps && v > eps); };
    if (straddles(a0, a1) && straddles(b0, b1)) {
      const double c = cross(dp, dq);
      const double t = std::clamp(cross(w, dq) / c, 0.0, 1.0);
      const double s = std::clamp(cross(w, dp) / c, 0.0, 1.0);
      return {true, t, s, 0.5 * ((p0 + t * dp) + (q0 + s * dq))};
    }
  }
  return {false, closest->t, closest->s, closest->point};
}

}  // namespace

SegmentHit segment_intersection(const Point2& p0, const Point2& p1, const Point2& q0, const Point2& q1, double tol) {
  // Cross products and squared lengths of segments far below 1 (1e-160 m)
  // underflow, and far above overflow. Scaling the four points by a power of
  // two, chosen from the largest coordinate so that it does not depend on the
  // argument order, is exact and brings them to order 1: the verdict, t and s
  // are then the same for a configuration at any scale.
  const double big = std::max({p0.cwiseAbs().maxCoeff(), p1.cwiseAbs().maxCoeff(), q0.cwiseAbs().maxCoeff(),
                               q1.cwiseAbs().maxCoeff()});
  if (!(big > 0.0) || !std::isfinite(big)) return intersect_scaled(p0, p1, q0, q1, tol);  // all zero, or NaN/inf
  const int e = std::ilogb(big);
  const auto scaled = [e](const Point2& v) { return Point2(std::scalbn(v.x(), -e), std::scalbn(v.y(), -e)); };
  SegmentHit h = intersect_scaled(scaled(p0), scaled(p1), scaled(q0), scaled(q1), tol);
  h.point = Point2(std::scalbn(h.point.x(), e), std::scalbn(h.point.y(), e));
  return h;
}

PolylineDistance closest_point_on_polyline(const Point2& p, const PointsRef& points) {
  if (points.rows() == 0) throw std::invalid_argument("closest_point_on_polyline: the polyline has no points");
  PolylineDistance best;
  best.distance = INFINITY;
  for (Eigen::Index i = 0; i < segment_count(points); ++i) {
    const auto seg = segment(points, i);
    const SegmentDistance d = point_segment_distance(p, seg[0], seg[1]);
    if (d.distance < best.distance) best = {d.distance, at(seg[0], seg[1], d.t), i, d.t};
  }
  return best;
}

double point_polyline_distance(const Point2& p, const PointsRef& points) {
  return closest_point_on_polyline(p, points).distance;
}

bool polyline_self_intersects(const PointsRef& points, double tol) {
  const Eigen::Index m = points.rows() - 1;  // segments
  for (Eigen::Index i = 0; i < m; ++i) {
    const auto si = segment(points, i);
    for (Eigen::Index j = i + 1; j < m; ++j) {
      const auto sj = segment(points, j);
      const double eps = relative_eps(si, sj, tol);
      if (boxes_apart(si, sj, eps)) continue;
      if (j == i + 1) {
        // Neighbours always share point i+1; they only fold back when the
        // far end of one lies on the other.
        if (point_segment_distance(si[0], sj[0], sj[1]).distance <= eps ||
            point_segment_distance(sj[1], si[0], si[1]).distance <= eps)
          return true;
      } else if (segment_intersection(si[0], si[1], sj[0], sj[1], tol).hit) {
        return true;
      }
    }
  }
  return false;
}

bool polylines_intersect(const PointsRef& a, const PointsRef& b, double tol) {
  if (a.rows() == 0 || b.rows() == 0) throw std::invalid_argument("polylines_intersect: a polyline has no points");
  for (Eigen::Index i = 0; i < segment_count(a); ++i) {
    const auto sa = segment(a, i);
    for (Eigen::Index j = 0; j < segment_count(b); ++j) {
      const auto sb = segment(b, j);
      if (boxes_apart(sa, sb, relative_eps(sa, sb, tol))) continue;
      if (segment_intersection(sa[0], sa[1], sb[0], sb[1], tol).hit) return true;
    }
  }
  return false;
}

}  // namespace wingcrack
