"""Independent reference values for the verification tests, with sources."""
from __future__ import annotations

import numpy as np
from scipy.special import ellipe, ellipk


def griffith(sigma: float, a: float, beta_deg: float) -> tuple[float, float]:
    """Central crack 2a in an infinite plate, remote uniaxial tension sigma at
    angle beta between the crack line and the load axis (Tada, Paris & Irwin,
    The Stress Analysis of Cracks Handbook, 3rd ed., 2000, with the
    stress resolved on the crack plane): KI = sigma sqrt(pi a) sin^2 beta,
    KII = sigma sqrt(pi a) sin beta cos beta."""
    b = np.radians(beta_deg)
    k = sigma * np.sqrt(np.pi * a)
    return k * np.sin(b) ** 2, k * np.sin(b) * np.cos(b)


def kinked_sifs(KI, KII, theta):
    """(kI, kII) of an infinitesimal kink at angle theta, paper eqs. (15)-(16),
    in the paper's form with the half and three-half angles: independent of
    eq. (10) (equivalent_k), so at the MTS angle kII = 0 and kI = K_eq is a
    real check of mts_angle and equivalent_k."""
    c1, c3 = np.cos(0.5 * theta), np.cos(1.5 * theta)
    s1, s3 = np.sin(0.5 * theta), np.sin(1.5 * theta)
    return (0.25 * (3.0 * c1 + c3) * KI - 0.75 * (s1 + s3) * KII,
            0.25 * (s1 + s3) * KI + 0.25 * (c1 + 3.0 * c3) * KII)


def tada_edge_crack_F(s: float) -> float:
    """Single edge crack of depth a in a strip of width b under remote tension:
    KI = sigma sqrt(pi a) F(a/b), F from Tada, Paris & Irwin (2000), accurate to 0.5% for a/b <= 0.6."""
    return 1.12 - 0.231 * s + 10.55 * s ** 2 - 21.72 * s ** 3 + 30.39 * s ** 4


def atkinson(phi_deg: float, a: float, R: float) -> tuple[float, float]:
    """Normalised SIFs N = K sqrt(pi) R / (f0 sqrt(a)) of the cracked Brazilian
    disc, the two-term series of Atkinson et al. (1982), eq. (40) of the paper."""
    u = np.radians(phi_deg)
    r2 = (a / R) ** 2
    NI = 1 - 4 * np.sin(u) ** 2 + 4 * np.sin(u) ** 2 * (1 - 4 * np.cos(u) ** 2) * r2
    NII = (2 + (8 * np.cos(u) ** 2 - 5) * r2) * np.sin(2 * u)
    return NI, NII


# The paper's Table 2, "Present model" column: phi -> (N_I, N_II).
PAPER_TABLE2 = {
    0: (1.0269, 0.0), 15: (0.7420, 1.0069), 30: (-0.0272, 1.7251), 45: (-1.0417, 1.9601),
    60: (-2.0252, 1.6787), 75: (-2.7469, 0.9580), 90: (-3.0132, 0.0),
}


def collinear_cracks(b: float, c: float) -> tuple[float, float]:
    """Two equal collinear cracks b < |x| < c in an infinite plate under remote
    tension normal to them (unit stress): (K at the inner tips x = +-b, K at
    the outer tips x = +-c). Westergaard function
    Z = (z^2 - p^2) / sqrt((z^2 - b^2)(z^2 - c^2)), p^2 = c^2 E(k')/K(k'),
    k'^2 = 1 - b^2/c^2 (Tada, Paris & Irwin 2000; complete elliptic integrals)."""
    m = 1.0 - (b / c) ** 2
    p2 = c * c * ellipe(m) / ellipk(m)
    k_inner = (p2 - b * b) * np.sqrt(np.pi / (b * (c * c - b * b)))
    k_outer = (c * c - p2) * np.sqrt(np.pi / (c * (c * c - b * b)))
    return k_inner, k_outer


