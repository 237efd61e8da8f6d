// pybind11 entry point: each concept binds itself in its own file
// (bind_<concept>.cpp) so the binding layer only converts types.
#include <pybind11/pybind11.h>

namespace py = pybind11;

void bind_geometry(py::module_& m);
void bind_sif(py::module_& m);
void bind_faces(py::module_& m);
void bind_estimate(py::module_& m);
void bind_rasterise(py::module_& m);

PYBIND11_MODULE(wingcrack_kernels, m) {
  m.doc() = "wingcrack C++ kernels: quarter-point geometry, SIF correlation, "
            "crack-path geometry, face splitting and node pairs, error estimate, P1 fields on grids";
  bind_geometry(m);
  bind_sif(m);
  bind_faces(m);
  bind_estimate(m);
  bind_rasterise(m);
}
