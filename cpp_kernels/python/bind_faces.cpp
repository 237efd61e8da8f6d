// Type conversion only: numpy arrays <-> the face-splitting and quarter-point kernels.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>

#include "wingcrack/face_split.hpp"
#include "wingcrack/quarter_point.hpp"

namespace py = pybind11;
using namespace wingcrack;

void bind_faces(py::module_& m) {
  m.def(
      "split_faces",
      [](const Coords2& x, const P2Cells& cells, const P2Edges& crack_edges, const IndexVector& crack_fracture,
         const P2Edges& boundary_edges) {
        SplitMesh s;
        {
          py::gil_scoped_release release;
          s = split_faces(x, cells, crack_edges, crack_fracture, boundary_edges);
        }
        py::dict out;
        out["x"] = s.x;
        out["cells"] = s.cells;
        out["boundary_edges"] = s.boundary_edges;
        out["parent"] = s.parent;
        out["pairs"] = s.pairs;
        out["pair_normal"] = s.pair_normal;
        out["pair_fracture"] = s.pair_fracture;
        out["crack_edges"] = s.crack_edges;
        out["crack_edges_minus"] = s.crack_edges_minus;
        return out;
      },
      py::arg("x"), py::arg("cells"), py::arg("crack_edges"), py::arg("crack_fracture"), py::arg("boundary_edges"),
      "Duplicate crack-face nodes of a P2 mesh (gmsh order [v0,v1,v2,m01,m12,m20]).\n\n"
      "crack_edges (k,3) [a,b,mid] oriented along the fracture direction d. Returns a dict:\n"
      "x, cells, boundary_edges (remapped), parent (original node of each node), pairs (p,2)\n"
      "[plus, minus] (+ = left of d), pair_normal (p,2) unit left normal of d, pair_fracture (p,),\n"
      "crack_edges (+ face copy, same orientation), crack_edges_minus (- face copy).");
  m.def("quarter_points", &quarter_points, py::arg("x"), py::arg("cells"), py::arg("tip_nodes"),
        py::call_guard<py::gil_scoped_release>(),
        "Copy of x with the mid node of every edge touching one tip node at 1/4 of the edge from the tip.");
  m.def("min_jacobian", &min_jacobian, py::arg("x"), py::arg("cells"), py::call_guard<py::gil_scoped_release>(),
        "(m,) minimum of det J of the P2 map over the 6 interior Dunavant points of each cell.");
}
