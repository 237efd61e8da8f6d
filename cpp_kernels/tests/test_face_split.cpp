// split_faces on hand-made P2 meshes whose answer can be counted by hand.
#include <gtest/gtest.h>

#include <array>
#include <map>
#include <set>
#include <vector>

#include "wingcrack/face_split.hpp"

using namespace wingcrack;

namespace {

// Structured P2 mesh of nx x ny unit squares, each cut along its (0,0)-(1,1)
// diagonal. Nodes sit on the half-integer lattice (I/2, J/2); all are used.
struct Grid {
  int nx, ny;
  Coords2 x;
  P2Cells cells;
  P2Edges boundary;

  Grid(int nx_, int ny_) : nx(nx_), ny(ny_) {
    x.resize((2 * nx + 1) * (2 * ny + 1), 2);
    for (int J = 0; J <= 2 * ny; ++J)
      for (int I = 0; I <= 2 * nx; ++I) x.row(at(I, J)) << 0.5 * I, 0.5 * J;
    cells.resize(2 * nx * ny, 6);
    int c = 0;
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const int I = 2 * i, J = 2 * j;
        cells.row(c++) << at(I, J), at(I + 2, J), at(I + 2, J + 2), at(I + 1, J), at(I + 2, J + 1), at(I + 1, J + 1);
        cells.row(c++) << at(I, J), at(I + 2, J + 2), at(I, J + 2), at(I + 1, J + 1), at(I + 1, J + 2), at(I, J + 1);
      }
    std::vector<std::array<std::int64_t, 3>> b;
    for (int i = 0; i < nx; ++i) b.push_back(horizontal(i, 0)), b.push_back(horizontal(i, ny));
    for (int j = 0; j < ny; ++j) b.push_back(vertical(0, j)), b.push_back(vertical(nx, j));
    boundary.resize(static_cast<Eigen::Index>(b.size()), 3);
    for (std::size_t e = 0; e < b.size(); ++e) boundary.row(e) << b[e][0], b[e][1], b[e][2];
  }
  std::int64_t at(int I, int J) const { return I + (2 * nx + 1) * J; }
  std::int64_t vertex(int i, int j) const { return at(2 * i, 2 * j); }
  // Edge from vertex (i, j) to (i+1, j), and from (i, j) to (i, j+1).
  std::array<std::int64_t, 3> horizontal(int i, int j) const {
    return {at(2 * i, 2 * j), at(2 * i + 2, 2 * j), at(2 * i + 1, 2 * j)};
  }
  std::array<std::int64_t, 3> vertical(int i, int j) const {
    return {at(2 * i, 2 * j), at(2 * i, 2 * j + 2), at(2 * i, 2 * j + 1)};
  }
};

P2Edges edges(const std::vector<std::array<std::int64_t, 3>>& list) {
  P2Edges e(static_cast<Eigen::Index>(list.size()), 3);
  for (std::size_t i = 0; i < list.size(); ++i) e.row(i) << list[i][0], list[i][1], list[i][2];
  return e;
}

IndexVector zeros(Eigen::Index n) { return IndexVector::Zero(n); }

Eigen::Vector2d centroid(const SplitMesh& s, Eigen::Index c) {
  return (s.x.row(s.cells(c, 0)) + s.x.row(s.cells(c, 1)) + s.x.row(s.cells(c, 2))).transpose() / 3.0;
}

// Every copy of a crack node is used only by cells of one region, and
// different regions use different copies: region(centroid) -> int.
template <class Region>
void expect_each_cell_keeps_its_side(const SplitMesh& s, Eigen::Index n_original, Region region) {
  std::set<std::int64_t> split;  // original nodes that got copies
  for (Eigen::Index v = n_original; v < s.x.rows(); ++v) {
    EXPECT_LT(s.parent(v), n_original);
    EXPECT_EQ(s.x(v, 0), s.x(s.parent(v), 0));  // a copy sits exactly on its original
    EXPECT_EQ(s.x(v, 1), s.x(s.parent(v), 1));
    split.insert(s.parent(v));
  }
  std::map<std::int64_t, int> region_of_node;
  for (Eigen::Index c = 0; c < s.cells.rows(); ++c) {
    const int r = region(centroid(s, c));
    for (int q = 0; q < 6; ++q) {
      const auto v = s.cells(c, q);
      if (!split.count(s.parent(v))) continue;
      const auto it = region_of_node.emplace(v, r).first;
      EXPECT_EQ(it->second, r) << "node " << v << " is used on two sides";
    }
  }
}

}  // namespace

