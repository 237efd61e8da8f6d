"""Growth of the tips in one step (paper section 3.2): which tips reached
the toughness, where each one goes, and the fracture set after the step.

For every tip that may grow (a Candidate: its SIFs of the method that drives
growth and its tip frame):
1. it reached KIc when K_eq >= KIc (1 - KEQ_RTOL);
2. direction: the MTS kink angle theta; length: the growth law
   L_i = Lmax (G_i / max G)^alpha with G_i = K_eq^2 / E' and the L_min rule
   (growth_law.advances); both rounded to grids (see ANGLE_GRID);
3. joining.placement: free, on another fracture ("joined", a T) or on the
   boundary;
4. a join onto the tip's own polyline would close a loop around a piece of
   the body that nothing holds; the tip goes straight to its proposed point
   instead when that point leaves the mesher the room a rosette needs
   (clear_of_own_fracture), and does not grow otherwise;
5. a join within reach of another fracture's free end meets that end
   (tip to tip: both stop). A joined end records the fracture it met in
   joined_to (tip to tip: both ends), which connects the two hydraulically
   (FractureSet.connect_pressures);
6. short straight growth moves the tip node, anything else adds a segment.
After all tips: growth made no two fractures cross (ComputationError otherwise).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from meshing import admissibility, network

import wingcrack_kernels as K
from ..errors import ComputationError
from ..material import e_prime
from ..parallel import snap
from ..shortest_advance import L_MIN
from .growth_law import STRAIGHT, advances
from .joining import placement

#: the join distance, in rosette radii (see joining.py): the clearance the
#: mesher keeps around a rosette
REACH = admissibility.TIP_CLEARANCE
#: relative tolerance of "K_eq reached KIc". Tips that the discretisation
#: cannot tell apart (displacement correlation is ~1e-3 accurate; the two
#: tips of a point-symmetric geometry differ by ~3e-5 on a mesh that is not
#: symmetric) grow together, as the symmetric physics says.
KEQ_RTOL = 1e-3
#: kink angles (rad) and advances (in propagation.length) are rounded to
#: these grids before the geometry is built (parallel.snap: 1 and N
#: processes then build the same geometry; with SIF round-off ~1e-13 a
#: rounding boundary separates them with probability ~1e-5 a tip and step).
#: 1e-8 rad moves a 1 mm step's end by 1e-11 m.
ANGLE_GRID = 1e-8
LENGTH_GRID = 1e-8

#: why a tip did not grow (the run's status names them when no tip could)
BELOW_KIC = "below KIc"
UNDER_L_MIN = "its advance would be under L_min = 0.4 mesh.tip_size"
FOLDS_BACK = "it would fold back onto its own fracture"


@dataclass(frozen=True)
class Rule:
    """What decides growth: the toughness KIc (Pa m^0.5), E' (Pa: E in plane
    stress, E/(1 - nu^2) in plane strain), Lmax (propagation.length, m),
    alpha, and the rosette radius h (mesh.tip_size, m)."""
    KIc: float
    Eprime: float
    length: float
    alpha: float
    tip_size: float

    @classmethod
    def of(cls, case) -> "Rule":
        m, p = case.material, case.propagation
        return cls(m.KIc, e_prime(m.E, m.nu, m.plane), p.length, p.alpha, case.mesh.tip_size)

    @property
    def reach(self) -> float:
        return REACH * self.tip_size


@dataclass(frozen=True)
class Candidate:
    """A tip that may grow: `index` in the step's tips, its fracture and end,
    K_eq and theta (rad) of the SIFs that drive growth, and its tip frame
    (ex along the crack out of the tip, ey = ex turned +90 degrees)."""
    index: int
    fracture: int
    end: int
    K_eq: float
    theta: float
    ex: np.ndarray
    ey: np.ndarray


@dataclass
class TipGrowth:
    """What a step did to one tip: state "growing", "arrested", "joined" or
    "boundary"; advance, the distance moved (m); why, for an arrested tip
    that was a candidate, the reason it did not grow."""
    state: str = "arrested"
    advance: float = 0.0
    why: str = ""


@dataclass
class Growth:
    """The growth of one step: a TipGrowth for every tip of the step."""
    tips: list

    @property
    def grew(self) -> bool:
        return any(t.advance > 0 for t in self.tips)

    def why_none(self) -> str:
        """Why no tip grew, for the run's status."""
        why = sorted({t.why for t in self.tips if t.why})
        return "; ".join(why) or "no tip may grow"


