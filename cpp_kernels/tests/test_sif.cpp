// SIF kernels against closed-form fields: the Williams expansion around a
// crack tip (Williams 1957; mode I/II terms as in Anderson, Fracture
// Mechanics, 4th ed., Table 2.2 for n = 1, and the general n-th term of the
// series, checked symbolically for equilibrium and traction-free faces), the
// MTS criterion (Erdogan & Sih 1963; paper eqs. 9-12) and eqs. (10), (14)-(16).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>
#include <utility>

#include "wingcrack/sif.hpp"

using namespace wingcrack;

namespace {

constexpr double pi = 3.14159265358979323846;

// Near-tip K field in the tip frame, polar (r, theta): Anderson Table 2.2.
Point2 williams_k(double KI, double KII, double r, double t, double mu, double kap) {
  const double a = std::sqrt(r / (2 * pi)) / (2 * mu);
  const double c = std::cos(t / 2), s = std::sin(t / 2);
  return {KI * a * c * (kap - 1 + 2 * s * s) + KII * a * s * (kap + 1 + 2 * c * c),
          KI * a * s * (kap + 1 - 2 * c * c) - KII * a * c * (kap - 1 - 2 * s * s)};
}

// n-th term of the Williams series, r^(n/2), mode I coefficient aI and mode
// II coefficient bII (n = 1: aI = KI / sqrt(2 pi), bII = KII / sqrt(2 pi);
// n = 2: T-stress and rigid rotation; n = 3: the r^(3/2) term).
Point2 williams_term(int n, double aI, double bII, double r, double t, double mu, double kap) {
  const double l = 0.5 * n, sg = (n % 2 == 0) ? 1.0 : -1.0, rl = std::pow(r, l) / (2 * mu);
  const double cl = std::cos(l * t), sl = std::sin(l * t), c2 = std::cos((l - 2) * t), s2 = std::sin((l - 2) * t);
  const double ux = aI * rl * (kap * cl - l * c2 + (l + sg) * cl) + bII * rl * (kap * sl - l * s2 + (l - sg) * sl);
  const double uy = aI * rl * (kap * sl + l * s2 - (l + sg) * sl) - bII * rl * (kap * cl + l * c2 - (l - sg) * cl);
  return {ux, uy};
}

struct Rosette {
  Point2 tip, ex, ey;
  double h;
  // Global positions of the rosette's crack-face nodes b, c (upper face,
  // theta = +pi) and d, e (lower face, theta = -pi).
  Point2 at(double r) const { return tip - r * ex; }
};

Rosette rosette(double phi, const Point2& tip, double h) {
  const Point2 ex(std::cos(phi), std::sin(phi));
  return {tip, ex, Point2(-ex.y(), ex.x()), h};
}

// A local displacement field, evaluated at the four nodes and rotated to the
// global frame, plus a rigid motion u0 + omega x (-y, x) of the global point.
template <class Field>
std::array<Point2, 4> sample(const Rosette& ro, Field field, const Point2& u0, double omega) {
  const double r[4] = {ro.h / 4, ro.h, ro.h / 4, ro.h};
  const double t[4] = {pi, pi, -pi, -pi};
  std::array<Point2, 4> u;
  for (int i = 0; i < 4; ++i) {
    const Point2 ul = field(r[i], t[i]);
    const Point2 x = ro.at(r[i]);
    u[i] = ul.x() * ro.ex + ul.y() * ro.ey + u0 + omega * Point2(-x.y(), x.x());
  }
  return u;
}

ModeSIFs correlate(const Rosette& ro, const std::array<Point2, 4>& u, double mu, double kap) {
  return displacement_correlation(u[0], u[1], u[2], u[3], ro.ex, ro.ey, ro.h, mu, kap);
}

// Eqs. (15)-(16), the local SIFs of an infinitesimal kink at angle theta, in
// the paper's form with the half and three-half angles: independent of eq.
// (10), so their agreement at the MTS angle checks mts_angle and equivalent_k.
ModeSIFs kinked_sifs(double KI, double KII, double theta) {
  const double c1 = std::cos(0.5 * theta), c3 = std::cos(1.5 * theta);
  const double s1 = std::sin(0.5 * theta), s3 = std::sin(1.5 * theta);
  return {0.25 * (3.0 * c1 + c3) * KI - 0.75 * (s1 + s3) * KII, 0.25 * (s1 + s3) * KI + 0.25 * (c1 + 3.0 * c3) * KII};
}

double sigma_theta(double KI, double KII, double t) {  // eq. (9) times sqrt(2 pi r)
  const double c = std::cos(t / 2);
  return KI * c * c * c - 1.5 * KII * c * std::sin(t);
}

}  // namespace