TEST(SplitFaces, StraightCrackThroughPatch) {
  // Crack y = 1 across a 2x2 patch, both ends on the outer boundary: its 3
  // vertices and 2 mid nodes each get one extra copy and one pair.
  const Grid g(2, 2);
  const auto crack = edges({g.horizontal(0, 1), g.horizontal(1, 1)});
  const SplitMesh s = split_faces(g.x, g.cells, crack, zeros(2), g.boundary);
  EXPECT_EQ(s.x.rows(), 25 + 5);
  ASSERT_EQ(s.pairs.rows(), 5);
  for (Eigen::Index p = 0; p < 5; ++p) {
    EXPECT_NE(s.pairs(p, 0), s.pairs(p, 1));
    EXPECT_EQ(s.parent(s.pairs(p, 0)), s.parent(s.pairs(p, 1)));
    EXPECT_DOUBLE_EQ(s.pair_normal(p, 0), 0.0);  // d = +x, left normal = +y exactly
    EXPECT_DOUBLE_EQ(s.pair_normal(p, 1), 1.0);
    EXPECT_EQ(s.pair_fracture(p), 0);
  }
  std::set<std::int64_t> plus, minus;
  for (Eigen::Index p = 0; p < 5; ++p) plus.insert(s.pairs(p, 0)), minus.insert(s.pairs(p, 1));
  for (Eigen::Index c = 0; c < s.cells.rows(); ++c) {
    const bool above = centroid(s, c).y() > 1.0;
    for (int q = 0; q < 6; ++q) {
      const auto v = s.cells(c, q);
      EXPECT_FALSE(above ? minus.count(v) : plus.count(v)) << "cell " << c << " uses the other face's node " << v;
    }
  }
  // + face copies of the crack edges belong to the upper cells, same orientation.
  for (Eigen::Index e = 0; e < 2; ++e)
    for (int q = 0; q < 3; ++q) {
      EXPECT_TRUE(plus.count(s.crack_edges(e, q)));
      EXPECT_TRUE(minus.count(s.crack_edges_minus(e, q)));
      EXPECT_EQ(s.parent(s.crack_edges(e, q)), crack(e, q));
    }
  expect_each_cell_keeps_its_side(s, 25, [](const Eigen::Vector2d& c) { return c.y() > 1.0 ? 1 : 0; });
  // The boundary edges at the two mouths follow their cells.
  for (Eigen::Index e = 0; e < s.boundary_edges.rows(); ++e) {
    const double ymid = s.x(s.boundary_edges(e, 2), 1);
    for (int q = 0; q < 3; ++q) {
      const auto v = s.boundary_edges(e, q);
      if (ymid > 1.0) EXPECT_FALSE(minus.count(v));
      else EXPECT_FALSE(plus.count(v));
    }
  }
}

TEST(SplitFaces, InteriorCrackTipsAreNotSplit) {
  // Crack from (1,1) to (3,1) inside a 4x2 patch: 2 edges, 2 interior tips.
  // Pairs: 1 inner vertex + 2 mid nodes = 2 * edges - tips = 3.
  const Grid g(4, 2);
  const auto crack = edges({g.horizontal(1, 1), g.horizontal(2, 1)});
  const SplitMesh s = split_faces(g.x, g.cells, crack, zeros(2), g.boundary);
  EXPECT_EQ(s.x.rows(), g.x.rows() + 3);
  EXPECT_EQ(s.pairs.rows(), 3);
  for (Eigen::Index p = 0; p < s.pairs.rows(); ++p)
    for (int q = 0; q < 2; ++q) {
      EXPECT_NE(s.parent(s.pairs(p, q)), g.vertex(1, 1));
      EXPECT_NE(s.parent(s.pairs(p, q)), g.vertex(3, 1));
    }
  // The tips keep one node, shared by cells above and below.
  EXPECT_EQ(s.crack_edges(0, 0), g.vertex(1, 1));
  EXPECT_EQ(s.crack_edges_minus(0, 0), g.vertex(1, 1));
  EXPECT_EQ(s.crack_edges(1, 1), g.vertex(3, 1));
  EXPECT_EQ(s.crack_edges_minus(1, 1), g.vertex(3, 1));
}

