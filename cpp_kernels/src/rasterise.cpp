#include "wingcrack/rasterise.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace wingcrack {

namespace {

// Barycentric slack: a node on an edge shared by two triangles must be found
// in both (round-off puts it a few ulps outside one of them); the linear
// interpolant extrapolated by 1e-12 of the triangle differs from the value on
// the edge by 1e-12 of the value range across the triangle.
constexpr double kInside = 1e-12;
// Index slack of a triangle's bounding box in grid steps: the barycentric test
// above decides; this only keeps round-off in (x - origin) / spacing from
// dropping a node on the box's edge before the test sees it.
constexpr double kIndexSlack = 1e-9;

double cross(double ax, double ay, double bx, double by) { return ax * by - ay * bx; }

void check_grid(const Grid2& grid, double fill) {
  for (int d = 0; d < 2; ++d) {
    if (!std::isfinite(grid.origin[d])) throw std::invalid_argument("rasterise_p1: origin must be finite");
    if (!(grid.spacing[d] > 0.0) || !std::isfinite(grid.spacing[d]))
      throw std::invalid_argument("rasterise_p1: spacing must be finite and > 0, got " +
                                  std::to_string(grid.spacing[d]));
    if (grid.counts[d] < 1)
      throw std::invalid_argument("rasterise_p1: counts must be >= 1, got " + std::to_string(grid.counts[d]));
  }
  if (!std::isfinite(fill)) throw std::invalid_argument("rasterise_p1: fill must be finite");
}

// The nodes that no triangle covers take the value of the nearest covered
// node in 4-neighbour steps (layer by layer from every covered node at once;
// a node first reached from several of the previous layer takes the smallest
// value), so the grid has no holes where gmsh interpolates near the edge of
// the triangles: in slivers between a straight cell edge and a curved
// boundary, or just outside the domain.
void dilate(GridValues& g, std::vector<std::int32_t>& layer) {
  const Eigen::Index n0 = g.rows(), n1 = g.cols();
  double* v = g.data();
  std::vector<Eigen::Index> front, next;
  for (Eigen::Index k = 0; k < n0 * n1; ++k)
    if (layer[k] == 0) front.push_back(k);
  for (std::int32_t l = 1; !front.empty(); ++l) {
    next.clear();
    for (const Eigen::Index k : front) {
      const Eigen::Index i = k / n1, j = k % n1;
      const Eigen::Index nb[4] = {i > 0 ? k - n1 : -1, i + 1 < n0 ? k + n1 : -1, j > 0 ? k - 1 : -1,
                                  j + 1 < n1 ? k + 1 : -1};
      for (const Eigen::Index q : nb) {
        if (q < 0) continue;
        if (layer[q] < 0) {
          layer[q] = l;
          v[q] = v[k];
          next.push_back(q);
        } else if (layer[q] == l) {
          v[q] = std::min(v[q], v[k]);
        }
      }
    }
    front.swap(next);
  }
}

}  // namespace

GridValues rasterise_p1(const Eigen::Ref<const Triangles2>& triangles, const Eigen::Ref<const VertexValues>& values,
                        const Grid2& grid, double fill) {
  check_grid(grid, fill);
  if (values.rows() != triangles.rows())
    throw std::invalid_argument("rasterise_p1: " + std::to_string(values.rows()) + " value rows for " +
                                std::to_string(triangles.rows()) + " triangles");
  if (!triangles.allFinite() || !values.allFinite())
    throw std::invalid_argument("rasterise_p1: triangle coordinates and values must be finite");

  const Eigen::Index n0 = grid.counts[0], n1 = grid.counts[1];
  const double ox = grid.origin[0], oy = grid.origin[1], sx = grid.spacing[0], sy = grid.spacing[1];
  GridValues g = GridValues::Constant(n0, n1, std::numeric_limits<double>::infinity());
  double* v = g.data();

  for (Eigen::Index c = 0; c < triangles.rows(); ++c) {
    const double ax = triangles(c, 0), ay = triangles(c, 1), bx = triangles(c, 2), by = triangles(c, 3),
                 cx = triangles(c, 4), cy = triangles(c, 5);
    const double area2 = cross(bx - ax, by - ay, cx - ax, cy - ay);
    if (area2 == 0.0) continue;
    const double lo_x = std::min({ax, bx, cx}), hi_x = std::max({ax, bx, cx});
    const double lo_y = std::min({ay, by, cy}), hi_y = std::max({ay, by, cy});
    const double fi0 = std::ceil((lo_x - ox) / sx - kIndexSlack), fi1 = std::floor((hi_x - ox) / sx + kIndexSlack);
    const double fj0 = std::ceil((lo_y - oy) / sy - kIndexSlack), fj1 = std::floor((hi_y - oy) / sy + kIndexSlack);
    if (fi1 < 0.0 || fj1 < 0.0 || fi0 > static_cast<double>(n0 - 1) || fj0 > static_cast<double>(n1 - 1)) continue;
    const Eigen::Index i0 = static_cast<Eigen::Index>(std::max(fi0, 0.0));
    const Eigen::Index i1 = static_cast<Eigen::Index>(std::min(fi1, static_cast<double>(n0 - 1)));
    const Eigen::Index j0 = static_cast<Eigen::Index>(std::max(fj0, 0.0));
    const Eigen::Index j1 = static_cast<Eigen::Index>(std::min(fj1, static_cast<double>(n1 - 1)));
    const double va = values(c, 0), vb = values(c, 1), vc = values(c, 2);
    for (Eigen::Index i = i0; i <= i1; ++i) {
      const double px = ox + static_cast<double>(i) * sx;
      for (Eigen::Index j = j0; j <= j1; ++j) {
        const double py = oy + static_cast<double>(j) * sy;
        // each coordinate from its own opposite edge, so that the two
        // triangles of a shared edge see a node on it alike
        const double la = cross(bx - px, by - py, cx - px, cy - py) / area2;
        const double lb = cross(cx - px, cy - py, ax - px, ay - py) / area2;
        const double lc = cross(ax - px, ay - py, bx - px, by - py) / area2;
        if (la < -kInside || lb < -kInside || lc < -kInside) continue;
        double& node = v[i * n1 + j];
        node = std::min(node, la * va + lb * vb + lc * vc);
      }
    }
  }

  std::vector<std::int32_t> layer(static_cast<std::size_t>(n0 * n1), -1);
  bool any = false;
  for (Eigen::Index k = 0; k < n0 * n1; ++k)
    if (std::isfinite(v[k])) {
      layer[k] = 0;
      any = true;
    }
  if (!any) return GridValues::Constant(n0, n1, fill);
  dilate(g, layer);
  return g;
}

}  // namespace wingcrack
