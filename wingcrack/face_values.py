"""What a solved step says about its fracture faces, pair by pair: the
jump, the tractions, the contact state, the slip, the fluid's pressure
and aperture (face_values, which io/faces.py writes), and the contact
solve's record (contact_record, in summary.json). Each reads a
step.Discretisation at its current solution."""
from __future__ import annotations

import numpy as np

from .fem.nodal import nodal_displacements
from .io.faces import SLIP, STICK
from .results import ContactRecord


def pair_states(disc):
    """(state (p,) int8 OPEN / STICK / SLIP (io.faces), closed (p,) bool:
    in contact, state != OPEN on a normal row) of every face-node pair,
    in cm.pairs order. Local (no communication)."""
    cm, c = disc.cm, disc.contact
    closed = np.zeros(len(cm.pairs), bool)
    if c.result is not None:
        normal = c.rows.normal
        closed[c.rows.pair[normal]] = c.result.active[normal]
    return c.pair_states(len(cm.pairs)), closed


def pair_slips(disc) -> np.ndarray:
    """(p,) the slip [u].t of every Coulomb pair at the current solution
    (0 elsewhere): the history the next mesh carries on."""
    c = disc.contact
    out = np.zeros(len(disc.cm.pairs))
    if c.result is not None:
        k = c.rows.coulomb
        out[c.rows.pair[k]] = c.result.jump[k]
    return out


def face_values(disc) -> dict:
    """The faces' values of every face-node pair, in cm.pairs order
    (io/faces.py writes them): {"jump": (p, 2) [u] = u(+) - u(-) (m),
    "normal_traction": (p,) t_n (Pa, <= 0 in contact; 0 without a normal
    row), "tangential_traction": (p,) t_t = -forces_t / weight = t.sigma.n
    (Pa, the shear stress on the face plane, signed as the slip it
    drives; 0 without a tangential row), "state" and "closed"
    (pair_states), "slip_increment": (p,) s - s_reference (m; 0 on
    non-coulomb pairs), "pressure": (p,) the fluid pressure of the pair's
    fracture at the solved load (Pa), "aperture": (p,) the fluid's aperture
    w + g + the residual aperture (m; w = [u].n, g the initial gap where a
    normal row holds it, the residual aperture on pre-existing faces; with
    the flow, no less than a held wing's least aperture),
    "flux": (p,) the fluid's volume flux along the fracture direction d
    (m^2/s per metre; 0 without the flow along the fractures)}.
    Collective (the face displacements are gathered)."""
    cm, problem, c = disc.cm, disc.problem, disc.contact
    pairs = np.asarray(cm.pairs, dtype=np.int64).reshape(-1, 2)
    fm, u = problem.fm, problem.u
    jump = nodal_displacements(fm, u, pairs[:, 0]) - nodal_displacements(fm, u, pairs[:, 1])
    normal_traction = np.zeros(len(pairs))
    tangential_traction = np.zeros(len(pairs))
    slip_increment = c.slip_increments(len(pairs))
    state, closed = pair_states(disc)
    if c.result is not None:
        normal = c.rows.normal
        t = c.tractions()
        normal_traction[c.rows.pair[normal]] = t[normal]
        tangential_traction[c.rows.pair[~normal]] = t[~normal]
    flow = disc.fluid.flow
    if flow is not None:   # the flow along the fractures: the pressure field and its flux
        pressure, flux = flow[0], flow[1]
    else:
        pressure = disc.fluid.pressures(problem.load_factor_solved)[np.asarray(cm.pair_fracture, np.int64)] \
            if len(pairs) else np.zeros(0)
        flux = np.zeros(len(pairs))
    gap = np.zeros(len(pairs))
    normal = c.rows.normal
    gap[c.rows.pair[normal]] = c.rows.gap[normal]
    n = np.asarray(cm.pair_normal, float).reshape(-1, 2)
    residual = disc.fluid.residual
    aperture = np.sum(jump * n, axis=1) + gap + (0.0 if residual is None else residual)
    if disc.fluid.least is not None:   # the flow's: a held wing's shut faces leave their least aperture
        aperture = np.where(disc.fluid.least > 0, np.maximum(aperture, disc.fluid.least), aperture)
    return {"jump": jump, "normal_traction": normal_traction, "tangential_traction": tangential_traction,
            "state": state, "slip_increment": slip_increment, "closed": closed, "pressure": pressure,
            "aperture": aperture, "flux": flux}


def contact_record(disc) -> ContactRecord:
    """The contact solve of the current solution, as summary.json records
    it: pairs and rows, the closed rows, the stick and slip pairs, the
    iterations, the KKT (and friction) residuals, the fallbacks taken."""
    c = disc.contact
    rec = ContactRecord(int(len(disc.cm.pairs)), int(len(c.rows)))
    if c.result is not None:
        state, _ = pair_states(disc)
        rec.closed = int(np.sum(c.result.active))
        rec.stick, rec.slip = int(np.sum(state == STICK)), int(np.sum(state == SLIP))
        rec.iterations = int(c.result.iterations)
        rec.kkt = c.result.kkt_residuals(c.rows.gap, c.rows.normal)
        rec.fallback = bool(c.result.fallback)
        rec.broken = int(getattr(c.result, "broken", 0))
        rec.loose = int(getattr(c.result, "loose", 0))
        if getattr(c.result, "state", None) is not None:
            rec.friction = c.result.friction_residuals(c.rows.weight)
    return rec
