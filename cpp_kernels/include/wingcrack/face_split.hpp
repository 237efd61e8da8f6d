#pragma once
// Splitting a conforming P2 triangle mesh along its crack edges so that the
// two crack faces get their own nodes, and pairing those nodes for contact.
//
// P2 node order is gmsh's: [v0, v1, v2, m01, m12, m20], counter-clockwise.
// An edge is [a, b, mid]. A crack edge is oriented along its fracture's
// direction d; the + face is the material on the left of d.
#include <cstdint>

#include <Eigen/Core>

namespace wingcrack {

// Plain row-major arrays, the shapes numpy hands over.
using Coords2 = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;
using P2Cells = Eigen::Matrix<std::int64_t, Eigen::Dynamic, 6, Eigen::RowMajor>;
using P2Edges = Eigen::Matrix<std::int64_t, Eigen::Dynamic, 3, Eigen::RowMajor>;
using NodePairs = Eigen::Matrix<std::int64_t, Eigen::Dynamic, 2, Eigen::RowMajor>;
using IndexVector = Eigen::Matrix<std::int64_t, Eigen::Dynamic, 1>;

struct SplitMesh {
  Coords2 x;                 // original nodes, then the new copies
  P2Cells cells;             // every cell refers to the copy on its own side
  P2Edges boundary_edges;    // remapped to the copy of the adjacent cell
  IndexVector parent;        // original node of each node of x
  NodePairs pairs;           // [plus, minus]: the two copies facing each other
  Coords2 pair_normal;       // unit left normal of d at the node (points into +)
  IndexVector pair_fracture; // fracture of each pair
  P2Edges crack_edges;       // the + face copy of each crack edge, same orientation
  P2Edges crack_edges_minus; // the - face copy
};

// Duplicates the nodes of the crack edges so that the crack faces become
// disconnected. Around a node the rays along its crack edges and its outer
// boundary edges cut the plane into angular sectors; every occupied sector
// gets its own copy of the node (the lowest-numbered occupied sector keeps the
// original index). So a node inside a straight crack gets 2 copies, an edge
// crack mouth 2, a T-junction 3, and an interior tip (one crack ray) stays one
// node and gets no pair. Throws std::invalid_argument on inconsistent input
// (index out of range, a crack edge that is not shared by one cell on each side).
SplitMesh split_faces(const Coords2& x, const P2Cells& cells, const P2Edges& crack_edges,
                      const IndexVector& crack_fracture, const P2Edges& boundary_edges);

}  // namespace wingcrack