TEST(Kappa, PlaneStrainAndStress) {
  EXPECT_DOUBLE_EQ(kappa(0.25, Plane::strain), 2.0);
  EXPECT_DOUBLE_EQ(kappa(0.25, Plane::stress), 2.75 / 1.25);
  EXPECT_THROW(kappa(0.6, Plane::strain), std::invalid_argument);
  EXPECT_THROW(kappa(-1.0, Plane::stress), std::invalid_argument);
}

TEST(Williams, GeneralTermReducesToTheKField) {
  // The series' n = 1 term is the K field: a consistency check of the two
  // independent transcriptions used below (rounding only, 1e-15 of the scale).
  const double mu = 3.0, kap = 1.8, s = std::sqrt(2 * pi);
  for (double t = -pi; t <= pi; t += 0.1) {
    const Point2 a = williams_k(1.3, -0.7, 0.2, t, mu, kap);
    const Point2 b = williams_term(1, 1.3 / s, -0.7 / s, 0.2, t, mu, kap);
    EXPECT_LT((a - b).norm(), 1e-15);
  }
}

// The correlation is exact for the K field plus rigid motion: the error is
// rounding only. The rigid motion is made as large as the crack-face
// displacement (|u| ~ K sqrt(h) / mu), so rounding stays ~1e-15 relative;
// 1e-10 leaves a wide margin without hiding a wrong factor or sign.
TEST(DisplacementCorrelation, ExactOnWilliamsKFieldAnyFrameAndRigidMotion) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  const double E = 30e9;
  const double K0 = 1e6;
  double worst = 0.0;
  const double modes[][2] = {{1, 0}, {0, 1}, {0, -1}, {0.7, -1.3}, {-0.4, 2.0}, {2.5, 0.3}};
  for (const Plane plane : {Plane::strain, Plane::stress})
    for (const double nu : {0.0, 0.25, 0.45})
      for (const auto& m : modes)
        for (int trial = 0; trial < 8; ++trial) {
          const double mu = E / (2 * (1 + nu)), kap = kappa(nu, plane);
          const double KI = K0 * m[0], KII = K0 * m[1];
          const double h = 1e-3 * std::pow(10.0, 2 * (U(rng) + 1));  // 1 mm .. 10 cm
          const Rosette ro = rosette(pi * U(rng), Point2(5 * U(rng), 5 * U(rng)), h);
          const double scale = K0 * std::sqrt(h) / mu;
          const Point2 u0 = scale * Point2(U(rng), U(rng));
          const double omega = scale / 5 * U(rng);
          const auto u = sample(ro, [&](double r, double t) { return williams_k(KI, KII, r, t, mu, kap); }, u0, omega);
          const ModeSIFs k = correlate(ro, u, mu, kap);
          const double err = std::max(std::abs(k.KI - KI), std::abs(k.KII - KII)) / std::hypot(KI, KII);
          worst = std::max(worst, err);
          EXPECT_LT(err, 1e-10) << "KI " << KI << " KII " << KII << " nu " << nu;
        }
  std::printf("[ measured ] Williams K field: max relative error %.2e\n", worst);
}

