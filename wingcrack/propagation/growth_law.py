"""How far each tip advances in one step (paper eq. 13 and section 3.2).

L_i = Lmax (G_i / max G)^alpha over the tips that grow (K_eq >= KIc), with
G_i the energy release rate in the kink direction: at the MTS angle the
kinked tip is in pure mode I with k_I = K_eq (eqs. 15-16), so G_i = K_eq^2/E'.
A tip whose L_i is below L_min = 0.4 h (h the rosette radius) does not grow,
except that a tip that would grow straight on (zero kink angle) still moves
its tip node forward by L_i.
"""
from __future__ import annotations

import numpy as np

from wingcrack.shortest_advance import L_MIN_RTOL

#: kink angles below this (rad) count as "zero" for the L_min exception
STRAIGHT = 1e-3


def advances(G, Lmax: float, alpha: float, Lmin: float, theta=None) -> np.ndarray:
    """Advance of each tip (0 for a tip that does not grow).

    G: energy release rates of the tips that reached KIc (others: pass 0 or
    a negative number). theta: their kink angles (for the L_min exception).
    """
    G = np.asarray(G, float)
    L = np.zeros_like(G)
    grow = G > 0
    if not grow.any():
        return L
    L[grow] = Lmax * (G[grow] / G[grow].max()) ** alpha
    short = grow & (L < Lmin * (1 - L_MIN_RTOL))
    if theta is not None:
        short &= np.abs(np.asarray(theta, float)) > STRAIGHT
    L[short] = 0.0
    return L