class KGDToughness:
    """The toughness-dominated KGD fracture (plane strain, zero viscosity: one
    pressure along the crack): a straight crack of half-length l under a
    confining stress s0 (compression > 0) fed at the rate Q (m^3/s per m).

    Sneddon's opening of a crack under the net pressure p - s0 in an infinite
    plate, w(x) = 4 (p - s0) / E' sqrt(l^2 - x^2), holds the volume
    2 pi (p - s0) l^2 / E' (Tada, Paris & Irwin, 5.1); with a residual
    aperture w_r along its pre-existing length 2 l0 (the grown part, a fresh
    crack, holds none) the crack holds
        V(p, l) = 2 pi (p - s0)+ l^2 / E' + 2 w_r l0.
    Once growing, KI = (p - s0) sqrt(pi l) = KIc:
        p(l) = s0 + KIc / sqrt(pi l),   V(l) = 2 sqrt(pi) KIc l^1.5 / E' + 2 w_r l0.
    The fluid (counted at the density of p0, rho = rho0 exp(c (p - p0))):
        exp(c (p(l) - p0)) V(l) = V0 + Q t,   V0 = V(p0, l0),
    so the time at which the crack reaches half-length l is explicit,
        t(l) = (exp(c (p(l) - p0)) V(l) - V0) / Q,
    and l(t) its inverse (t(l) increases with l here). Without compressibility
    and residual aperture, l(t) = [E' Q t / (2 sqrt(pi) KIc)]^(2/3) from
    l = 0 (the issue's form)."""

    def __init__(self, Ep, KIc, Q, l0, s0=0.0, c=0.0, p0=0.0, w_r=0.0):
        self.Ep, self.KIc, self.Q, self.l0, self.s0, self.c, self.p0, self.w_r = Ep, KIc, Q, l0, s0, c, p0, w_r

    def pressure(self, l):
        return self.s0 + self.KIc / np.sqrt(np.pi * l)

    def volume(self, p, l):
        return 2 * np.pi * max(p - self.s0, 0.0) * l * l / self.Ep + 2 * self.w_r * self.l0

    def fluid(self, p, l):
        return np.exp(self.c * (p - self.p0)) * self.volume(p, l)

    def time(self, l):
        return (self.fluid(self.pressure(l), l) - self.fluid(self.p0, self.l0)) / self.Q

    def length(self, t):
        from scipy.optimize import brentq

        lo = 0.5 * self.l0   # a discrete crack at l0 may reach KIc a little before t(l0)
        hi = 2 * self.l0
        while self.time(hi) < t:
            hi *= 2
        return brentq(lambda l: self.time(l) - t, lo, hi, xtol=1e-15 * hi, rtol=1e-15)