TEST(SplitFaces, EdgeCrackFromBoundary) {
  // Crack from the mouth (0,1) on the left side to the tip (1,1), reversed
  // orientation d = -x to exercise the sides: + face (left of d) is below.
  const Grid g(2, 2);
  const auto e = g.horizontal(0, 1);
  const auto crack = edges({{e[1], e[0], e[2]}});
  const SplitMesh s = split_faces(g.x, g.cells, crack, zeros(1), g.boundary);
  EXPECT_EQ(s.x.rows(), 25 + 2);
  ASSERT_EQ(s.pairs.rows(), 2);  // mouth and mid node
  for (Eigen::Index p = 0; p < 2; ++p) {
    EXPECT_NEAR(s.pair_normal(p, 0), 0.0, 1e-15);
    EXPECT_NEAR(s.pair_normal(p, 1), -1.0, 1e-15);
  }
  std::set<std::int64_t> plus, minus;
  for (Eigen::Index p = 0; p < 2; ++p) plus.insert(s.pairs(p, 0)), minus.insert(s.pairs(p, 1));
  for (Eigen::Index c = 0; c < s.cells.rows(); ++c) {
    const bool below = centroid(s, c).y() < 1.0;
    for (int q = 0; q < 6; ++q) EXPECT_FALSE(below ? minus.count(s.cells(c, q)) : plus.count(s.cells(c, q)));
  }
  // The two boundary edges meeting at the mouth now hold different copies.
  std::set<std::int64_t> mouth_copies;
  for (Eigen::Index b = 0; b < s.boundary_edges.rows(); ++b)
    for (int q = 0; q < 2; ++q)
      if (s.parent(s.boundary_edges(b, q)) == g.vertex(0, 1)) mouth_copies.insert(s.boundary_edges(b, q));
  EXPECT_EQ(mouth_copies.size(), 2u);
}

TEST(SplitFaces, TJunctionGetsThreeCopies) {
  // In a 4x4 patch: fracture 0 from (1,2) to (3,2), fracture 1 from (2,2) up
  // to (2,3). The junction (2,2) has 3 crack rays -> 3 copies and 3 pairs.
  const Grid g(4, 4);
  const auto crack = edges({g.horizontal(1, 2), g.horizontal(2, 2), g.vertical(2, 2)});
  IndexVector fracture(3);
  fracture << 0, 0, 1;
  const SplitMesh s = split_faces(g.x, g.cells, crack, fracture, g.boundary);
  const auto junction = g.vertex(2, 2);
  int copies = 0;
  for (Eigen::Index v = 0; v < s.x.rows(); ++v) copies += s.parent(v) == junction;
  EXPECT_EQ(copies, 3);
  // Pairs: mids 3, inner vertex of fracture 0 seen as 1 pair from its two
  // rays... except it is the junction, whose 3 rays give 3 distinct pairs.
  // Tips (1,2), (3,2), (2,3) are not split. Total = 3 mids + 3 junction = 6.
  EXPECT_EQ(s.pairs.rows(), 6);
  EXPECT_EQ(s.x.rows(), g.x.rows() + 3 + 2);
  int junction_pairs = 0;
  for (Eigen::Index p = 0; p < s.pairs.rows(); ++p)
    if (s.parent(s.pairs(p, 0)) == junction) {
      ++junction_pairs;
      const Eigen::Vector2d expected = s.pair_fracture(p) == 0 ? Eigen::Vector2d(0, 1) : Eigen::Vector2d(-1, 0);
      EXPECT_NEAR((s.pair_normal.row(p).transpose() - expected).norm(), 0.0, 1e-15);
    }
  EXPECT_EQ(junction_pairs, 3);
  expect_each_cell_keeps_its_side(s, g.x.rows(), [](const Eigen::Vector2d& c) {
    if (c.y() < 2.0) return 0;
    return c.x() < 2.0 ? 1 : 2;
  });
  // The three regions around the junction use three different copies.
  std::map<int, std::set<std::int64_t>> used;
  for (Eigen::Index c = 0; c < s.cells.rows(); ++c)
    for (int q = 0; q < 3; ++q)
      if (s.parent(s.cells(c, q)) == junction) {
        const Eigen::Vector2d m = centroid(s, c);
        used[m.y() < 2.0 ? 0 : (m.x() < 2.0 ? 1 : 2)].insert(s.cells(c, q));
      }
  ASSERT_EQ(used.size(), 3u);
  std::set<std::int64_t> all;
  for (const auto& [r, nodes] : used) {
    EXPECT_EQ(nodes.size(), 1u);
    all.insert(nodes.begin(), nodes.end());
  }
  EXPECT_EQ(all.size(), 3u);
}

TEST(SplitFaces, RejectsCrackEdgeOnBoundary) {
  const Grid g(2, 2);
  EXPECT_THROW(split_faces(g.x, g.cells, edges({g.horizontal(0, 0)}), zeros(1), g.boundary), std::invalid_argument);
}