// The 8 / -1 weights: at r = h/4 the r^(3/2) term is 1/8 of its value at
// r = h, so 8 (h/4)^(3/2) - h^(3/2) = 0. A constant, the T-stress and the
// rigid rotation (the n = 0 and n = 2 terms) are equal on both faces and
// drop out of the face differences. Checked on the terms alone (whose face
// jumps are not small, so the cancellation is not trivially true) and added
// to a K field.
TEST(DisplacementCorrelation, CancelsHigherWilliamsTermsAndRigidMotion) {
  const double mu = 11e9, kap = kappa(0.3, Plane::strain), h = 0.02;
  const Rosette ro = rosette(2.1, Point2(-1.5, 0.4), h);
  const double a = 1e6 / h;  // r^(3/2) coefficients as large as the K field at r = h
  // Returning Point2 (not auto) evaluates the Eigen sum before the
  // temporaries it refers to die.
  const auto extra = [&](double r, double t) -> Point2 {
    return williams_term(3, a, -0.6 * a, r, t, mu, kap) + williams_term(2, 3e5, 2e5, r, t, mu, kap) +
           Point2(1e-4, -2e-4);
  };
  // The n = 3 term alone has a face jump at the quarter point of the order of
  // the crack opening, yet correlates to zero.
  const auto u3 = sample(ro, [&](double r, double t) { return williams_term(3, a, -0.6 * a, r, t, mu, kap); },
                         Point2::Zero(), 0.0);
  const double jump = (u3[0] - u3[2]).norm();
  const auto uk = sample(ro, [&](double r, double t) { return williams_k(1e6, 0, r, t, mu, kap); }, Point2::Zero(), 0.0);
  EXPECT_GT(jump, 0.05 * (uk[0] - uk[2]).norm());
  const ModeSIFs k3 = correlate(ro, u3, mu, kap);
  EXPECT_LT(std::hypot(k3.KI, k3.KII), 1e-10 * 1e6);

  const double KI = 0.8e6, KII = -1.1e6;
  const auto u = sample(ro, [&](double r, double t) -> Point2 { return williams_k(KI, KII, r, t, mu, kap) + extra(r, t); },
                        Point2(3e-5, 1e-5), 2e-6);
  const ModeSIFs k = correlate(ro, u, mu, kap);
  const double err = std::max(std::abs(k.KI - KI), std::abs(k.KII - KII)) / std::hypot(KI, KII);
  std::printf("[ measured ] K field + r^(3/2) + T-stress + rigid: relative error %.2e\n", err);
  EXPECT_LT(err, 1e-10);

  // Without the corner node (the plain quarter-point formula from b - d) the
  // r^(3/2) term is not cancelled: the weights are what removes it.
  const double scale_b = mu / (1 + kap) * std::sqrt(2 * pi / (h / 4));
  const double KI_qp = scale_b * (u[0] - u[2]).dot(ro.ey);
  EXPECT_GT(std::abs(KI_qp - KI), 1e-3 * std::abs(KI));
}

TEST(DisplacementCorrelation, VectorisedMatchesScalarAndValidates) {
  const int k = 3;
  Vectors2 ub(k, 2), uc(k, 2), ud(k, 2), ue(k, 2), ex(k, 2), ey(k, 2);
  Eigen::ArrayXd h(k), mu(k), kap(k);
  for (int i = 0; i < k; ++i) {
    const Rosette ro = rosette(0.5 * i, Point2(i, -i), 0.01 * (i + 1));
    const auto u = sample(ro, [&](double r, double t) { return williams_k(1.0 + i, 0.5 - i, r, t, 1.0, 2.0); },
                          Point2::Zero(), 0.0);
    ub.row(i) = u[0];
    uc.row(i) = u[1];
    ud.row(i) = u[2];
    ue.row(i) = u[3];
    ex.row(i) = ro.ex;
    ey.row(i) = ro.ey;
    h(i) = ro.h;
    mu(i) = 1.0;
    kap(i) = 2.0;
  }
  const TipSIFs s = displacement_correlation(ub, uc, ud, ue, ex, ey, h, mu, kap);
  for (int i = 0; i < k; ++i) {
    EXPECT_NEAR(s.KI(i), 1.0 + i, 1e-12);
    EXPECT_NEAR(s.KII(i), 0.5 - i, 1e-12);
  }
  EXPECT_THROW(displacement_correlation(ub, uc, ud, ue, ex, ey, h.head(2), mu, kap), std::invalid_argument);
  const Point2 z = Point2::Zero(), x(1, 0), y(0, 1);
  EXPECT_THROW(displacement_correlation(z, z, z, z, x, y, 0.0, 1.0, 2.0), std::invalid_argument);
  EXPECT_THROW(displacement_correlation(z, z, z, z, x, -y, 1.0, 1.0, 2.0), std::invalid_argument);  // left-handed
  EXPECT_THROW(displacement_correlation(z, z, z, z, 2 * x, y, 1.0, 1.0, 2.0), std::invalid_argument);
}

