#pragma once
// A field that is linear on each of a set of triangles (P1, possibly
// discontinuous between them), sampled at the nodes of a regular 2D grid: the
// error-estimate size field of one mesh handed to the mesher of the next as a
// gmsh "Structured" field, which interpolates the grid bilinearly.
#include <array>

#include <Eigen/Core>

namespace wingcrack {

// (m, 6) row-major: row c = [x0, y0, x1, y1, x2, y2], numpy's (m, 3, 2) as is.
using Triangles2 = Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor>;
// (m, 3): the field's value at each triangle's 3 vertices.
using VertexValues = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
// (n0, n1) row-major: [i, j] is the node origin + (i spacing[0], j spacing[1]),
// so the flat index is i n1 + j (x-major, as gmsh's Structured field reads it).
using GridValues = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

struct Grid2 {
  std::array<double, 2> origin;
  std::array<double, 2> spacing;
  std::array<Eigen::Index, 2> counts;
};

// The field at every grid node. A node covered by a triangle (closed: its
// barycentric coordinates all >= -1e-12, so that a node on an edge shared by
// two triangles is in both despite round-off) gets that triangle's linear
// interpolant; a node covered by several gets the smallest of their values.
// A node covered by none gets the value of the nearest covered node in grid
// steps (4-neighbour dilation; among several equally near, the smallest), or
// `fill` when no node at all is covered. Triangles of zero area cover nothing.
// Cost O(m + n0 n1).
// Throws std::invalid_argument on a non-finite coordinate, value or fill, a
// non-finite origin, a spacing that is not > 0, or a count < 1.
GridValues rasterise_p1(const Eigen::Ref<const Triangles2>& triangles, const Eigen::Ref<const VertexValues>& values,
                        const Grid2& grid, double fill);

}  // namespace wingcrack
