#include "wingcrack/face_split.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace wingcrack {
namespace {

using Vec2 = Eigen::Vector2d;

constexpr double kPi = 3.14159265358979323846;
// Two rays closer than this (radians) are the same ray.
constexpr double kSameRay = 1e-9;
// Local [a, b, mid] of the three edges of a P2 triangle in gmsh order.
constexpr int kEdge[3][3] = {{0, 1, 3}, {1, 2, 4}, {2, 0, 5}};

Vec2 node(const Coords2& x, std::int64_t i) { return x.row(i).transpose(); }

// Tangent (pointing from a to b) of the P2 edge [a, b, mid] at its end a
// (which = 0), end b (1) or mid node (2).
Vec2 edge_tangent(const Coords2& x, std::int64_t a, std::int64_t b, std::int64_t m, int which) {
  const Vec2 xa = node(x, a), xb = node(x, b), xm = node(x, m);
  if (which == 0) return 4.0 * xm - 3.0 * xa - xb;
  if (which == 1) return 3.0 * xb - 4.0 * xm + xa;
  return xb - xa;
}

// Compressed adjacency: items of key k are item[start[k] .. start[k+1]).
struct Adjacency {
  std::vector<std::int64_t> start, item;
};

template <class ForEachPair>
Adjacency build_adjacency(std::int64_t n_keys, ForEachPair for_each) {
  Adjacency adj;
  adj.start.assign(n_keys + 1, 0);
  for_each([&](std::int64_t key, std::int64_t) { ++adj.start[key + 1]; });
  for (std::int64_t k = 0; k < n_keys; ++k) adj.start[k + 1] += adj.start[k];
  adj.item.resize(adj.start[n_keys]);
  std::vector<std::int64_t> fill(adj.start.begin(), adj.start.end() - 1);
  for_each([&](std::int64_t key, std::int64_t value) { adj.item[fill[key]++] = value; });
  return adj;
}

void check_indices(const Eigen::Ref<const Eigen::Matrix<std::int64_t, Eigen::Dynamic, Eigen::Dynamic,
                                                         Eigen::RowMajor>>& a,
                   std::int64_t n, const char* what) {
  if (a.size() > 0 && (a.minCoeff() < 0 || a.maxCoeff() >= n))
    throw std::invalid_argument(std::string("split_faces: ") + what + " refers to a node out of range");
}

// Adds to `angles` the directions in which the edge [a, b, m] leaves node v.
void add_rays(const Coords2& x, std::int64_t v, std::int64_t a, std::int64_t b, std::int64_t m,
              std::vector<double>& angles) {
  auto push = [&](const Vec2& t) { angles.push_back(std::atan2(t.y(), t.x())); };
  if (v == a) push(edge_tangent(x, a, b, m, 0));
  if (v == b) push(-edge_tangent(x, a, b, m, 1));
  if (v == m) {
    const Vec2 t = edge_tangent(x, a, b, m, 2);
    push(t);
    push(-t);
  }
}

// Sorted distinct ray angles in (-pi, pi].
std::vector<double> distinct_rays(std::vector<double> angles) {
  std::sort(angles.begin(), angles.end());
  std::vector<double> out;
  for (double a : angles)
    if (out.empty() || a - out.back() > kSameRay) out.push_back(a);
  if (out.size() > 1 && out.front() + 2.0 * kPi - out.back() <= kSameRay) out.pop_back();
  return out;
}

// Sector i lies between ray i and ray i+1 counter-clockwise; the last one
// wraps from the last ray to the first.
std::size_t sector_of(const std::vector<double>& rays, double angle) {
  const auto it = std::upper_bound(rays.begin(), rays.end(), angle);
  if (it == rays.begin()) return rays.size() - 1;
  return static_cast<std::size_t>(it - rays.begin()) - 1;
}

}  // namespace

