"""Do the step's two SIF methods agree? Displacement correlation (the
paper's: four nodes next to the tip) and the interaction integral (the
reference: it integrates the whole field around the tip) are compared at
every tip; a disagreement worth telling is a warning of the step
(sif_warnings) and one line of the whole result (result_warnings)."""
from __future__ import annotations

import numpy as np

#: the two SIF methods disagree at a tip when KI or KII differ by more than
#: this fraction of the interaction integral's K = sqrt(KI_M^2 + KII_M^2)
#: of the tip, and by more than this fraction of SIF_FLOOR * the step's K
#: scale (sif_scale: the larger of KIc and the step's largest K)
SIF_AGREEMENT = 0.01
#: Below SIF_FLOOR * the step's K scale a tip's own K is no measure of the
#: disagreement. Both methods' errors are absolute, fractions of the field's
#: K scale (the verification states them so: on the Griffith crack DC 0.3 %
#: and M 0.04 % of s sqrt(pi a); on a closed crack |KI| < 5e-3 of it), so at
#: a closed or shielded tip whose K is round-off or a small fraction of the
#: scale they differ by "100 % of K" while each is as accurate as anywhere.
#: Such a tip is far from growth: K_eq <= 1.3 K (the MTS criterion's
#: largest ratio, at KII/KI = -sqrt(3)) < 0.65 of the scale, KIc where the
#: step is critical; it would take a disagreement of 0.35 KIc, 70 times the
#: floor of 0.5 % of the scale, to change that, and that still warns. At a
#: tip above the floor the rule is 1 % of its own K.
SIF_FLOOR = 0.5


def sif_scale(tips, KIc=None) -> float:
    """The K scale of a step's tips (Pa m^0.5): the larger of KIc (None:
    the case has none) and the largest interaction-integral K =
    sqrt(KI_M^2 + KII_M^2) of the tips that have one."""
    ks = [float(np.hypot(t.KI_M, t.KII_M)) for t in tips if t.KI_M is not None and t.KII_M is not None]
    return max(ks + [float(KIc or 0.0)])


def sif_warnings(tips, KIc=None) -> list:
    """One line for each of a step's `tips` where displacement correlation
    (KI, KII) and the interaction integral (KI_M, KII_M, the reference: it
    integrates the whole field around the tip, where correlation reads four
    nodes next to it) differ by more than SIF_AGREEMENT of the tip's K =
    sqrt(KI_M^2 + KII_M^2) and of SIF_FLOOR * sif_scale(tips, KIc): the
    disagreement at a tip whose K is far below the K that drives growth
    (KIc, the case's; None: the step's largest K alone) is no news."""
    out = []
    floor = SIF_FLOOR * sif_scale(tips, KIc)
    for t in tips:
        if t.KI_M is None or t.KII_M is None:
            continue
        k = float(np.hypot(t.KI_M, t.KII_M))
        off = max(abs(t.KI - t.KI_M), abs(t.KII - t.KII_M))
        if k > 0 and off > SIF_AGREEMENT * max(k, floor):
            out.append(f"fracture {t.fracture} end {t.end}: displacement correlation KI {t.KI:.6g}, KII {t.KII:.6g} "
                       f"and the interaction integral KI_M {t.KI_M:.6g}, KII_M {t.KII_M:.6g} Pa m^0.5 differ by "
                       f"{100 * off / k:.3g} % of K")
    return out


def result_warnings(steps: list, method: str = "correlation") -> list:
    """The warnings of a whole result from its steps' own (one line, however
    many steps and tips)."""
    flagged = [(s.step, w) for s in steps for w in s.warnings]   # a step's warnings are sif_warnings
    if not flagged:
        return []
    steps_hit = sorted({k for k, _ in flagged})
    first_step, first = flagged[0]
    where = f"step {first_step}" if len(steps_hit) == 1 else f"{len(steps_hit)} steps (first: step {first_step})"
    driver = ("growth is driven by displacement correlation (propagation.sif = \"interaction\" uses the other)"
              if method == "correlation" else "growth is driven by the interaction integral")
    return [f"the two SIF methods differ by more than {100 * SIF_AGREEMENT:g} % of K (and "
            f"{100 * SIF_AGREEMENT * SIF_FLOOR:g} % of the larger of KIc and the step's largest K) at {len(flagged)} "
            f"tip(s) in {where}: {first}; {driver}; see the steps' warnings in summary.json"]
