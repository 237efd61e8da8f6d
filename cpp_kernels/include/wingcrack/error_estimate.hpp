#pragma once
// The Zienkiewicz-Zhu (1987) recovery error estimator and the element size
// field it implies (paper section 3.3.1, eqs. 35-36).
//
// Cells are P2 triangles in gmsh order [v0, v1, v2, m01, m12, m20]; only the
// vertices (columns 0-2) matter here, mid-edge nodes are ignored, and every
// area is that of the straight vertex triangle. A mesh split along its cracks
// has separate nodes on the two faces, so nothing is ever averaged across a
// crack.
//
// Norm: the error is measured in the Frobenius norm of the stress tensor,
// |s|^2 = sxx^2 + syy^2 + 2 sxy^2 (sxy counted twice, szz left out), so
// eta has units Pa m and needs no material constants. It is equivalent to the
// energy norm up to the bounds of the compliance, which is all an equidistribution
// rule needs.
#include <Eigen/Core>

#include "wingcrack/face_split.hpp"

namespace wingcrack {

// FE stress of each cell at its 3 vertices, (m, 3 x 3) row-major:
// row c = [sxx, syy, sxy at v0 | at v1 | at v2]; numpy's (m, 3, 3) as is.
using CellStress = Eigen::Matrix<double, Eigen::Dynamic, 9, Eigen::RowMajor>;
// (n, 3) [sxx, syy, sxy] per node.
using NodalStress = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

struct ZZError {
  NodalStress recovered;  // sigma* at every vertex; NaN rows at mid-edge (and unused) nodes
  Eigen::VectorXd eta;    // (m,) eta_c = ||sigma_h - sigma*||_c, Pa m
};

// Recovered nodal stress sigma*_i = sum_c A_c sigma_c(x_i) / sum_c A_c over
// the cells c having node i as a vertex, where sigma_c(x_i) is cell c's own
// (linear) stress at that vertex. This is eq. (35) with the cell's value at
// the node in place of its mean over the cell: both agree for piecewise
// constant stress, but only the vertex value reproduces a linear field exactly
// (eta = 0), which is what a P2 displacement gives on straight cells.
// sigma* is then linear on each cell between its vertex values and
// eta_c^2 = int_c |sigma_h - sigma*|^2 dA, integrated exactly by the
// edge-midpoint rule (the integrand is quadratic).
// Throws std::invalid_argument on a node index out of range, a row count of
// cell_stress other than cells.rows(), or a cell of zero area.
ZZError zz_error(const Coords2& x, const P2Cells& cells, const Eigen::Ref<const CellStress>& cell_stress);

// Target size at every vertex from the classical equidistribution rule
// (Zienkiewicz & Zhu 1987): every cell should carry the same error
// e* = total_error_target / sqrt(m) (so that the cells sum to the target in
// the l2 sense), and eta_c scales like h_c^p, hence
//   h_c' = h_c (e* / eta_c)^(1/p),  clamped to [h_min, h_max]
// (h_max where eta_c = 0). A vertex takes the minimum of h_c' over its cells:
// the cell asking for the finest mesh wins. Finally the field is graded:
//   size_i <= size_j + grading |x_i - x_j| on every vertex edge i-j,
// i.e. a size ratio at most 1 + grading across an edge about as long as the
// smaller size. This is computed exactly (the largest field below the
// ungraded one that satisfies the bound: Dijkstra from all vertices at once,
// the fixed point of Gauss-Seidel sweeps of size_i = min(size_i, size_j +
// grading L_ij)); grading only lowers sizes, so they stay in [h_min, h_max].
// Returns (n,) sizes, NaN at nodes that are no cell's vertex.
// Throws std::invalid_argument on inconsistent sizes or on a non-positive
// target, p, grading, h_current or h_min, h_min > h_max, or non-finite h_max
// or eta < 0.
Eigen::VectorXd zz_sizes(const Coords2& x, const P2Cells& cells, const Eigen::VectorXd& eta,
                         const Eigen::VectorXd& h_current, double total_error_target, double p, double h_min,
                         double h_max, double grading = 0.5);

}  // namespace wingcrack
