#include "wingcrack/error_estimate.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace wingcrack {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void check_cells(const Coords2& x, const P2Cells& cells, const char* who) {
  if (cells.size() > 0 && (cells.minCoeff() < 0 || cells.maxCoeff() >= x.rows()))
    throw std::invalid_argument(std::string(who) + ": cells refer to a node out of range");
}

// Area of the straight vertex triangle; the sign (orientation) is irrelevant here.
double vertex_area(const Coords2& x, const P2Cells& cells, Eigen::Index c) {
  const auto a = cells(c, 0), b = cells(c, 1), d = cells(c, 2);
  const double ux = x(b, 0) - x(a, 0), uy = x(b, 1) - x(a, 1);
  const double vx = x(d, 0) - x(a, 0), vy = x(d, 1) - x(a, 1);
  return 0.5 * std::abs(ux * vy - uy * vx);
}

// |s|^2 with sxy counted twice: the Frobenius norm of the symmetric 2x2 tensor.
double frobenius2(double sxx, double syy, double sxy) { return sxx * sxx + syy * syy + 2.0 * sxy * sxy; }

}  // namespace

ZZError zz_error(const Coords2& x, const P2Cells& cells, const Eigen::Ref<const CellStress>& cell_stress) {
  check_cells(x, cells, "zz_error");
  const Eigen::Index m = cells.rows(), n = x.rows();
  if (cell_stress.rows() != m)
    throw std::invalid_argument("zz_error: cell_stress has " + std::to_string(cell_stress.rows()) +
                                " rows, cells " + std::to_string(m));

  Eigen::VectorXd area(m);
  std::vector<double> weight(n, 0.0);
  NodalStress sum = NodalStress::Zero(n, 3);
  for (Eigen::Index c = 0; c < m; ++c) {
    area(c) = vertex_area(x, cells, c);
    if (!(area(c) > 0.0))
      throw std::invalid_argument("zz_error: cell " + std::to_string(c) + " has zero area");
    for (int k = 0; k < 3; ++k) {
      const auto v = cells(c, k);
      weight[v] += area(c);
      for (int s = 0; s < 3; ++s) sum(v, s) += area(c) * cell_stress(c, 3 * k + s);
    }
  }

  ZZError out;
  out.recovered.resize(n, 3);
  for (Eigen::Index v = 0; v < n; ++v)
    for (int s = 0; s < 3; ++s) out.recovered(v, s) = weight[v] > 0.0 ? sum(v, s) / weight[v] : kNaN;

  // e = sigma_h - sigma* is linear on the cell, |e|^2 quadratic: the
  // edge-midpoint rule (weights A/3) integrates it exactly.
  out.eta.resize(m);
  for (Eigen::Index c = 0; c < m; ++c) {
    double e[3][3];
    for (int k = 0; k < 3; ++k)
      for (int s = 0; s < 3; ++s) e[k][s] = cell_stress(c, 3 * k + s) - out.recovered(cells(c, k), s);
    double integral = 0.0;
    for (int k = 0; k < 3; ++k) {
      const int l = (k + 1) % 3;
      integral += frobenius2(0.5 * (e[k][0] + e[l][0]), 0.5 * (e[k][1] + e[l][1]), 0.5 * (e[k][2] + e[l][2]));
    }
    out.eta(c) = std::sqrt(area(c) / 3.0 * integral);
  }
  return out;
}

Eigen::VectorXd zz_sizes(const Coords2& x, const P2Cells& cells, const Eigen::VectorXd& eta,
                         const Eigen::VectorXd& h_current, double total_error_target, double p, double h_min,
                         double h_max, double grading) {
  check_cells(x, cells, "zz_sizes");
  const Eigen::Index m = cells.rows(), n = x.rows();
  if (eta.size() != m || h_current.size() != m)
    throw std::invalid_argument("zz_sizes: eta and h_current need one value per cell (" + std::to_string(m) +
                                "), got " + std::to_string(eta.size()) + " and " +
                                std::to_string(h_current.size()));
  if (!(total_error_target > 0.0) || !(p > 0.0) || !(grading > 0.0))
    throw std::invalid_argument("zz_sizes: total_error_target, p and grading must be > 0");
  if (!(h_min > 0.0) || !(h_min <= h_max) || !std::isfinite(h_max))
    throw std::invalid_argument("zz_sizes: need 0 < h_min <= h_max < inf");
  if (m > 0 && (!(eta.minCoeff() >= 0.0) || !eta.allFinite()))
    throw std::invalid_argument("zz_sizes: eta must be finite and >= 0");
  if (m > 0 && (!(h_current.minCoeff() > 0.0) || !h_current.allFinite()))
    throw std::invalid_argument("zz_sizes: h_current must be finite and > 0");

  const double e_star = total_error_target / std::sqrt(static_cast<double>(m));
  Eigen::VectorXd size = Eigen::VectorXd::Constant(n, kNaN);
  for (Eigen::Index c = 0; c < m; ++c) {
    const double h = eta(c) > 0.0 ? h_current(c) * std::pow(e_star / eta(c), 1.0 / p) : h_max;
    const double clamped = std::clamp(h, h_min, h_max);  // also catches inf from a denormal eta
    for (int k = 0; k < 3; ++k) {
      const auto v = cells(c, k);
      if (!(size(v) <= clamped)) size(v) = clamped;  // NaN (unset) compares false
    }
  }

  // Vertex adjacency (CSR over the 3 vertex edges of every cell, both ways;
  // an interior edge appears twice, which the relaxation does not mind).
  std::vector<Eigen::Index> start(n + 1, 0), nbr(6 * m);
  for (Eigen::Index c = 0; c < m; ++c)
    for (int k = 0; k < 3; ++k) start[cells(c, k) + 1] += 2;
  for (Eigen::Index v = 0; v < n; ++v) start[v + 1] += start[v];
  std::vector<Eigen::Index> fill(start.begin(), start.end() - 1);
  for (Eigen::Index c = 0; c < m; ++c)
    for (int k = 0; k < 3; ++k) {
      const auto a = cells(c, k), b = cells(c, (k + 1) % 3);
      nbr[fill[a]++] = b;
      nbr[fill[b]++] = a;
    }

  // Dijkstra with every vertex a source at its own size: pops vertices in
  // increasing final size, so each is settled once and the bound is exact.
  using Item = std::pair<double, Eigen::Index>;
  std::vector<Item> heap;
  heap.reserve(n);
  for (Eigen::Index v = 0; v < n; ++v)
    if (!std::isnan(size(v))) heap.emplace_back(size(v), v);
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue(std::greater<Item>(), std::move(heap));
  while (!queue.empty()) {
    const auto [s, i] = queue.top();
    queue.pop();
    if (s > size(i)) continue;  // stale entry
    for (Eigen::Index e = start[i]; e < start[i + 1]; ++e) {
      const auto j = nbr[e];
      const double bound = s + grading * std::hypot(x(i, 0) - x(j, 0), x(i, 1) - x(j, 1));
      if (bound < size(j)) {
        size(j) = bound;
        queue.emplace(bound, j);
      }
    }
  }
  return size;
}

}  // namespace wingcrack