TEST(MTS, PureModes) {
  const double pure_ii = -2 * std::atan(1 / std::sqrt(2.0));
  EXPECT_EQ(mts_angle(1.0, 0.0), 0.0);
  EXPECT_EQ(mts_angle(-1.0, 0.0), 0.0);  // documented: closed crack under pure compression
  EXPECT_EQ(mts_angle(0.0, 0.0), 0.0);
  EXPECT_NEAR(mts_angle(0.0, 1.0), pure_ii, 1e-15);
  EXPECT_NEAR(mts_angle(0.0, 1.0) * 180 / pi, -70.5288, 1e-4);
  EXPECT_NEAR(mts_angle(0.0, -3e6), -pure_ii, 1e-15);
  EXPECT_NEAR(mts_angle(0.0, -1.0) * 180 / pi, 70.5288, 1e-4);
}

TEST(MTS, ContinuousAsKIIVanishes) {
  // With KI = 1, tan(theta/2) = -KII + 2 KII^3 + ..., so
  // theta = -2 KII + (14/3) KII^3 + ...: the gap is below 10 KII^3, plus
  // rounding (1e-15 relative), down to subnormal KII without NaN.
  for (double KII = 1e-1; KII > 1e-300; KII *= 1e-3)
    for (const double sign : {1.0, -1.0}) {
      const double theta = mts_angle(1.0, sign * KII);
      ASSERT_TRUE(std::isfinite(theta));
      EXPECT_NEAR(theta, -2 * sign * KII, KII * (10 * KII * KII + 1e-15));
    }
}

TEST(MTS, ScaleInvariantDownToSubnormals) {
  // Found by the hypothesis tests: mts_angle(0, 2.2e-310) was 1.2309594173407779
  // instead of 1.2309594173407747 (hypot and the quotient of subnormals keep
  // few digits). The angle depends on KI / KII only; with power-of-two scales
  // the products below are exact, so the angles must agree exactly.
  for (const int e : {-1060, -1035, -1000, -500, 0, 500, 1000})
    for (const auto& [KI, KII] : {std::pair{0.0, 1.0}, {0.0, -3.0}, {1.0, 1.0}, {-5.0, 2.0}, {7.0, -1.0}, {-1.0, 9.0}}) {
      const double s = std::ldexp(1.0, e);
      EXPECT_EQ(mts_angle(s * KI, s * KII), mts_angle(KI, KII)) << "scale 2^" << e << ", KI " << KI << ", KII " << KII;
    }
}