def m_vertex_similarity(N: int, grading: float = 5.0, gauss: int = 12):
    """The viscosity-dominated KGD's similarity solution (zero toughness,
    zero lag, a Newtonian fluid; Adachi & Detournay 2002), solved here on N
    elements: (gamma, omega(0), pi(0)).

    With l(t) the half-length, w = (mu'/(E' t))^(1/3) l omega(xi) and
    p - s0 = E' (mu'/(E' t))^(1/3) pi(xi), xi = x / l, the problem has no
    parameter left:
        pi(xi) = 1/(4 pi) PV int_-1^1 omega'(s) / (xi - s) ds      (elasticity)
        omega^3 pi' = -(int_xi^1 omega ds + 2/3 xi omega)           (lubrication and the
                                                                     fluid's balance of the
                                                                     self-similar growth)
    and the pumped volume Q t = 2 l^2 (mu'/(E' t))^(1/3) int_0^1 omega gives
    l = gamma (E' Q^3 t^4 / mu')^(1/6), gamma = (2 int_0^1 omega)^(-1/2).
    omega piecewise linear on nodes graded towards the tip (1 - (1 - j/N)^grading),
    flat on the first element (omega'(0) = 0), 0 at the tip; pi of the
    elasticity exact for it (logarithms), pi of the lubrication integrated
    from pi(0) (Gauss); the two equal at the elements' midpoints, a Newton
    (scipy's hybr) on the nodal omega and pi(0)."""
    from scipy.optimize import root

    xi = 1 - (1 - np.arange(N + 1) / N) ** grading
    a, b, h = xi[:-1], xi[1:], np.diff(xi)
    mid = 0.5 * (a + b)
    g, gw = np.polynomial.legendre.leggauss(gauss)
    g = (g + 1) / 2
    x = mid[:, None]
    # pi at the midpoints per unit slope of each element and of its mirror image (omega is even)
    kernel = (np.log(np.abs((x - a) / (x - b))) - np.log(np.abs((x + b) / (x + a)))) / (4 * np.pi)

    def fields(u):
        om = np.r_[u[:-1], 0.0]
        tail = np.r_[np.cumsum((0.5 * (om[:-1] + om[1:]) * h)[::-1])[::-1], 0.0]   # int_xi^1 omega at the nodes

        def rate(e, s):   # pi' = -(int_s^1 omega + 2/3 s omega) / omega^3 in element e
            w = om[e] + (s - xi[e]) / h[e] * (om[e + 1] - om[e])
            return -(tail[e + 1] + 0.5 * (w + om[e + 1]) * (xi[e + 1] - s) + 2 / 3 * s * w) / w ** 3

        at_nodes = np.r_[0.0, np.cumsum([h[e] * gw @ rate(e, a[e] + g * h[e]) / 2 for e in range(N - 1)])]
        half = np.array([h[e] / 2 * gw @ rate(e, a[e] + g * h[e] / 2) / 2 for e in range(N)])
        pi_lub = u[-1] + at_nodes + half
        pi_el = kernel @ (np.diff(om) / h)
        return om, tail, pi_el, pi_lub

    def residual(u):
        om, _, pi_el, pi_lub = fields(u)
        return np.r_[pi_el - pi_lub, om[0] - om[1]]

    start = np.r_[1.4 * (1 - xi[:-1] ** 2) ** (2 / 3), 0.5]
    sol = root(residual, start, method="hybr", options={"xtol": 1e-13})
    if not sol.success:
        raise RuntimeError(f"the M-vertex similarity solution did not converge on {N} elements: {sol.message}")
    om, tail, _, _ = fields(sol.x)
    return (2 * tail[0]) ** -0.5, om[0], sol.x[-1]


def m_vertex_constants(levels=(40, 80, 160)):
    """(gamma, Omega0, Pi0) of the M-vertex KGD, Richardson-extrapolated
    from three meshes (m_vertex_similarity; each halving of the elements
    halves the error, about: first order): l = gamma (E' Q^3 t^4 / mu')^(1/6),
    w0 = Omega0 (mu' Q^3 / E')^(1/6) t^(1/3), p0 - s0 = Pi0 (mu' E'^2 / t)^(1/3).
    gamma = 0.6151 (Adachi & Detournay: 0.6152), Omega0 = 1.1251,
    Pi0 = 0.5450; the next finer triple (80, 160, 320 elements) moves them
    by 4e-4, 5e-4, 3e-4 of themselves."""
    runs = np.array([m_vertex_similarity(n) for n in levels])
    d1, d2 = runs[1] - runs[0], runs[2] - runs[1]
    r = d2 / d1
    best = runs[2] + d2 * r / (1 - r)
    gamma, om0, pi0 = best
    return gamma, gamma * om0, pi0


