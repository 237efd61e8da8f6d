// Type conversion only: numpy arrays <-> the polyline geometry kernels.
// Shapes are checked here so that a wrong array is a ValueError naming the
// argument, not pybind11's generic "incompatible function arguments".
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <string>
#include <vector>

#include "wingcrack/geometry.hpp"

namespace py = pybind11;
using namespace wingcrack;

namespace {

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

std::string shape_of(const Array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

Point2 to_point(const Array& a, const char* name) {
  if (a.ndim() != 1 || a.shape(0) != 2)
    throw py::value_error(std::string(name) + " must be a point of shape (2,), got shape " + shape_of(a));
  return {a.data()[0], a.data()[1]};
}

// A view, no copy: the array outlives the call.
Eigen::Map<const Points2> to_points(const Array& a, const char* name, Eigen::Index min_points) {
  if (a.ndim() != 2 || a.shape(1) != 2)
    throw py::value_error(std::string(name) + " must be points of shape (n, 2), got shape " + shape_of(a));
  if (a.shape(0) < min_points)
    throw py::value_error(std::string(name) + " needs at least " + std::to_string(min_points) + " point(s), got " +
                          std::to_string(a.shape(0)));
  return Eigen::Map<const Points2>(a.data(), a.shape(0), 2);
}

// k rows of (k, 2) points, each checked like to_points
void check_rows(const Array& a, const char* name, py::ssize_t k) {
  if (a.ndim() != 2 || a.shape(1) != 2 || a.shape(0) != k)
    throw py::value_error(std::string(name) + " must be points of shape (" + std::to_string(k) + ", 2), got shape " +
                          shape_of(a));
}

Point2 row(const Array& a, py::ssize_t i) { return {a.data()[2 * i], a.data()[2 * i + 1]}; }

}  // namespace

void bind_geometry(py::module_& m) {
  m.def(
      "segment_intersection",
      [](const Array& p0, const Array& p1, const Array& q0, const Array& q1, double tol) {
        const SegmentHit h =
            segment_intersection(to_point(p0, "p0"), to_point(p1, "p1"), to_point(q0, "q0"), to_point(q1, "q1"), tol);
        return py::make_tuple(h.hit, h.t, h.s, h.point);
      },
      py::arg("p0"), py::arg("p1"), py::arg("q0"), py::arg("q1"), py::arg("tol") = 1e-12,
      "Intersection of the closed segments [p0, p1] and [q0, q1] -> (hit, t, s, point (2,)).\n\n"
      "hit when their distance is <= tol * (length of the longer segment): crossings, touches (an end\n"
      "on the other segment) and collinear overlaps (point = middle of the overlap). t, s in [0, 1]\n"
      "locate point on each segment. Symmetric: swapping the segments swaps t and s. When hit is\n"
      "False, t, s, point are those of the closest approach. Zero-length segments act as points.");

  m.def(
      "segment_intersections",
      [](const Array& p0, const Array& p1, const Array& q0, const Array& q1, double tol) {
        const py::ssize_t k = p0.ndim() == 2 ? p0.shape(0) : 0;
        check_rows(p0, "p0", k);
        check_rows(p1, "p1", k);
        check_rows(q0, "q0", k);
        check_rows(q1, "q1", k);
        py::array_t<bool> hit(k);
        Array t(k), s(k), point(std::vector<py::ssize_t>{k, 2});
        auto h = hit.mutable_unchecked<1>();
        auto tt = t.mutable_unchecked<1>();
        auto ss = s.mutable_unchecked<1>();
        auto pt = point.mutable_unchecked<2>();
        for (py::ssize_t i = 0; i < k; ++i) {
          const SegmentHit r = segment_intersection(row(p0, i), row(p1, i), row(q0, i), row(q1, i), tol);
          h(i) = r.hit;
          tt(i) = r.t;
          ss(i) = r.s;
          pt(i, 0) = r.point[0];
          pt(i, 1) = r.point[1];
        }
        return py::make_tuple(hit, t, s, point);
      },
      py::arg("p0"), py::arg("p1"), py::arg("q0"), py::arg("q1"), py::arg("tol") = 1e-12,
      "segment_intersection of k pairs of segments at once: the rows of p0, p1, q0, q1 (k, 2) ->\n"
      "(hit (k,) bool, t (k,), s (k,), point (k, 2)), each row what segment_intersection gives.");

  m.def(
      "point_segment_distance",
      [](const Array& p, const Array& a, const Array& b) {
        const SegmentDistance d = point_segment_distance(to_point(p, "p"), to_point(a, "a"), to_point(b, "b"));
        return py::make_tuple(d.distance, d.t);
      },
      py::arg("p"), py::arg("a"), py::arg("b"),
      "(distance, t) from p to the segment [a, b]; t in [0, 1] locates the closest point (0 if a == b).");

  m.def(
      "point_polyline_distance",
      [](const Array& p, const Array& points) {
        return point_polyline_distance(to_point(p, "p"), to_points(points, "points", 1));
      },
      py::arg("p"), py::arg("points"), "Distance (float) from p (2,) to the polyline points (n, 2), n >= 1.");

  m.def(
      "point_polyline_distances",
      [](const Array& p, const Array& points) {
        const py::ssize_t k = p.ndim() == 2 ? p.shape(0) : 0;
        check_rows(p, "p", k);
        const auto line = to_points(points, "points", 1);
        Array out(k);
        auto d = out.mutable_unchecked<1>();
        for (py::ssize_t i = 0; i < k; ++i) d(i) = point_polyline_distance(row(p, i), line);
        return out;
      },
      py::arg("p"), py::arg("points"),
      "point_polyline_distance of k points p (k, 2) at once: their distances (k,) to the polyline\n"
      "points (n, 2), n >= 1.");

  m.def(
      "closest_point_on_polyline",
      [](const Array& p, const Array& points) {
        const PolylineDistance d = closest_point_on_polyline(to_point(p, "p"), to_points(points, "points", 1));
        return py::make_tuple(d.distance, d.point, static_cast<py::ssize_t>(d.segment), d.t);
      },
      py::arg("p"), py::arg("points"),
      "(distance, point (2,), segment, t): the closest point of the polyline (n, 2) to p, on segment\n"
      "[segment, segment + 1] at parameter t.");

  m.def(
      "polyline_self_intersects",
      [](const Array& points, double tol) { return polyline_self_intersects(to_points(points, "points", 1), tol); },
      py::arg("points"), py::arg("tol") = 1e-12,
      "True when non-adjacent segments of the open polyline (n, 2) touch or cross, or adjacent ones\n"
      "overlap (fold back). tol is relative to the segment lengths, as in segment_intersection. A\n"
      "zero-length segment counts as self-intersection; a polygon's closing segment is not implied.");

  m.def(
      "polylines_intersect",
      [](const Array& a, const Array& b, double tol) {
        return polylines_intersect(to_points(a, "a", 1), to_points(b, "b", 1), tol);
      },
      py::arg("a"), py::arg("b"), py::arg("tol") = 1e-12,
      "True when any segment of polyline a (n, 2) touches or crosses any segment of b (m, 2);\n"
      "tol relative to the segment lengths, as in segment_intersection.");
}