TEST(MTS, MaximumOfHoopStressEq9) {
  // Random mixed modes on the unit circle, leaving out KI < -0.95 |K|: near
  // pure compression sigma_theta <= 0 everywhere and flattens, so the second
  // derivative tends to 0 and its sign is not a meaningful check there.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> U(-pi, pi);
  double worst_d1 = 0.0, worst_d2 = -INFINITY;
  int n = 0;
  while (n < 2000) {
    const double phi = U(rng), KI = std::cos(phi), KII = std::sin(phi);
    if (KI < -0.95) continue;
    ++n;
    const double t = mts_angle(KI, KII);
    ASSERT_GT(t, -pi);
    ASSERT_LT(t, pi);
    const auto f = [&](double a) { return sigma_theta(KI, KII, a); };
    // Central differences: d = 1e-5 gives truncation ~1e-10 and rounding
    // ~1e-11 for the slope, d = 1e-3 gives ~1e-7 and ~1e-9 for the curvature.
    const double d1 = (f(t + 1e-5) - f(t - 1e-5)) / 2e-5;
    const double d2 = (f(t + 1e-3) - 2 * f(t) + f(t - 1e-3)) / 1e-6;
    worst_d1 = std::max(worst_d1, std::abs(d1));
    worst_d2 = std::max(worst_d2, d2);
    EXPECT_LT(std::abs(d1), 1e-8);
    EXPECT_LT(d2, -1e-3);
    // And it is the global maximum over the half-plane of angles.
    for (double a = -pi; a <= pi; a += 1e-3) EXPECT_LE(f(a), f(t) + 1e-12);
    // The paper's sufficient condition, eq. (12).
    EXPECT_LT(KII * (std::sin(t / 2) + 9 * std::sin(1.5 * t)), KI * (std::cos(t / 2) + 3 * std::cos(1.5 * t)));
  }
  std::printf("[ measured ] MTS: max |dsigma/dtheta| %.2e, max d2sigma/dtheta2 %.3f (|K| = 1)\n", worst_d1, worst_d2);
}

TEST(EquivalentK, PureModesAndKinkedSIFs) {
  EXPECT_DOUBLE_EQ(equivalent_k(2.5e6, 0.0, mts_angle(2.5e6, 0.0)), 2.5e6);
  for (const double KII : {1.0, -1.0, 4e6})
    EXPECT_NEAR(equivalent_k(0.0, KII, mts_angle(0.0, KII)), 2 / std::sqrt(3.0) * std::abs(KII),
                1e-14 * std::abs(KII));
  // At the MTS angle the kinked tip is in pure mode I: kII = 0 and kI = K_eq
  // up to rounding of O(1) trig terms, 1e-12 |K|.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  double worst = 0.0;
  for (int i = 0; i < 1000; ++i) {
    const double KI = 1e6 * U(rng), KII = 1e6 * U(rng), K = std::hypot(KI, KII);
    const double t = mts_angle(KI, KII);
    const ModeSIFs k = kinked_sifs(KI, KII, t);
    const double err = std::max(std::abs(k.KII), std::abs(k.KI - equivalent_k(KI, KII, t))) / K;
    worst = std::max(worst, err);
    EXPECT_LT(err, 1e-12);
  }
  std::printf("[ measured ] kinked_sifs at MTS: max |kII|, |kI - K_eq| / |K| = %.2e\n", worst);
}

TEST(EnergyReleaseRate, PlaneStrainAndStress) {
  const double E = 20e9, nu = 0.27, KI = 1.2e6, KII = -0.7e6;
  const double strain = energy_release_rate(KI, KII, E, nu, kappa(nu, Plane::strain));
  const double stress = energy_release_rate(KI, KII, E, nu, kappa(nu, Plane::stress));
  EXPECT_NEAR(strain, (1 - nu * nu) * (KI * KI + KII * KII) / E, 1e-14 * strain);
  EXPECT_NEAR(stress, (KI * KI + KII * KII) / E, 1e-14 * stress);
  EXPECT_THROW(energy_release_rate(1, 1, 0.0, nu, 2.0), std::invalid_argument);
}

TEST(Vectorised, AnglesAndEnergies) {
  Eigen::ArrayXd KI(3), KII(3);
  KI << 1.0, 0.0, -0.3;
  KII << 0.0, 1.0, 0.8;
  const Eigen::ArrayXd t = mts_angle(KI, KII);
  const Eigen::ArrayXd keq = equivalent_k(KI, KII, t);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(t(i), mts_angle(KI(i), KII(i)));
    EXPECT_EQ(keq(i), equivalent_k(KI(i), KII(i), t(i)));
  }
  EXPECT_THROW(mts_angle(KI, KII.head(2)), std::invalid_argument);
}
