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

#: kink angles below this (rad) count as "zero" for the L_min exception
STRAIGHT = 1e-3
#: L_min, the shortest advance of a kinked tip, in rosette radii (mesh.tip_size)
L_MIN = 0.4
#: relative round-off allowed below L_min (0.4 * 0.05 is 0.020000000000000004)
L_MIN_RTOL = 1e-9


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


def length_problem(length: float, tip_size: float) -> str | None:
    """Why Lmax = `length` cannot work with rosettes of radius `tip_size`
    (None when it can). That no step is longer than the domain is a limit of
    the case reader's (propagation.length at most L).

    The tip that grows farthest advances by Lmax; with Lmax under L_min
    every kinked tip would advance less than L_min and so never grow, and
    the run would only repeat its first step. Every Lmax >= L_min works: a
    wing's next rosette is then min(tip_size, 0.75 Lmax) >= 0.3 tip_size,
    above the mesher's smallest (0.1 tip_size), and the growth module sends
    a tip that place_tip would join onto its own polyline (an artefact of
    steps under 0.75 tip_size) straight on instead, when the mesher has room
    for it."""
    Lmin = L_MIN * tip_size
    if not length >= Lmin * (1 - L_MIN_RTOL):
        return (f"{length:g} m is under L_min = {L_MIN:g} mesh.tip_size = {Lmin:g} m: a kinked tip never advances "
                f"less than L_min, so no tip could grow; use at least {Lmin:g} m (or a smaller mesh.tip_size)")
    return None
