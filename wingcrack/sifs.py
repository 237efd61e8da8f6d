"""The SIFs of a solved step (a step.Discretisation at its current
solution): both methods at every tip (at_tips, the step's record), or
those of the method that drives growth alone (driving, what the
critical-load search asks at every trial: displacement correlation's four
nodal displacements a tip are cheap; correlation, that method alone).

propagation.sif says which method drives growth: "correlation" (the
paper's) or "interaction" (the interaction integral, where it has room;
correlation's elsewhere). theta, K_eq and G of a tip are the driving
method's.
"""
from __future__ import annotations

from dataclasses import replace

import numpy as np

import wingcrack_kernels as K
from .errors import ComputationError


def method(case) -> str:
    """"correlation" or "interaction": which SIFs drive growth."""
    return case.propagation.sif


def at_tips(case, disc, polylines) -> list:
    """TipSIF of every tip of the mesh for the current solution: both
    methods, and theta, K_eq, G of the method that drives growth.
    polylines: the fractures' (n, 2) points."""
    from .tip_sifs import tip_sifs   # DOLFINx: loaded by the first step (startup.py), not by the step's import

    m = case.material
    tips = tip_sifs(disc.problem, disc.cm, [np.asarray(p, float) for p in polylines], case.domain, m.E, m.nu,
                    m.plane, case.stress.tensor(), face_forces=face_forces(disc))
    for t in tips:
        require_finite(f"a SIF at fracture {t.fracture} end {t.end}",
                       [v for v in (t.KI, t.KII, t.KI_M, t.KII_M, t.G, t.K_eq) if v is not None])
    return driven(tips, case)


def driving(case, disc, polylines):
    """(KI, KII) of every tip by the method that drives growth: displacement
    correlation alone (cheap), or the interaction integral (where it has
    no room, correlation)."""
    if method(case) == "correlation":
        return correlation(case, disc)
    tips = at_tips(case, disc, polylines)
    return (np.array([t.KI if t.KI_M is None else t.KI_M for t in tips], float),
            np.array([t.KII if t.KII_M is None else t.KII_M for t in tips], float))


def correlation(case, disc):
    """(KI, KII) of every tip by displacement correlation alone: four nodal
    displacements a tip."""
    from .tip_sifs import correlation_sifs   # DOLFINx: as in at_tips

    m = case.material
    return correlation_sifs(disc.problem, disc.cm, m.E, m.nu, m.plane)


def face_forces(disc):
    """(n_nodes, 2) the forces on the face nodes at the current solution,
    contact and fluid pressure (the interaction integral's crack-face
    term), or None when the faces carry none."""
    out = None
    contact, problem = disc.contact, disc.problem
    if contact.result is not None:
        out = contact.nodal_forces(len(disc.cm.x))
    p = problem.loads.face_forces_at(problem.load_factor_solved)
    if p is not None:
        out = p if out is None else out + p
    return out


def driven(tips: list, case) -> list:
    """`tips` (TipSIF) with theta, K_eq and G of the SIFs that drive growth:
    unchanged for displacement correlation; from KI_M, KII_M for the
    interaction integral, where it had room (else correlation's stay)."""
    if method(case) == "correlation" or not tips:
        return tips
    m = case.material
    kap = K.kappa(m.nu, m.plane)
    out = []
    for t in tips:
        if t.KI_M is None:
            out.append(t)
            continue
        KI, KII = np.array([t.KI_M], float), np.array([t.KII_M], float)
        theta = np.atleast_1d(K.mts_angle(KI, KII))
        out.append(replace(t, theta=float(theta[0]), K_eq=float(np.atleast_1d(K.equivalent_k(KI, KII, theta))[0]),
                           G=float(np.atleast_1d(K.energy_release_rate(KI, KII, m.E, m.nu, kap))[0])))
    return out


def require_finite(what: str, values) -> None:
    """ComputationError when a value of the solution is NaN or inf (a case
    whose magnitudes floating point cannot hold): said at once, instead of
    growth on NaN or a summary that cannot be written."""
    bad = [v for v in np.atleast_1d(np.asarray(values, float)) if not np.isfinite(v)]
    if bad:
        raise ComputationError(f"the solution is not finite ({what} is {bad[0]:g}): the magnitudes of the case "
                               "are beyond floating point")
