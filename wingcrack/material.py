"""Linear isotropic elasticity in 2D, plane stress or plane strain: the
material constants every layer uses, in one place (numpy only, no DOLFINx)."""
from __future__ import annotations

import numpy as np

# The Kolosov constant, 3 - 4 nu (plane strain), (3 - nu)/(1 + nu) (plane
# stress), is defined once, in the kernels, whose SIF formulas take it.
from wingcrack_kernels import kappa  # noqa: F401


def lame(E: float, nu: float, plane: str) -> tuple[float, float]:
    """In-plane Lame constants (lambda, mu) in Pa: mu the shear modulus.

    Plane stress replaces lambda by 2 mu lambda / (lambda + 2 mu), so that the
    same 2D formula sigma = lambda tr(eps) I + 2 mu eps serves both cases.
    """
    lame_mu = E / (2.0 * (1.0 + nu))
    lame_lambda = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
    if plane == "stress":
        lame_lambda = 2.0 * lame_mu * lame_lambda / (lame_lambda + 2.0 * lame_mu)
    return lame_lambda, lame_mu


def e_prime(E: float, nu: float, plane: str) -> float:
    """E' in G = K^2 / E' (Pa): E (plane stress), E / (1 - nu^2) (plane strain)."""
    if plane not in ("stress", "strain"):
        raise ValueError(f"plane must be 'strain' or 'stress', got {plane!r}")
    return E if plane == "stress" else E / (1.0 - nu * nu)


def in_plane_strain(sigma: np.ndarray, E: float, nu: float, plane: str) -> np.ndarray:
    """Strain (2x2) of a 2x2 in-plane stress under the same constitutive law."""
    lame_lambda, lame_mu = lame(E, nu, plane)
    tr = np.trace(sigma) / (2.0 * lame_lambda + 2.0 * lame_mu)
    return (sigma - lame_lambda * tr * np.eye(2)) / (2.0 * lame_mu)
