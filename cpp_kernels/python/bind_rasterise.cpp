// Type conversion only: numpy arrays <-> the P1 field rasteriser.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <string>

#include "wingcrack/rasterise.hpp"

namespace py = pybind11;
using namespace wingcrack;

namespace {

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

std::string shape_of(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

void need_shape(const py::array& a, const char* name, std::initializer_list<py::ssize_t> shape, const char* want) {
  bool ok = a.ndim() == static_cast<py::ssize_t>(shape.size());
  py::ssize_t d = 0;
  for (const py::ssize_t n : shape) {
    ok = ok && (n < 0 || a.shape(d) == n);  // -1: any length
    ++d;
  }
  if (!ok) throw py::value_error(std::string(name) + " must have shape " + want + ", got " + shape_of(a));
}

}  // namespace

void bind_rasterise(py::module_& m) {
  m.def(
      "rasterise_p1",
      [](const Array& triangles, const Array& values, const Array& origin, const Array& spacing,
         const py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>& counts, double fill) {
        need_shape(triangles, "triangles", {-1, 3, 2}, "(m, 3, 2)");
        need_shape(values, "values", {triangles.shape(0), 3}, "(m, 3) with m = len(triangles)");
        need_shape(origin, "origin", {2}, "(2,)");
        need_shape(spacing, "spacing", {2}, "(2,)");
        need_shape(counts, "counts", {2}, "(2,)");
        const Eigen::Map<const Triangles2> tri(triangles.data(), triangles.shape(0), 6);
        const Eigen::Map<const VertexValues> val(values.data(), values.shape(0), 3);
        const Grid2 grid{{origin.data()[0], origin.data()[1]},
                         {spacing.data()[0], spacing.data()[1]},
                         {static_cast<Eigen::Index>(counts.data()[0]), static_cast<Eigen::Index>(counts.data()[1])}};
        GridValues g;
        {
          py::gil_scoped_release release;
          g = rasterise_p1(tri, val, grid, fill);
        }
        return g;
      },
      py::arg("triangles"), py::arg("values"), py::arg("origin"), py::arg("spacing"), py::arg("counts"),
      py::arg("fill"),
      "A P1 field on triangles sampled at the nodes of a regular grid -> (n0, n1) array.\n\n"
      "triangles (m,3,2), values (m,3): the field, linear on each triangle. Node [i, j] is\n"
      "origin + (i spacing[0], j spacing[1]), counts = (n0, n1). A node in a (closed) triangle gets\n"
      "its linear interpolant, the smallest where several hold it; a node in none the value of the\n"
      "nearest such node in 4-neighbour grid steps (the smallest among equally near ones), or fill\n"
      "when no node is in any triangle. O(m + n0 n1).");
}
