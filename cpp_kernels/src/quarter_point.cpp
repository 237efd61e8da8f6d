#include "wingcrack/quarter_point.hpp"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>
#include <vector>

namespace wingcrack {
namespace {

constexpr int kEdge[3][3] = {{0, 1, 3}, {1, 2, 4}, {2, 0, 5}};

// The points of the degree-4 Dunavant rule on the reference triangle:
// barycentric (a, a, 1 - 2a) and permutations, all interior.
struct QuadPoint {
  double xi, eta;
};
constexpr double kA1 = 0.445948490915965;
constexpr double kA2 = 0.091576213509771;
constexpr std::array<QuadPoint, 6> kRule{{{kA1, kA1},
                                          {1.0 - 2.0 * kA1, kA1},
                                          {kA1, 1.0 - 2.0 * kA1},
                                          {kA2, kA2},
                                          {1.0 - 2.0 * kA2, kA2},
                                          {kA2, 1.0 - 2.0 * kA2}}};

// det J of the P2 map of cell c at (xi, eta), nodes [v0, v1, v2, m01, m12, m20].
double det_jacobian(const Coords2& x, const P2Cells& cells, std::int64_t c, double xi, double eta) {
  const double l0 = 1.0 - xi - eta, l1 = xi, l2 = eta;
  const double dxi[6] = {-(4.0 * l0 - 1.0), 4.0 * l1 - 1.0, 0.0, 4.0 * (l0 - l1), 4.0 * l2, -4.0 * l2};
  const double deta[6] = {-(4.0 * l0 - 1.0), 0.0, 4.0 * l2 - 1.0, -4.0 * l1, 4.0 * l1, 4.0 * (l0 - l2)};
  double x_xi = 0, x_eta = 0, y_xi = 0, y_eta = 0;
  for (int i = 0; i < 6; ++i) {
    const auto v = cells(c, i);
    x_xi += dxi[i] * x(v, 0);
    y_xi += dxi[i] * x(v, 1);
    x_eta += deta[i] * x(v, 0);
    y_eta += deta[i] * x(v, 1);
  }
  return x_xi * y_eta - x_eta * y_xi;
}

void check_cells(const Coords2& x, const P2Cells& cells, const char* who) {
  if (cells.size() > 0 && (cells.minCoeff() < 0 || cells.maxCoeff() >= x.rows()))
    throw std::invalid_argument(std::string(who) + ": cells refer to a node out of range");
}

}  // namespace

Coords2 quarter_points(const Coords2& x, const P2Cells& cells, const IndexVector& tip_nodes) {
  check_cells(x, cells, "quarter_points");
  std::vector<char> is_tip(x.rows(), 0);
  for (Eigen::Index i = 0; i < tip_nodes.size(); ++i) {
    if (tip_nodes(i) < 0 || tip_nodes(i) >= x.rows())
      throw std::invalid_argument("quarter_points: tip node out of range");
    is_tip[tip_nodes(i)] = 1;
  }
  Coords2 out = x;
  for (Eigen::Index c = 0; c < cells.rows(); ++c)
    for (const auto& e : kEdge) {
      const auto a = cells(c, e[0]), b = cells(c, e[1]), mid = cells(c, e[2]);
      if (is_tip[a] == is_tip[b]) continue;
      const auto tip = is_tip[a] ? a : b, corner = is_tip[a] ? b : a;
      out.row(mid) = 0.75 * x.row(tip) + 0.25 * x.row(corner);
    }
  return out;
}

Eigen::VectorXd min_jacobian(const Coords2& x, const P2Cells& cells) {
  check_cells(x, cells, "min_jacobian");
  Eigen::VectorXd out(cells.rows());
  for (Eigen::Index c = 0; c < cells.rows(); ++c) {
    double lowest = det_jacobian(x, cells, c, kRule[0].xi, kRule[0].eta);
    for (const auto& q : kRule) lowest = std::min(lowest, det_jacobian(x, cells, c, q.xi, q.eta));
    out(c) = lowest;
  }
  return out;
}

}  // namespace wingcrack
