"""L_min, the shortest advance of a kinked tip (paper section 3.2), and the
rule it sets on Lmax (`propagation.length`). The growth law applies L_min to
each tip; the case refuses an Lmax under it. Both read it here, so the case
needs nothing of the propagation loop."""
from __future__ import annotations

#: L_min, the shortest advance of a kinked tip, in rosette radii (mesh.tip_size)
L_MIN = 0.4
#: relative round-off allowed below L_min (0.4 * 0.05 is 0.020000000000000004)
L_MIN_RTOL = 1e-9


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
