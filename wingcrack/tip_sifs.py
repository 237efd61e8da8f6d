"""Stress intensity factors at every tip: displacement correlation (the
paper's method, on the quarter-point rosette) and the interaction integral
(an independent check), plus G, the MTS kink angle and K_eq."""
from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

import wingcrack_kernels as K
from .contact.face_term import face_term
from .fem.interaction_integral import InteractionIntegral
from .fem.nodal import nodal_displacements
from .material import kappa
from .results import TipValues

# Outer radius of the interaction-integral domain, in rosette radii; it is
# cut back so the domain holds no other fracture, boundary or crack kink.
R_OUT_ROSETTES = 4.0
#: an annulus domain needs an outer radius above this many rosette radii
ANNULUS = 1.2
#: outer radius of the one-layer domain, in rosette radii (see interaction_radius)
R_OUT_ONE_LAYER = 1.05


@dataclass
class TipSIF(TipValues):
    """A tip's SIFs by both methods (results.TipValues) and r_out, the outer
    radius of its interaction-integral domain (m; 0 where it had no room)."""
    r_out: float

    def as_dict(self):
        return asdict(self)


def interaction_radius(tip, fractures, domain) -> float:
    """Largest safe outer radius of the M-integral domain at `tip` (0 when
    there is no room for one).

    The domain is cut back so that it holds no other fracture, no boundary
    and no kink of the tip's own crack. A grown wing's last segment is
    shorter than 1.5 rosette radii (meshing makes the rosette at most 0.75
    of it), which leaves no annulus between the rosette and the kink; then
    the domain is the one layer of elements around the rosette (q = 1 on
    the ring, 0 on every vertex beyond R_OUT_ONE_LAYER h): the kink, at
    >= 1.33 h, is at most a vertex of that layer, so the crack inside it is
    straight. Measured against displacement correlation on wings after a
    70-degree kink: 0.2 % (KI) and 0.4 % of KI (KII); the full annulus to
    4 h gives 0.04 % on straight cracks."""
    h = tip.h
    p = np.asarray(tip.x, float)
    others = min(R_OUT_ROSETTES * h, 0.8 * domain.distance_to_boundary(p))
    own = np.inf
    for i, pts in enumerate(fractures):
        pts = np.asarray(pts, float)
        if i == tip.fracture:
            # the crack must be straight inside the domain: stay clear of
            # its last kink (or its other end)
            rest = pts[:-1] if tip.end == 1 else pts[1:]
            if len(rest) >= 2:
                own = 0.8 * K.point_polyline_distance(p, rest)
            else:
                own = 0.8 * float(np.linalg.norm(pts[-1] - pts[0]))
        else:
            others = min(others, 0.8 * K.point_polyline_distance(p, pts))
    limit = min(others, own)
    if limit > ANNULUS * h:
        return limit
    if others > ANNULUS * h and own / 0.8 > R_OUT_ONE_LAYER * h:   # q = 0 at the kink
        return R_OUT_ONE_LAYER * h
    return 0.0


def _face_correction(cm, tip, face_forces, r_in, r_out, shear_modulus, kap):
    """E'/2-free face term F = int t . du^a/dx1 q ds over both faces."""
    sel = np.asarray(cm.crack_fracture) == tip.fracture
    plus = np.asarray(cm.crack_edges)[sel]
    minus = np.asarray(cm.crack_edges_minus)[sel]
    upper, lower = (plus, minus) if tip.end == 1 else (minus, plus)
    args = (tip.x, tip.ex, tip.ey, r_in, r_out, shear_modulus, kap)
    uI, uII = face_term(cm.x, upper, face_forces, *args)
    lI, lII = face_term(cm.x, lower, face_forces, *args)
    # du^a/dx1 = -c/sqrt(r) on the upper face, +c/sqrt(r) on the lower
    return lI - uI, lII - uII


def correlation_sifs(problem, cm, E: float, nu: float, plane: str):
    """(KI, KII) of every tip of `cm` by displacement correlation: cheap (four
    nodal displacements a tip), used inside the critical-load search."""
    tips = cm.tips
    if not tips:
        return np.zeros(0), np.zeros(0)
    nodes = np.array([[t.upper[0], t.upper[1], t.lower[0], t.lower[1]] for t in tips], dtype=np.int64)
    u = problem.u_at(problem.fm.block_dofs(nodes.ravel())[1])   # tip face nodes: outside a far interior
    u = nodal_displacements(problem.fm, u, nodes.ravel()).reshape(len(tips), 4, 2)
    ex = np.array([t.ex for t in tips], float)
    ey = np.array([t.ey for t in tips], float)
    h = np.array([t.h for t in tips], float)
    shear_modulus = E / (2 * (1 + nu))
    KI, KII = K.displacement_correlation(u[:, 0], u[:, 1], u[:, 2], u[:, 3], ex, ey, h, shear_modulus,
                                         kappa(nu, plane))
    return np.atleast_1d(KI), np.atleast_1d(KII)


def tip_sifs(problem, cm, fractures, domain, E: float, nu: float, plane: str, sigma0,
             face_forces=None) -> list[TipSIF]:
    """SIFs of every tip of `cm`. face_forces: (nodes, 2) nodal forces on the
    crack faces (contact), needed by the interaction integral's face term."""
    tips = cm.tips
    if not tips:
        return []
    shear_modulus = E / (2 * (1 + nu))
    kap = kappa(nu, plane)
    KI, KII = correlation_sifs(problem, cm, E, nu, plane)
    theta = np.atleast_1d(K.mts_angle(KI, KII))
    Keq = np.atleast_1d(K.equivalent_k(KI, KII, theta))
    G = np.atleast_1d(K.energy_release_rate(KI, KII, E, nu, kap))

    M = InteractionIntegral(problem, E, nu, plane, sigma0)
    out = []
    for i, t in enumerate(tips):
        r_out = interaction_radius(t, fractures, domain)
        r_in = t.h * (1.0 + 1e-6)
        if r_out > 0.0:
            kim, kiim = M.sifs(t.x, t.ex, t.ey, r_in, r_out)
            if face_forces is not None:
                fI, fII = _face_correction(cm, t, face_forces, r_in, r_out, shear_modulus, kap)
                kim -= M.Eprime / 2 * fI
                kiim -= M.Eprime / 2 * fII
        else:
            kim = kiim = None  # no room for a domain: reported as null, never NaN
        out.append(TipSIF(int(t.fracture), int(t.end), float(t.x[0]), float(t.x[1]),
                          float(KI[i]), float(KII[i]), kim, kiim, float(G[i]),
                          float(theta[i]), float(Keq[i]), float(r_out)))
    return out