def may_grow(cm, fset) -> list:
    """Indices into cm.tips (a crack mesh's tips) of the tips that may grow:
    free ends of fractures that grow."""
    active = set(fset.active_tips())
    return [i for i, t in enumerate(cm.tips) if (int(t.fracture), int(t.end)) in active]


def candidates(tips, cm, indices) -> list:
    """The Candidate of each tip `indices` of the step's `tips` (TipSIF, in
    cm.tips order): its driving SIFs and its tip frame from the mesh."""
    return [Candidate(i, tips[i].fracture, tips[i].end, tips[i].K_eq, tips[i].theta,
                      np.asarray(cm.tips[i].ex, float), np.asarray(cm.tips[i].ey, float)) for i in indices]


def reached(candidates, rule: Rule) -> np.ndarray:
    """Which candidates reached the toughness."""
    keq = np.array([c.K_eq for c in candidates], float)
    return keq >= rule.KIc * (1 - KEQ_RTOL)


def grow(fset, candidates: list, n_tips: int, rule: Rule, domain) -> Growth:
    """Advance the candidates in `fset` (in place, in their order: a later
    tip sees where an earlier one went) and return the Growth of all n_tips
    tips of the step."""
    out = Growth([TipGrowth() for _ in range(n_tips)])
    if not candidates:
        return out
    at_kic = reached(candidates, rule)
    keq = np.array([c.K_eq for c in candidates], float)
    G = np.where(at_kic, keq ** 2 / rule.Eprime, 0.0)
    theta = snap([c.theta for c in candidates], ANGLE_GRID)
    Lmin = L_MIN * rule.tip_size
    L = snap(advances(G, rule.length, rule.alpha, Lmin, theta), LENGTH_GRID * rule.length)
    for j, c in enumerate(candidates):
        tip = out.tips[c.index]
        if L[j] <= 0:
            tip.why = UNDER_L_MIN if at_kic[j] else BELOW_KIC
            continue
        f = fset.fractures[c.fracture]
        if f.ends[c.end] != "tip":   # met end to end by a tip that grew before it in this step
            tip.state = f.ends[c.end]
            continue
        d = np.cos(theta[j]) * np.asarray(c.ex, float) + np.sin(theta[j]) * np.asarray(c.ey, float)
        p, state, met = placement(fset, c.fracture, c.end, d, L[j], domain, rule.reach)
        moves_node = abs(theta[j]) <= STRAIGHT and L[j] < Lmin   # straight on, short: the tip node moves
        if state == "joined" and on_own_fracture(f, c.end, p):
            p = f.tip(c.end) + L[j] * d
            pts = f.points if c.end == 1 else f.points[::-1]      # the tip last
            grown = np.vstack([pts[:-1] if moves_node else pts, p])
            if not clear_of_own_fracture(fset, c.fracture, c.end, grown, rule, domain):
                tip.why = FOLDS_BACK
                continue
            state = "tip"
        elif state == "joined":   # on another fracture's growing end: link them end to end
            p, tip_met = meet_tip_to_tip(fset, c.fracture, p, rule.reach)
            met = met if tip_met is None else tip_met
        a = f.tip(c.end)
        if moves_node and state == "tip":
            f.move_tip(c.end, p)
        else:
            f.extend(c.end, p)
        f.ends[c.end] = state
        f.joined_to[c.end] = met if state == "joined" else None
        tip.state = "growing" if state == "tip" else state
        tip.advance = float(np.linalg.norm(p - a))
    check_no_crossing(fset)
    return out


def on_own_fracture(f, end, p) -> bool:
    """Is the join point `p` on the growing fracture's own polyline (beyond
    the segment at the tip)? Joining there closes a loop around a piece of
    the body that nothing holds."""
    pts = f.points[:-1] if end == 1 else f.points[1:]
    if len(pts) < 2:
        return False
    scale = float(np.ptp(f.points, axis=0).max()) or 1.0
    return K.point_polyline_distance(np.asarray(p, float), pts) <= 1e-9 * scale


