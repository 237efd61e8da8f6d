"""The mesher's plan: the fractures, tips, boundary anchors and junctions of
one mesh, checked against the admissibility rules (meshing/admissibility.py)
and joined (meshing/network.py); pure geometry, before gmsh."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from meshing import admissibility, network, point_symmetry
from meshing.domain import Domain


# Ends of fractures and bc points closer than this (times the domain diameter)
# to the boundary are on it.
ON_BOUNDARY = admissibility.REL_TOL


@dataclass
class _Tip:
    fracture: int
    end: int
    x: np.ndarray  # tip point
    back: np.ndarray  # unit vector from the tip back along the crack
    h: float  # rosette radius


@dataclass
class Plan:
    fractures: list[np.ndarray]  # mouths projected onto the boundary, junction points inserted
    tips: list[_Tip]
    anchors: list[tuple[int, float, np.ndarray]]  # boundary split points (edge, param, point)
    point_anchor: list[int]  # anchor of each bc point
    mouth_anchor: dict[tuple[int, int], int]  # (fracture, end) -> anchor
    junction: dict[tuple[int, int], tuple[int, int]] = field(default_factory=dict)
    # (fracture, end) -> (host fracture, vertex of the host's polyline) at a T


ROSETTE_IN_SEGMENT = admissibility.ROSETTE_IN_SEGMENT


def make_plan(domain: Domain, fractures, points, tip_size: float) -> Plan:
    tol = ON_BOUNDARY * domain.length_scale()
    anchors: list[tuple[int, float, np.ndarray]] = []

    def anchor(p) -> int:
        q, edge, t = domain.project(p)
        for i, (_, _, a) in enumerate(anchors):
            if np.linalg.norm(a - q) <= tol:
                return i
        anchors.append((edge, t, q))
        return len(anchors) - 1

    polylines, mouth_anchor, free_ends = [], {}, []
    for f, pts in enumerate(fractures):
        pts = np.array(pts, dtype=np.float64)
        if pts.ndim != 2 or pts.shape[1] != 2 or len(pts) < 2 or not np.all(np.isfinite(pts)):
            raise ValueError(f"fracture {f}: points must be finite, (n >= 2, 2)")
        if np.any(np.linalg.norm(np.diff(pts, axis=0), axis=1) <= 1e3 * tol):
            raise ValueError(f"fracture {f}: two consecutive points coincide")
        inner = pts[1:-1]
        if len(inner) and (
            not np.all(domain.contains(inner)) or np.any(domain.distance_to_boundary(inner) <= tol)
        ):
            raise ValueError(f"fracture {f}: inner points must lie inside the domain")
        for end, i in ((0, 0), (1, -1)):
            if domain.distance_to_boundary(pts[i]) <= tol:
                a = anchor(pts[i])
                pts[i] = anchors[a][2]
                mouth_anchor[(f, end)] = a
            elif not domain.contains(pts[i]):
                raise ValueError(f"fracture {f}: end {end} lies outside the domain")
            else:
                free_ends.append((f, end))
        polylines.append(pts)

    joined = network.join(polylines, free_ends, tol, mouths=list(mouth_anchor))
    admissibility.require(admissibility.joins(joined, [len(p) for p in fractures]))
    polylines, junction, met = joined.polylines, joined.junction, joined.met
    tips = []
    for f, end in free_ends:
        if (f, end) in junction or (f, end) in met:
            continue
        pts = polylines[f]
        i, j = (0, 1) if end == 0 else (-1, -2)
        back = pts[j] - pts[i]
        length = float(np.linalg.norm(back))
        tips.append(_Tip(f, end, pts[i].copy(), back / length, admissibility.rosette_radius(tip_size, length)))

    point_anchor = []
    for q, p in enumerate(points):
        p = np.asarray(p, dtype=np.float64).reshape(2)
        if domain.distance_to_boundary(p) > 1e-6 * domain.length_scale():
            raise ValueError(f"bc point {q} at {p.tolist()} is not on the boundary")
        point_anchor.append(anchor(p))

    rosettes = [admissibility.Rosette(t.fracture, t.end, t.x, t.h) for t in tips]
    admissibility.require(admissibility.rosettes(domain, polylines, rosettes, tip_size))
    return Plan(polylines, tips, anchors, point_anchor, mouth_anchor, junction)


def with_divider(domain, plan: Plan, half) -> Plan:
    """The plan of a point-symmetric geometry: the divider's crossings become
    fracture vertices, its ends and every anchor's image become anchors."""
    tol = ON_BOUNDARY * domain.length_scale()
    fractures, junction = point_symmetry.insert_divider(plan.fractures, plan.junction, half, tol)
    anchors = list(plan.anchors)

    def add(p) -> np.ndarray:
        for _, _, a in anchors:
            if np.linalg.norm(a - p) <= tol:
                return a
        q, edge, t = domain.project(p)
        anchors.append((edge, t, q))
        return q

    for _, _, a in plan.anchors:
        add(point_symmetry.rotate(a, half.center))
    half.points[0], half.points[-1] = add(half.points[0]), add(half.points[-1])
    return dataclasses.replace(plan, fractures=fractures, junction=junction, anchors=anchors)
