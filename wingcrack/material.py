"""Linear isotropic elasticity in 2D, plane stress or plane strain: the
material constants every layer uses, in one place (numpy only, no DOLFINx)."""
from __future__ import annotations

import numpy as np

# The Kolosov constant, 3 - 4 nu (plane strain), (3 - nu)/(1 + nu) (plane
# stress), is defined once, in the kernels, whose SIF formulas take it.
from wingcrack_kernels import kappa  # noqa: F401


def lame(E: float, nu: float, plane: str) -> tuple[float, float]:
    """In-plane Lame constants (lambda, mu) in Pa.

    Plane stress replaces lambda by 2 mu lambda / (lambda + 2 mu), so that the
    same 2D formula sigma = lambda tr(eps) I + 2 mu eps serves both cases.
    """
    mu = E / (2.0 * (1.0 + nu))
    lam = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
    if plane == "stress":
        lam = 2.0 * mu * lam / (lam + 2.0 * mu)
    return lam, mu


def e_prime(E: float, nu: float, plane: str) -> float:
    """E' in G = K^2 / E' (Pa): E (plane stress), E / (1 - nu^2) (plane strain)."""
    if plane not in ("stress", "strain"):
        raise ValueError(f"plane must be 'strain' or 'stress', got {plane!r}")
    return E if plane == "stress" else E / (1.0 - nu * nu)


def in_plane_strain(sigma: np.ndarray, E: float, nu: float, plane: str) -> np.ndarray:
    """Strain (2x2) of a 2x2 in-plane stress under the same constitutive law."""
    lam, mu = lame(E, nu, plane)
    tr = np.trace(sigma) / (2.0 * lam + 2.0 * mu)
    return (sigma - lam * tr * np.eye(2)) / (2.0 * mu)
