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
