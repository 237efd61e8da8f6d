#pragma once
// Stress intensity factors from the quarter-point rosette (displacement
// correlation, paper eqs. 32-33), the maximum tangential stress criterion
// (eqs. 9-12), the SIFs of the kinked tip (eqs. 15-16) and the energy release
// rate (eq. 14). SI units: K in Pa m^0.5, mu and E in Pa, h in m, G in J/m^2,
// angles in radians measured from x' (the crack axis ahead of the tip)
// towards y', so a positive KII (sliding of the upper face towards +x')
// kinks the crack to negative angles.
//
// Every function has a scalar form for one tip and a form vectorised over k
// tips (row i of every argument is tip i; all arguments have k rows).
#include <Eigen/Core>

#include "wingcrack/geometry.hpp"

namespace wingcrack {

// (k, 2) global displacement or direction vectors, one row per tip.
using Vectors2 = Points2;
using VectorsRef = Eigen::Ref<const Vectors2>;
using ValuesRef = Eigen::Ref<const Eigen::ArrayXd>;

enum class Plane { strain, stress };

// Kolosov constant: 3 - 4 nu (plane strain), (3 - nu)/(1 + nu) (plane stress).
// Throws std::invalid_argument unless -1 < nu <= 0.5.
double kappa(double nu, Plane plane);

struct ModeSIFs {
  double KI = 0.0;
  double KII = 0.0;
};

struct TipSIFs {
  Eigen::ArrayXd KI;
  Eigen::ArrayXd KII;
};

// Paper eqs. (32)-(33), written with E / (2 (1 + nu)) = mu:
//   K = mu / (3 (1 + kappa)) sqrt(2 pi / h) [8 (q_b - q_d) - (q_c - q_e)],
// q = u.ey for KI, q = u.ex for KII. u_b, u_c: global displacements of the
// quarter-point and corner nodes of the upper face (the +y' side), u_d, u_e
// of the lower face; (ex, ey) the right-handed unit tip frame; h > 0 the
// tip-corner distance. The weights 8 and -1 cancel the r^(3/2) term of the
// Williams expansion; the face differences cancel rigid motions.
// Throws std::invalid_argument for h <= 0, mu <= 0, kappa <= -1 or a frame
// that is not orthonormal and right-handed (to 1e-6).
ModeSIFs displacement_correlation(const Point2& u_b, const Point2& u_c, const Point2& u_d, const Point2& u_e,
                                  const Point2& ex, const Point2& ey, double h, double mu, double kappa);
TipSIFs displacement_correlation(const VectorsRef& u_b, const VectorsRef& u_c, const VectorsRef& u_d,
                                 const VectorsRef& u_e, const VectorsRef& ex, const VectorsRef& ey, const ValuesRef& h,
                                 const ValuesRef& mu, const ValuesRef& kappa);

// MTS kink angle (eq. 11) theta0 = 2 atan((KI - sqrt(KI^2 + 8 KII^2)) / (4 KII)),
// the maximum of sigma_theta (eq. 9), in (-pi, pi). KII = 0 gives 0; that
// includes KI < 0 (a closed crack under pure compression has no tensile
// sigma_theta; K_eq = KI < 0 then reports no growth).
double mts_angle(double KI, double KII);
Eigen::ArrayXd mts_angle(const ValuesRef& KI, const ValuesRef& KII);

// Eq. (10): K_eq = KI cos^3(theta/2) - 1.5 KII cos(theta/2) sin(theta),
// i.e. sigma_theta sqrt(2 pi r) at angle theta.
double equivalent_k(double KI, double KII, double theta);
Eigen::ArrayXd equivalent_k(const ValuesRef& KI, const ValuesRef& KII, const ValuesRef& theta);

// Eq. (14): G = (1 + nu)(1 + kappa) / (4 E) (KI^2 + KII^2), which is
// (1 - nu^2)(KI^2 + KII^2)/E in plane strain and (KI^2 + KII^2)/E in plane
// stress. KI enters squared whatever its sign. Throws for E <= 0.
double energy_release_rate(double KI, double KII, double E, double nu, double kappa);
Eigen::ArrayXd energy_release_rate(const ValuesRef& KI, const ValuesRef& KII, const ValuesRef& E, const ValuesRef& nu,
                                   const ValuesRef& kappa);

}  // namespace wingcrack
