// Type conversion only: numpy arrays <-> the Zienkiewicz-Zhu estimator kernels.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <string>
#include <utility>

#include "wingcrack/error_estimate.hpp"

namespace py = pybind11;
using namespace wingcrack;

namespace {

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

// (m, 3, 3) numpy stress viewed in place as the kernel's (m, 9) rows.
Eigen::Map<const CellStress> as_cell_stress(const Array& a) {
  if (a.ndim() != 3 || a.shape(1) != 3 || a.shape(2) != 3) {
    std::string s = "(";
    for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
    throw py::value_error("cell_stress must have shape (m, 3, 3), got " + s + ")");
  }
  return Eigen::Map<const CellStress>(a.data(), a.shape(0), 9);
}

}  // namespace

void bind_estimate(py::module_& m) {
  m.def(
      "zz_error",
      [](const Coords2& x, const P2Cells& cells, const Array& cell_stress) {
        const auto stress = as_cell_stress(cell_stress);
        ZZError r;
        {
          py::gil_scoped_release release;
          r = zz_error(x, cells, stress);
        }
        return std::make_pair(std::move(r.recovered), std::move(r.eta));
      },
      py::arg("x"), py::arg("cells"), py::arg("cell_stress"),
      "Zienkiewicz-Zhu estimator (paper eqs. 35-36) on a P2 mesh, gmsh order [v0,v1,v2,m01,m12,m20].\n\n"
      "cell_stress (m,3,3): [c, k] = (sxx, syy, sxy) of cell c's FE stress at its vertex k.\n"
      "Returns (recovered (n,3), eta (m,)): recovered[i] = sum_c A_c sigma_c(x_i) / sum_c A_c over\n"
      "the cells with vertex i (NaN rows at mid-edge nodes), A_c the straight vertex-triangle area;\n"
      "eta_c = sqrt(int_c |sigma_h - sigma*|^2 dA), sigma* linear between the recovered vertex\n"
      "values, |s|^2 = sxx^2 + syy^2 + 2 sxy^2 (Pa m for stress in Pa, x in m).");
  m.def("zz_sizes", &zz_sizes, py::arg("x"), py::arg("cells"), py::arg("eta"), py::arg("h_current"),
        py::arg("total_error_target"), py::arg("p") = 1.0, py::arg("h_min"), py::arg("h_max"),
        py::arg("grading") = 0.5, py::call_guard<py::gil_scoped_release>(),
        "(n,) target element size at every vertex (NaN at other nodes) from equidistribution:\n"
        "h_c' = h_c (e*/eta_c)^(1/p), e* = total_error_target/sqrt(m), clamped to [h_min, h_max]\n"
        "(h_max where eta_c = 0); a vertex takes the min over its cells; then graded exactly so that\n"
        "size_i <= size_j + grading |x_i - x_j| on every vertex edge. p is the convergence order of\n"
        "eta_c in the element size. h_min and h_max have no default: pass them by keyword to keep p's.");
}