SplitMesh split_faces(const Coords2& x, const P2Cells& cells, const P2Edges& crack_edges,
                      const IndexVector& crack_fracture, const P2Edges& boundary_edges) {
  const std::int64_t n = x.rows(), m = cells.rows(), k = crack_edges.rows(), j = boundary_edges.rows();
  if (crack_fracture.size() != k)
    throw std::invalid_argument("split_faces: crack_fracture needs one entry per crack edge");
  check_indices(cells, n, "cells");
  check_indices(crack_edges, n, "crack_edges");
  check_indices(boundary_edges, n, "boundary_edges");

  // Crack nodes get a compact local index.
  std::vector<std::int64_t> local(n, -1), crack_nodes;
  for (std::int64_t e = 0; e < k; ++e)
    for (int q = 0; q < 3; ++q) {
      const std::int64_t v = crack_edges(e, q);
      if (local[v] < 0) {
        local[v] = static_cast<std::int64_t>(crack_nodes.size());
        crack_nodes.push_back(v);
      }
    }
  const std::int64_t nc = static_cast<std::int64_t>(crack_nodes.size());

  const Adjacency node_cells = build_adjacency(nc, [&](auto emit) {
    for (std::int64_t c = 0; c < m; ++c)
      for (int q = 0; q < 6; ++q)
        if (local[cells(c, q)] >= 0) emit(local[cells(c, q)], c);
  });
  const Adjacency node_crack = build_adjacency(nc, [&](auto emit) {
    for (std::int64_t e = 0; e < k; ++e)
      for (int q = 0; q < 3; ++q) emit(local[crack_edges(e, q)], e);
  });
  const Adjacency node_boundary = build_adjacency(nc, [&](auto emit) {
    for (std::int64_t e = 0; e < j; ++e)
      for (int q = 0; q < 3; ++q)
        if (local[boundary_edges(e, q)] >= 0) emit(local[boundary_edges(e, q)], e);
  });

  SplitMesh out;
  out.cells = cells;
  std::vector<Vec2> new_x;
  std::vector<std::int64_t> new_parent;

  std::vector<double> angles;
  std::vector<std::size_t> cell_sector;
  std::vector<std::int64_t> copy_of_sector;
  for (std::int64_t l = 0; l < nc; ++l) {
    const std::int64_t v = crack_nodes[l];
    angles.clear();
    for (auto i = node_crack.start[l]; i < node_crack.start[l + 1]; ++i) {
      const auto e = node_crack.item[i];
      add_rays(x, v, crack_edges(e, 0), crack_edges(e, 1), crack_edges(e, 2), angles);
    }
    for (auto i = node_boundary.start[l]; i < node_boundary.start[l + 1]; ++i) {
      const auto e = node_boundary.item[i];
      add_rays(x, v, boundary_edges(e, 0), boundary_edges(e, 1), boundary_edges(e, 2), angles);
    }
    const std::vector<double> rays = distinct_rays(angles);
    if (rays.size() <= 1) continue;  // an interior tip: one sector, nothing to split

    // A cell lies in the sector that holds the direction to its centroid.
    const Vec2 xv = node(x, v);
    const auto c0 = node_cells.start[l], c1 = node_cells.start[l + 1];
    cell_sector.resize(c1 - c0);
    for (auto i = c0; i < c1; ++i) {
      const auto c = node_cells.item[i];
      const Vec2 d = (node(x, cells(c, 0)) + node(x, cells(c, 1)) + node(x, cells(c, 2))) / 3.0 - xv;
      cell_sector[i - c0] = sector_of(rays, std::atan2(d.y(), d.x()));
    }
    copy_of_sector.assign(rays.size(), -1);
    bool original_used = false;
    for (std::size_t s = 0; s < rays.size(); ++s) {
      if (std::find(cell_sector.begin(), cell_sector.end(), s) == cell_sector.end()) continue;
      if (!original_used) {
        copy_of_sector[s] = v;
        original_used = true;
      } else {
        copy_of_sector[s] = n + static_cast<std::int64_t>(new_x.size());
        new_x.push_back(xv);
        new_parent.push_back(v);
      }
    }
    for (auto i = c0; i < c1; ++i) {
      const auto c = node_cells.item[i];
      for (int q = 0; q < 6; ++q)
        if (cells(c, q) == v) out.cells(c, q) = copy_of_sector[cell_sector[i - c0]];
    }
  }

  const std::int64_t n_new = n + static_cast<std::int64_t>(new_x.size());
  out.x.resize(n_new, 2);
  out.x.topRows(n) = x;
  out.parent.resize(n_new);
  for (std::int64_t i = 0; i < n; ++i) out.parent(i) = i;
  for (std::size_t i = 0; i < new_x.size(); ++i) {
    out.x.row(n + i) = new_x[i].transpose();
    out.parent(n + i) = new_parent[i];
  }

  // In a P2 mesh the mid node names its edge: mid node -> (cell, local edge).
  std::vector<std::int64_t> mid_cells(2 * n, -1);
  for (std::int64_t c = 0; c < m; ++c)
    for (int le = 0; le < 3; ++le) {
      const std::int64_t mid = cells(c, kEdge[le][2]);
      const std::int64_t code = 3 * c + le;
      if (mid_cells[2 * mid] < 0) mid_cells[2 * mid] = code;
      else mid_cells[2 * mid + 1] = code;
    }
  // The copy of edge [a, b, mid] as seen by the cell of `code`.
  auto edge_in_cell = [&](std::int64_t code, std::int64_t a, std::int64_t b, std::int64_t mid,
                          std::int64_t* copy) {
    const std::int64_t c = code / 3;
    const int* le = kEdge[code % 3];
    const std::int64_t orig[3] = {a, b, mid};
    for (int q = 0; q < 3; ++q) {
      int hit = -1;
      for (int r = 0; r < 3; ++r)
        if (cells(c, le[r]) == orig[q]) hit = le[r];
      if (hit < 0) throw std::invalid_argument("split_faces: an edge's ends do not match its cell");
      copy[q] = out.cells(c, hit);
    }
  };

  out.boundary_edges = boundary_edges;
  for (std::int64_t e = 0; e < j; ++e) {
    const std::int64_t code = mid_cells[2 * boundary_edges(e, 2)];
    if (code < 0) throw std::invalid_argument("split_faces: boundary edge " + std::to_string(e) + " has no cell");
    std::int64_t copy[3];
    edge_in_cell(code, boundary_edges(e, 0), boundary_edges(e, 1), boundary_edges(e, 2), copy);
    for (int q = 0; q < 3; ++q) out.boundary_edges(e, q) = copy[q];
  }

  out.crack_edges.resize(k, 3);
  out.crack_edges_minus.resize(k, 3);
  std::map<std::pair<std::int64_t, std::int64_t>, std::int64_t> pair_index;
  std::vector<std::pair<std::int64_t, std::int64_t>> pairs;
  std::vector<Vec2> normal_sum;
  std::vector<std::int64_t> fracture;
  for (std::int64_t e = 0; e < k; ++e) {
    const std::int64_t a = crack_edges(e, 0), b = crack_edges(e, 1), mid = crack_edges(e, 2);
    const std::int64_t codes[2] = {mid_cells[2 * mid], mid_cells[2 * mid + 1]};
    if (codes[0] < 0 || codes[1] < 0)
      throw std::invalid_argument("split_faces: crack edge " + std::to_string(e) +
                                  " is not shared by two cells");
    int sides[2];
    for (int s = 0; s < 2; ++s) {
      const std::int64_t c = codes[s] / 3;
      const std::int64_t opposite = cells(c, (kEdge[codes[s] % 3][1] + 1) % 3);
      const Vec2 xa = node(x, a), d = node(x, b) - xa, r = node(x, opposite) - xa;
      sides[s] = d.x() * r.y() - d.y() * r.x() > 0.0 ? +1 : -1;
    }
    if (sides[0] == sides[1])
      throw std::invalid_argument("split_faces: both cells of crack edge " + std::to_string(e) +
                                  " lie on the same side");
    std::int64_t plus[3], minus[3];
    edge_in_cell(codes[sides[0] > 0 ? 0 : 1], a, b, mid, plus);
    edge_in_cell(codes[sides[0] > 0 ? 1 : 0], a, b, mid, minus);
    for (int q = 0; q < 3; ++q) {
      out.crack_edges(e, q) = plus[q];
      out.crack_edges_minus(e, q) = minus[q];
    }
    // Pairs in the order a, mid, b along each edge; a polyline vertex is met twice.
    for (int q : {0, 2, 1}) {
      if (plus[q] == minus[q]) continue;
      const Vec2 t = edge_tangent(x, a, b, mid, q).normalized();
      const Vec2 left(-t.y(), t.x());
      const auto key = std::make_pair(plus[q], minus[q]);
      const auto found = pair_index.find(key);
      if (found == pair_index.end()) {
        pair_index.emplace(key, static_cast<std::int64_t>(pairs.size()));
        pairs.push_back(key);
        normal_sum.push_back(left);
        fracture.push_back(crack_fracture(e));
      } else {
        normal_sum[found->second] += left;
      }
    }
  }
  const auto p = static_cast<std::int64_t>(pairs.size());
  out.pairs.resize(p, 2);
  out.pair_normal.resize(p, 2);
  out.pair_fracture.resize(p);
  for (std::int64_t i = 0; i < p; ++i) {
    out.pairs(i, 0) = pairs[i].first;
    out.pairs(i, 1) = pairs[i].second;
    out.pair_normal.row(i) = normal_sum[i].normalized().transpose();
    out.pair_fracture(i) = fracture[i];
  }
  return out;
}

}  // namespace wingcrack