class KGDViscosity:
    """The viscosity-dominated KGD fracture (plane strain, zero toughness, an
    incompressible Newtonian fluid of viscosity eta fed at the rate Q, m^3/s
    per metre, into the whole fracture; zero fluid lag): the M-vertex of
    Adachi & Detournay (2002, Int. J. Numer. Anal. Meth. Geomech. 26:579),
        l(t) = 0.6152 (E' Q^3 / mu')^(1/6) t^(2/3)    (the half-length; mu' = 12 eta),
    the opening w0 and the net pressure p0 at the injection point from the
    similarity solution solved here (m_vertex_constants: Omega0, Pi0; its
    gamma is the published 0.6152 to 1e-4). GEOS's validation quotes the same
    two to two digits: w0^2 = 2.1 (mu' Q / E')^(1/2) l (here 2.058),
    w0 p0 = 0.62 (mu' Q E')^(1/2) (here 0.613)."""

    GAMMA = 0.6152

    def __init__(self, Ep, eta, Q):
        self.Ep, self.mup, self.Q = Ep, 12.0 * eta, Q
        self.gamma, self.Omega0, self.Pi0 = m_vertex_constants()

    def length(self, t):
        return self.GAMMA * (self.Ep * self.Q ** 3 / self.mup) ** (1 / 6) * t ** (2 / 3)

    def opening(self, t):
        return self.Omega0 * (self.mup * self.Q ** 3 / self.Ep) ** (1 / 6) * t ** (1 / 3)

    def net_pressure(self, t):
        return self.Pi0 * (self.mup * self.Ep ** 2 / t) ** (1 / 3)

def diffusion_step(x, t, alpha, dp):
    """The pressure rise along an infinite conduit whose pressure is raised
    by dp at x = 0 at t = 0: dp erfc(|x| / sqrt(4 alpha t)), alpha the
    hydraulic diffusivity (Carslaw & Jaeger, Conduction of Heat in Solids,
    2nd ed., 1959, sec. 2.4; for a fault of fixed hydraulic aperture w_h,
    alpha = w_h^2 / (12 eta c_f))."""
    from scipy.special import erfc

    return dp * erfc(np.abs(np.asarray(x, float)) / np.sqrt(4.0 * alpha * t))


def diffusion_flux(t, alpha, conductivity, q):
    """The pressure rise at the end x = 0 of a half-infinite conduit fed the
    volume flux q (m^2/s) from t = 0: (2 q / k) sqrt(alpha t / pi), k the
    conductivity w_h^3 / (12 eta) (Carslaw & Jaeger, sec. 2.9: a constant
    flux into a semi-infinite solid)."""
    return 2.0 * q / conductivity * np.sqrt(alpha * np.asarray(t, float) / np.pi)


def fluid_driven_slip_front(T: float) -> float:
    """lambda of the slip front a(t) = lambda sqrt(4 alpha t) of a planar
    Coulomb fault (friction f, effective normal stress sigma', initial
    shear tau0 < f sigma') whose pore pressure is raised by dp at x = 0 at
    t = 0 and diffuses as dp erfc(|x| / sqrt(4 alpha t)) (Bhattacharya &
    Viesca, Science 364:464, 2019; Viesca, JFM 2021, the plane-strain case):
    the root of T = (f sigma' - tau0) / (f dp) = (2/pi) int_0^1
    erfc(lambda s) / sqrt(1 - s^2) ds. The condition is that of a shear
    crack |x| < a loaded by the stress drop tau0 - f (sigma' - p(x)), whose
    stress intensity vanishes at the front (the friction bound is reached
    there without a singularity): int_0^a drop(x) / sqrt(a^2 - x^2) dx = 0.
    Integrated in s = sin(theta), smooth on [0, pi/2]."""
    from scipy.integrate import quad
    from scipy.optimize import brentq
    from scipy.special import erfc

    def t_of(lam):
        return 2.0 / np.pi * quad(lambda th: erfc(lam * np.sin(th)), 0.0, np.pi / 2, epsabs=1e-14, epsrel=1e-13)[0]

    return brentq(lambda lam: t_of(lam) - T, 1e-10, 1e3, xtol=1e-14, rtol=1e-13)
