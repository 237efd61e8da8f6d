// Type conversion only: numpy arrays <-> the SIF kernels.
//
// Every per-tip argument is either one value per tip, (k,) or (k, 2), or a
// single value, a scalar or (2,), shared by all k tips. The results are (k,)
// arrays, or Python floats when every argument was a single value. Shapes are
// checked here so that a wrong array is a ValueError naming the argument.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <initializer_list>
#include <string>

#include "wingcrack/sif.hpp"

namespace py = pybind11;
using namespace wingcrack;

namespace {

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

std::string shape_of(const Array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

struct PerTip {
  const char* name;
  bool single;         // one value for every tip
  Eigen::Index rows;   // number of tips it carries (1 if single)
};

struct Values {
  PerTip info;
  Eigen::ArrayXd v;
  Eigen::ArrayXd for_tips(Eigen::Index k) const { return info.single ? Eigen::ArrayXd::Constant(k, v(0)) : v; }
};

struct Vectors {
  PerTip info;
  Vectors2 v;
  Vectors2 for_tips(Eigen::Index k) const { return info.single ? Vectors2(v.replicate(k, 1)) : v; }
};

Values to_values(const Array& a, const char* name) {
  if (a.ndim() == 0) return {{name, true, 1}, Eigen::ArrayXd::Constant(1, a.data()[0])};
  if (a.ndim() == 1) return {{name, false, a.shape(0)}, Eigen::Map<const Eigen::ArrayXd>(a.data(), a.shape(0))};
  throw py::value_error(std::string(name) + " must be a scalar or have shape (k,), got shape " + shape_of(a));
}

Vectors to_vectors(const Array& a, const char* name) {
  if (a.ndim() == 1 && a.shape(0) == 2) return {{name, true, 1}, Eigen::Map<const Vectors2>(a.data(), 1, 2)};
  if (a.ndim() == 2 && a.shape(1) == 2)
    return {{name, false, a.shape(0)}, Eigen::Map<const Vectors2>(a.data(), a.shape(0), 2)};
  throw py::value_error(std::string(name) + " must have shape (k, 2) or (2,), got shape " + shape_of(a));
}

struct Tips {
  Eigen::Index k;
  bool single;  // every argument was a single value: return floats
};

// k from the arguments that carry one value per tip; they must agree.
Tips count_tips(std::initializer_list<PerTip> args) {
  const PerTip* first = nullptr;
  for (const PerTip& a : args) {
    if (a.single) continue;
    if (!first) {
      first = &a;
    } else if (a.rows != first->rows) {
      throw py::value_error(std::string(a.name) + " has " + std::to_string(a.rows) + " tips but " + first->name +
                            " has " + std::to_string(first->rows) +
                            ": per-tip arguments need the same length k (or a single shared value)");
    }
  }
  return first ? Tips{first->rows, false} : Tips{1, true};
}

py::object result(const Eigen::ArrayXd& a, const Tips& tips) {
  return tips.single ? py::object(py::float_(a(0))) : py::object(py::cast(a));
}

Plane to_plane(const std::string& plane) {
  if (plane == "strain") return Plane::strain;
  if (plane == "stress") return Plane::stress;
  throw py::value_error("plane must be 'strain' or 'stress', got '" + plane + "'");
}

}  // namespace

void bind_sif(py::module_& m) {
  m.def(
      "kappa", [](double nu, const std::string& plane) { return kappa(nu, to_plane(plane)); }, py::arg("nu"),
      py::arg("plane"),
      "Kolosov constant: 3 - 4 nu (plane='strain'), (3 - nu)/(1 + nu) (plane='stress'). -1 < nu <= 0.5.");

  m.def(
      "displacement_correlation",
      [](const Array& u_b, const Array& u_c, const Array& u_d, const Array& u_e, const Array& ex, const Array& ey,
         const Array& h, const Array& mu, const Array& kappa) {
        const Vectors vb = to_vectors(u_b, "u_b"), vc = to_vectors(u_c, "u_c"), vd = to_vectors(u_d, "u_d"),
                      ve = to_vectors(u_e, "u_e"), fx = to_vectors(ex, "ex"), fy = to_vectors(ey, "ey");
        const Values vh = to_values(h, "h"), vmu = to_values(mu, "mu"), vk = to_values(kappa, "kappa");
        const Tips tips =
            count_tips({vb.info, vc.info, vd.info, ve.info, fx.info, fy.info, vh.info, vmu.info, vk.info});
        const Eigen::Index k = tips.k;
        const TipSIFs s = displacement_correlation(vb.for_tips(k), vc.for_tips(k), vd.for_tips(k), ve.for_tips(k),
                                                   fx.for_tips(k), fy.for_tips(k), vh.for_tips(k), vmu.for_tips(k),
                                                   vk.for_tips(k));
        return py::make_tuple(result(s.KI, tips), result(s.KII, tips));
      },
      py::arg("u_b"), py::arg("u_c"), py::arg("u_d"), py::arg("u_e"), py::arg("ex"), py::arg("ey"), py::arg("h"),
      py::arg("mu"), py::arg("kappa"),
      "SIFs (KI, KII) in Pa m^0.5 by quarter-point displacement correlation (paper eqs. 32-33):\n"
      "K = mu / (3 (1 + kappa)) sqrt(2 pi / h) [8 (q_b - q_d) - (q_c - q_e)], q = u.ey for KI, u.ex for KII.\n\n"
      "u_b, u_c: global (x, y) displacements in m of the quarter-point and corner nodes of the upper face\n"
      "(the +ey side), u_d, u_e of the lower face, each (k, 2); ex, ey (k, 2) the right-handed unit tip\n"
      "frame (ex ahead of the tip); h (k,) tip-corner distance in m; mu shear modulus in Pa; kappa the\n"
      "Kolosov constant. Any argument may be a single value shared by all tips. Returns two (k,) arrays,\n"
      "or two floats when every argument is a single value.");

  m.def(
      "mts_angle",
      [](const Array& KI, const Array& KII) {
        const Values a = to_values(KI, "KI"), b = to_values(KII, "KII");
        const Tips tips = count_tips({a.info, b.info});
        return result(mts_angle(a.for_tips(tips.k), b.for_tips(tips.k)), tips);
      },
      py::arg("KI"), py::arg("KII"),
      "MTS kink angle in rad, in (-pi, pi), from ex towards ey (paper eq. 11):\n"
      "2 atan((KI - sqrt(KI^2 + 8 KII^2)) / (4 KII)); 0 when KII == 0 (also for KI < 0: closed crack,\n"
      "K_eq = KI < 0). Positive KII gives a negative angle (-70.53 deg for pure mode II).\n"
      "Scalars or (k,) arrays in; float or (k,) out.");

  m.def(
      "equivalent_k",
      [](const Array& KI, const Array& KII, const Array& theta) {
        const Values a = to_values(KI, "KI"), b = to_values(KII, "KII"), t = to_values(theta, "theta");
        const Tips tips = count_tips({a.info, b.info, t.info});
        const Eigen::Index k = tips.k;
        return result(equivalent_k(a.for_tips(k), b.for_tips(k), t.for_tips(k)), tips);
      },
      py::arg("KI"), py::arg("KII"), py::arg("theta"),
      "K_eq = KI cos^3(theta/2) - 1.5 KII cos(theta/2) sin(theta) (paper eq. 10), in Pa m^0.5.");

  m.def(
      "energy_release_rate",
      [](const Array& KI, const Array& KII, const Array& E, const Array& nu, const Array& kappa) {
        const Values a = to_values(KI, "KI"), b = to_values(KII, "KII"), e = to_values(E, "E"),
                     n = to_values(nu, "nu"), kp = to_values(kappa, "kappa");
        const Tips tips = count_tips({a.info, b.info, e.info, n.info, kp.info});
        const Eigen::Index k = tips.k;
        return result(energy_release_rate(a.for_tips(k), b.for_tips(k), e.for_tips(k), n.for_tips(k), kp.for_tips(k)),
                      tips);
      },
      py::arg("KI"), py::arg("KII"), py::arg("E"), py::arg("nu"), py::arg("kappa"),
      "G = (1 + nu)(1 + kappa) / (4 E) (KI^2 + KII^2) in J/m^2 (paper eq. 14): (1 - nu^2) K^2 / E in\n"
      "plane strain, K^2 / E in plane stress.");
}
