#include "wingcrack/sif.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <stdexcept>
#include <string>

namespace wingcrack {

namespace {

constexpr double pi = 3.14159265358979323846;

// Loose enough for frames built in float64 from any normalisation, tight
// enough to catch an unnormalised or left-handed frame, which would scale or
// flip the SIFs silently.
constexpr double frame_tol = 1e-6;

void check_frame(const Point2& ex, const Point2& ey) {
  const bool ok = std::abs(ex.norm() - 1.0) <= frame_tol && std::abs(ey.norm() - 1.0) <= frame_tol &&
                  std::abs(ex.dot(ey)) <= frame_tol && std::abs(ex.x() * ey.y() - ex.y() * ey.x() - 1.0) <= frame_tol;
  if (!ok) throw std::invalid_argument("displacement_correlation: (ex, ey) must be a right-handed orthonormal frame");
}

void check_rows(const char* what, Eigen::Index k, std::initializer_list<Eigen::Index> rows) {
  for (const Eigen::Index r : rows)
    if (r != k)
      throw std::invalid_argument(std::string(what) + ": every argument must have one row per tip (" +
                                  std::to_string(k) + "), got " + std::to_string(r));
}

}  // namespace

double kappa(double nu, Plane plane) {
  if (!(nu > -1.0 && nu <= 0.5)) throw std::invalid_argument("kappa: Poisson's ratio must be in (-1, 0.5]");
  return plane == Plane::strain ? 3.0 - 4.0 * nu : (3.0 - nu) / (1.0 + nu);
}

ModeSIFs displacement_correlation(const Point2& u_b, const Point2& u_c, const Point2& u_d, const Point2& u_e,
                                  const Point2& ex, const Point2& ey, double h, double mu, double kappa) {
  if (!(h > 0.0)) throw std::invalid_argument("displacement_correlation: h must be > 0");
  if (!(mu > 0.0)) throw std::invalid_argument("displacement_correlation: mu must be > 0");
  if (!(kappa > -1.0)) throw std::invalid_argument("displacement_correlation: kappa must be > -1");
  check_frame(ex, ey);
  // Jumps of the quarter-point and corner nodes; 8 and -1 are the weights
  // that make sqrt(r) exact and r^(3/2) vanish at r = h/4 and r = h.
  const Point2 jump = 8.0 * (u_b - u_d) - (u_c - u_e);
  const double scale = mu / (3.0 * (1.0 + kappa)) * std::sqrt(2.0 * pi / h);
  return {scale * jump.dot(ey), scale * jump.dot(ex)};
}

TipSIFs displacement_correlation(const VectorsRef& u_b, const VectorsRef& u_c, const VectorsRef& u_d,
                                 const VectorsRef& u_e, const VectorsRef& ex, const VectorsRef& ey, const ValuesRef& h,
                                 const ValuesRef& mu, const ValuesRef& kappa) {
  const Eigen::Index k = u_b.rows();
  check_rows("displacement_correlation", k,
             {u_c.rows(), u_d.rows(), u_e.rows(), ex.rows(), ey.rows(), h.size(), mu.size(), kappa.size()});
  TipSIFs out{Eigen::ArrayXd(k), Eigen::ArrayXd(k)};
  for (Eigen::Index i = 0; i < k; ++i) {
    const ModeSIFs s = displacement_correlation(u_b.row(i).transpose(), u_c.row(i).transpose(), u_d.row(i).transpose(),
                                                u_e.row(i).transpose(), ex.row(i).transpose(), ey.row(i).transpose(),
                                                h(i), mu(i), kappa(i));
    out.KI(i) = s.KI;
    out.KII(i) = s.KII;
  }
  return out;
}

double mts_angle(double KI, double KII) {
  if (KII == 0.0) return 0.0;
  // The angle depends on KI / KII only: scaling both by the larger keeps
  // subnormal SIFs (which hold few digits in hypot and the quotient) and
  // huge ones as accurate as O(1) ones.
  const double big = std::max(std::abs(KI), std::abs(KII));
  KI /= big;
  KII /= big;
  const double root = std::hypot(KI, std::sqrt(8.0) * KII);  // no overflow of the squares
  // For KI > 0 the numerator KI - root cancels as KII -> 0; multiplying by
  // (KI + root) gives the same value without the cancellation, so theta
  // goes continuously to 0. For KI < 0 the original form has no cancellation.
  const double tan_half = KI > 0.0 ? -2.0 * KII / (KI + root) : (KI - root) / (4.0 * KII);
  return 2.0 * std::atan(tan_half);
}

Eigen::ArrayXd mts_angle(const ValuesRef& KI, const ValuesRef& KII) {
  check_rows("mts_angle", KI.size(), {KII.size()});
  Eigen::ArrayXd theta(KI.size());
  for (Eigen::Index i = 0; i < KI.size(); ++i) theta(i) = mts_angle(KI(i), KII(i));
  return theta;
}

double equivalent_k(double KI, double KII, double theta) {
  const double c = std::cos(0.5 * theta);
  return KI * c * c * c - 1.5 * KII * c * std::sin(theta);
}

Eigen::ArrayXd equivalent_k(const ValuesRef& KI, const ValuesRef& KII, const ValuesRef& theta) {
  check_rows("equivalent_k", KI.size(), {KII.size(), theta.size()});
  Eigen::ArrayXd out(KI.size());
  for (Eigen::Index i = 0; i < KI.size(); ++i) out(i) = equivalent_k(KI(i), KII(i), theta(i));
  return out;
}

double energy_release_rate(double KI, double KII, double E, double nu, double kappa) {
  if (!(E > 0.0)) throw std::invalid_argument("energy_release_rate: E must be > 0");
  return (1.0 + nu) * (1.0 + kappa) / (4.0 * E) * (KI * KI + KII * KII);
}

Eigen::ArrayXd energy_release_rate(const ValuesRef& KI, const ValuesRef& KII, const ValuesRef& E, const ValuesRef& nu,
                                   const ValuesRef& kappa) {
  check_rows("energy_release_rate", KI.size(), {KII.size(), E.size(), nu.size(), kappa.size()});
  Eigen::ArrayXd out(KI.size());
  for (Eigen::Index i = 0; i < KI.size(); ++i) out(i) = energy_release_rate(KI(i), KII(i), E(i), nu(i), kappa(i));
  return out;
}

}  // namespace wingcrack