def clear_of_own_fracture(fset, fi: int, end: int, grown, rule: Rule, domain) -> bool:
    """May end `end` of fracture `fi` become the free tip of the polyline
    `grown` (its points after the step, the growing tip last)?

    joining.place_tip joins a tip within `reach` of any polyline, its own
    included. Near its own polyline that is no join but an artefact of short
    steps: after a kink, the next step's end is about two step lengths from
    the kink point, within reach whenever the length is under 0.75 tip_size
    (with length = tip_size / 2 a tip would sit at KIc without growing). The tip goes on if its new segment crosses nothing, it stays
    `reach` from the boundary and every other fracture (else place_tip would
    have joined them), and the next mesh takes it: the mesher's own rules
    (meshing.admissibility.rosettes) for every free tip's rosette on the
    polylines after the step."""
    grown = np.asarray(grown, float)
    p, a = grown[-1], grown[-2]
    if not domain.contains(p) or domain.distance_to_boundary(p) <= rule.reach:
        return False
    earlier = max(len(grown) - 3, 0)     # the new segment crosses none of the earlier ones
    if K.segment_intersections(np.tile(a, (earlier, 1)), np.tile(p, (earlier, 1)), grown[:earlier],
                               grown[1:earlier + 1], 1e-12)[0].any():
        return False
    polylines, tips = [], []
    for g, other in enumerate(fset.fractures):
        if g == fi:
            polylines.append(grown)
            ends = (other.ends[1 - end], "tip")   # grown runs from the other end to the growing tip
            pts = grown
        else:
            if (K.point_polyline_distance(p, other.points) <= rule.reach
                    or K.polylines_intersect(np.array([a, p]), other.points, 1e-12)):
                return False
            polylines.append(other.points)
            ends, pts = other.ends, other.points
        for e, (i, j) in ((0, (0, 1)), (1, (-1, -2))):
            if ends[e] == "tip":
                h = admissibility.rosette_radius(rule.tip_size, float(np.linalg.norm(pts[j] - pts[i])))
                tips.append(admissibility.Rosette(g, e, np.asarray(pts[i], float), h))
    return admissibility.rosettes(domain, polylines, tips, rule.tip_size) is None


def meet_tip_to_tip(fset, fi, p, reach):
    """A join point within `reach` of another fracture's free end (a tip)
    would leave that tip's rosette no room: the two meet at that end, which
    stops growing too ("joined", joined_to fracture `fi`). Returns the join
    point and the index of the fracture met (None when no tip is within
    reach: `p` unchanged)."""
    for g, other in enumerate(fset.fractures):
        if g == fi:
            continue
        for e in (0, 1):
            if other.ends[e] == "tip" and np.linalg.norm(other.tip(e) - p) <= reach:
                other.ends[e] = "joined"
                other.joined_to[e] = fi
                return other.tip(e).copy(), g
    return p, None


def crossing_pair(polys, pre=None):
    """(i, j) of the first two polylines that cross (touching at a T or an
    end is not crossing), or None. pre: per polyline the (first, last)
    vertex of its pre-existing part; two pre-existing parts may cross (the
    case's network, which `check` accepts), so such crossings do not count.
    Only segments near each other are measured (meshing.network's search)."""
    polys = [np.asarray(p, float) for p in polys]
    if len(polys) < 2:
        return None
    a, b, owner, index = network.segments(polys)
    extent = float(np.ptp(np.concatenate([a, b]), axis=0).max()) or 1.0
    i, j = network.near_segment_pairs(a, b, 1e-9 * extent)
    keep = owner[i] != owner[j]
    if pre is not None:
        first = np.array([p[0] for p in pre], dtype=np.int64)
        last = np.array([p[1] for p in pre], dtype=np.int64)

        def is_pre(k):
            return (index[k] >= first[owner[k]]) & (index[k] + 1 <= last[owner[k]])
        keep &= ~(is_pre(i) & is_pre(j))
    i, j = i[keep], j[keep]
    order = np.lexsort((index[j], index[i], owner[j], owner[i]))
    i, j = i[order], j[order]
    hit, t, u, _ = K.segment_intersections(a[i], b[i], a[j], b[j], 1e-12)
    crossed = np.flatnonzero(hit & (1e-9 < t) & (t < 1 - 1e-9) & (1e-9 < u) & (u < 1 - 1e-9))
    return (int(owner[i[crossed[0]]]), int(owner[j[crossed[0]]])) if len(crossed) else None


def check_no_crossing(fset) -> None:
    """Growth never makes fractures cross (they may touch at T-junctions;
    pre-existing fractures may cross each other)."""
    pair = crossing_pair(fset.polylines(), [f.pre for f in fset.fractures])
    if pair is not None:
        raise ComputationError(f"fractures {pair[0]} and {pair[1]} cross")
