"""What geometry can be meshed: the one set of rules that `wingcrack check`
(wingcrack/case/), the mesher (meshing/mesher.py), meshing.Domain and
the growth of tips (propagation/joining.py) share, so that what the check
accepts the mesher meshes, and what growth makes the next mesh takes.

Each rule is a function returning a `Problem` (the key it is about, in the
case file's terms, and the reason) or None. The case check raises
CaseError(problem.key, problem.message); the mesher raises `Inadmissible`
(a ValueError) with the same text.

Lengths are relative: REL_TOL times the domain's length scale is "on the
boundary", "touching" and "zero length"; clearances around a crack tip are
in rosette radii h (the mesher's rosette: radius min(tip_size, 0.75 x the
tip's segment)). The clearances were measured with the mesher, its own
checks switched off, on the rectangle [-1, 1]^2 with tip_size 0.02, size
0.2 and 32 sectors (tests/unit/test_admissibility.py keeps the measurements):
the mesh of a rosette disc that comes within g h of something else has a
triangle of quality ~g (the rosette's own sectors: 0.33); at g = 0 the
mesh is invalid or gmsh aborts.

Fractures may meet (meshing/network.py joins them: T's, X's, ends met end
to end, closed loops). What no mesh holds (a common stretch, a meeting on
the boundary: `joins`) both the check and the mesher refuse; what makes
poor cells (junction angles, junctions too near each other or the
boundary, an end a hair off a fracture) the check refuses for the case's
fractures, while the mesher takes what growth makes (a wing's T at any
angle) as it is.

The rules' terms (tolerances, clearances, Problem) are meshing/rules.py and
the rules of how fractures meet meshing/junction_rules.py; this module is
the rules' one face (it re-exports both). Pure numpy, scipy and the
compiled kernels; never the `wingcrack` package.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import wingcrack_kernels as K
from scipy.spatial import cKDTree

from meshing import network
from meshing.junction_rules import (fracture_ends, ends_on_or_apart, fractures_meet, joined, joined_ends, joins,
                                    junction_angles, junctions_apart)
from meshing.rules import (ANCHOR_GAP, GAP, JUNCTION_GAP, LENGTH_RANGE, MAX_OFFSET, MIN_JUNCTION_ANGLE, MIN_ROSETTE,
                           MIN_TIP_FRACTION, NEAR_MISS, NEIGHBOUR_CLEARANCE, REL_TOL, ROSETTE_IN_SEGMENT, TIP_CLEARANCE,
                           Inadmissible, Problem, fracture_key, require, short_of)

# the rules' one public face: its own rules, with the terms and the junction rules it shares
__all__ = ["ANCHOR_GAP", "GAP", "JUNCTION_GAP", "LENGTH_RANGE", "MAX_OFFSET", "MIN_JUNCTION_ANGLE", "MIN_ROSETTE",
           "MIN_TIP_FRACTION", "NEAR_MISS", "NEIGHBOUR_CLEARANCE", "REL_TOL", "ROSETTE_IN_SEGMENT", "TIP_CLEARANCE",
           "anchors_apart", "bc_point", "case_geometry", "ends_on_or_apart", "far_outside", "far_outside_each",
           "fracture", "fracture_key", "fractures_meet", "free_tips", "Inadmissible", "joined", "joined_ends",
           "joins", "junction_angles", "junctions_apart", "polygon", "Problem", "require", "Rosette",
           "rosette_radius", "rosettes", "rosettes_apart", "scale", "segments_hold_rosettes", "tip_size"]


@dataclass(frozen=True)
class Rosette:
    """The rosette disc of one crack tip: fracture f, end (0: first point,
    1: last), centre x and radius h."""

    fracture: int
    end: int
    x: np.ndarray
    h: float


def _hits(a, b, p, q) -> np.ndarray:
    """(k,) bool: whether the segment [a, b] meets each segment [p, q] (rows
    of (k, 2)) at REL_TOL (the kernel's segment_intersection, one call)."""
    k = len(p)
    return K.segment_intersections(np.tile(a, (k, 1)), np.tile(b, (k, 1)), p, q, REL_TOL)[0]


# ---------------------------------------------------------------- the domain


def scale(size: float, offset: float, size_key: str, offset_key: str) -> Problem | None:
    """The domain's size within LENGTH_RANGE, its coordinates within MAX_OFFSET sizes of the origin."""
    lo, hi = LENGTH_RANGE
    if not lo <= size <= hi:
        return Problem(size_key, f"a domain {size:g} m across is outside the verified range {lo:g} .. {hi:g} m")
    if offset > MAX_OFFSET * size:
        return Problem(offset_key, f"coordinates {offset:g} m from the origin are over {MAX_OFFSET:g} times "
                                   f"the domain size ({size:g} m): move the origin near the domain")
    return None


def polygon(pts: np.ndarray, key: str) -> Problem | None:
    """Edges of non-zero length, no two crossing or touching, a positive area, counter-clockwise."""
    pts = np.asarray(pts, dtype=np.float64)
    extent = float(np.ptp(pts, axis=0).max())
    tol = REL_TOL * max(extent, np.finfo(float).tiny)
    edges = np.roll(pts, -1, axis=0) - pts
    for i, e in enumerate(edges):
        if np.linalg.norm(e) <= tol:
            return Problem(key, f"edge{i} has zero length (points {i} and {(i + 1) % len(pts)} coincide)")
    area2 = float(np.sum(pts[:, 0] * np.roll(pts[:, 1], -1) - np.roll(pts[:, 0], -1) * pts[:, 1]))
    if K.polyline_self_intersects(pts, REL_TOL):
        return Problem(key, "the polygon intersects itself")
    n = len(pts)
    # the closing edge (n-1 -> 0) against every edge j not adjacent to it, j = 1 ... n-3
    met = np.flatnonzero(_hits(pts[n - 1], pts[0], pts[1:n - 2], pts[2:n - 1]))
    if len(met):
        return Problem(key, f"the polygon intersects itself (edge{n - 1} meets edge{met[0] + 1})")
    if abs(area2) <= tol * extent:
        return Problem(key, "the polygon has no area")
    if area2 < 0:
        return Problem(key, "points must run counter-clockwise (they run clockwise)")
    return None


def tip_size(tip: float, domain, key: str = "mesh.tip_size") -> Problem | None:
    """A rosette well above the geometric tolerance."""
    L = float(domain.length_scale())
    if tip < MIN_TIP_FRACTION * L:
        return Problem(key, f"{tip:g} m is below {MIN_TIP_FRACTION:g} of the domain size "
                            f"({L:g} m): too close to the geometric tolerance")
    return None


# ---------------------------------------------------------------- fractures


def far_outside(domain, p) -> bool:
    """p outside the domain's bounding box grown by its size: decided without
    the distance computations, whose squares overflow for p ~ 1e200."""
    L = float(domain.length_scale())
    if domain.shape == "disc":
        lo, hi = domain.center - domain.radius, domain.center + domain.radius
    else:
        lo, hi = domain.vertices().min(axis=0), domain.vertices().max(axis=0)
    return bool(np.any(np.asarray(p) < lo - L) or np.any(np.asarray(p) > hi + L))


def far_outside_each(domain, pts) -> np.ndarray:
    """far_outside of each point (n, 2)."""
    L = float(domain.length_scale())
    if domain.shape == "disc":
        lo, hi = domain.center - domain.radius, domain.center + domain.radius
    else:
        lo, hi = domain.vertices().min(axis=0), domain.vertices().max(axis=0)
    p = np.asarray(pts, dtype=np.float64).reshape(-1, 2)
    return np.any(p < lo - L, axis=1) | np.any(p > hi + L, axis=1)


def fracture(pts: np.ndarray, key: str, domain) -> Problem | None:
    """One pre-existing fracture: inside the domain (only its ends may lie on
    the boundary: an edge crack's mouth, or both for a fracture from boundary
    to boundary), segments of non-zero length, not crossing itself (a
    polyline of three or more segments may close on itself: last point on
    the first) or the boundary."""
    tol = REL_TOL * float(domain.length_scale())
    far = far_outside_each(domain, pts)
    if far.any():
        i = int(np.argmax(far))
        return Problem(f"{key}[{i}]", f"({pts[i][0]:g}, {pts[i][1]:g}) is outside the domain")
    seg = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    for i, s in enumerate(seg):
        if s <= tol:
            return Problem(key, f"segment {i} (points {i} and {i + 1}) has zero length")
    n = len(pts)
    if n > 3 and np.linalg.norm(pts[-1] - pts[0]) <= tol:   # a ring: its two ends meet
        ring = pts[:-1]
        if K.polyline_self_intersects(ring, REL_TOL) or _hits(pts[-2], pts[-1], pts[1:n - 3], pts[2:n - 2]).any():
            return Problem(key, "the polyline intersects itself")
    elif n > 2 and K.polyline_self_intersects(pts, REL_TOL):
        return Problem(key, "the polyline intersects itself")
    pts = np.asarray(pts, dtype=np.float64)
    on = np.atleast_1d(domain.on_boundary(pts, tol))
    inside = np.atleast_1d(domain.contains(pts)) & ~on
    for i in np.flatnonzero(~inside):
        if (i == 0 or i == n - 1) and on[i]:
            continue  # an edge crack's mouth
        p = pts[i]
        where = "on the boundary (only an end may be)" if on[i] else "outside the domain"
        return Problem(f"{key}[{i}]", f"({p[0]:g}, {p[1]:g}) is {where}")
    # Every point inside does not keep a segment inside: a chord between two
    # boundary ends may run along the boundary, and a polygon may be concave.
    mid = 0.5 * (pts[:-1] + pts[1:])
    off = ~(np.atleast_1d(domain.contains(mid)) & ~np.atleast_1d(domain.on_boundary(mid, tol)))
    if off.any():
        return Problem(key, f"segment {int(np.argmax(off))} runs along or outside the boundary")
    if domain.shape == "polygon":  # rectangles and discs are convex
        poly = np.asarray(domain.vertices(), float)
        m = len(poly)
        i, j = np.divmod(np.arange((n - 1) * m), m)   # every segment i against every boundary edge j, i first
        hit, _, _, x = K.segment_intersections(pts[i], pts[i + 1], poly[j], np.roll(poly, -1, axis=0)[j], REL_TOL)
        for k in np.flatnonzero(hit):
            at_mouth = (i[k] == 0 and np.linalg.norm(x[k] - pts[0]) <= tol) or (
                i[k] == n - 2 and np.linalg.norm(x[k] - pts[-1]) <= tol
            )
            if not at_mouth:
                return Problem(key, f"segment {i[k]} crosses the boundary edge{j[k]}")
    return None


def rosette_radius(tip: float, segment: float) -> float:
    """The mesher's rosette radius at a tip whose segment is `segment` long."""
    return min(tip, ROSETTE_IN_SEGMENT * segment)


def free_tips(domain, polylines, tip: float, net: network.Joined | None = None) -> list[Rosette]:
    """The rosettes of the fracture ends that are tips: not on the boundary,
    not on a fracture (net: the fractures joined, joined() when None; the
    radius from the end's segment there, as the mesher has it)."""
    net = joined(domain, polylines) if net is None else net
    free, _ = fracture_ends(domain, net.polylines)
    out = []
    for f, end in free:
        if (f, end) in net.partner:
            continue
        pts = net.polylines[f]
        i, j = (0, 1) if end == 0 else (-1, -2)
        out.append(Rosette(f, end, np.asarray(pts[i], dtype=np.float64),
                           rosette_radius(tip, float(np.linalg.norm(pts[j] - pts[i])))))
    return out


def rosettes(domain, polylines, tips: list[Rosette], tip: float, key: str = "mesh.tip_size",
             margin: float = 0.0) -> Problem | None:
    """Every rosette disc holds nothing but its own crack's last segment and
    keeps GAP radii from everything else: the boundary, other fractures, its
    own non-adjacent segments (the one before its own: NEIGHBOUR_CLEARANCE),
    and every other rosette. `margin` (m) is added to every clearance: the
    case check asks a few REL_TOL more than the mesher, which sees the mouths
    moved onto the boundary (by up to REL_TOL), so that a geometry on the
    edge of a rule is not accepted by one and refused by the other."""
    polylines = [np.asarray(p, dtype=np.float64) for p in polylines]
    x = np.array([t.x for t in tips], dtype=np.float64).reshape(-1, 2)
    h = np.array([t.h for t in tips], dtype=np.float64)
    fr = np.array([t.fracture for t in tips], dtype=np.int64)
    # per tip: its first problem in the order short segment, boundary, segments
    # (in fracture and segment order); the first tip that has one is reported
    short = h < MIN_ROSETTE * tip
    d_boundary = np.atleast_1d(domain.distance_to_boundary(x)) if len(tips) else np.zeros(0)
    to_boundary = d_boundary <= TIP_CLEARANCE * h + margin
    seg_hit = {}   # tip -> (distance, segment) of its first segment within reach
    if polylines and len(tips):
        a, b, owner, index = network.segments(polylines)
        ab = b - a
        n_seg = np.array([len(p) - 1 for p in polylines], dtype=np.int64)
        pt, sg = network.segments_near_points(x, TIP_CLEARANCE * h + margin, a, b)
        u = np.clip(np.einsum("ij,ij->i", x[pt] - a[sg], ab[sg]) / np.einsum("ij,ij->i", ab[sg], ab[sg]), 0.0, 1.0)
        d = np.linalg.norm(x[pt] - a[sg] - u[:, None] * ab[sg], axis=1)
        end = np.array([t.end for t in tips], dtype=np.int64)[pt]
        n = n_seg[fr[pt]]
        mine = owner[sg] == fr[pt]
        own = mine & (index[sg] == np.where(end == 0, 0, n - 1))
        # the segment before its own shares the kink point: the disc must only stay off it
        neighbour = mine & (index[sg] == np.where(end == 0, 1, n - 2))
        reach = np.where(neighbour, NEIGHBOUR_CLEARANCE, TIP_CLEARANCE)
        hit = np.flatnonzero((d <= reach * h[pt] + margin) & ~own)
        for k in hit[::-1]:   # pt, sg sorted: the first segment of each tip wins
            seg_hit[int(pt[k])] = (float(d[k]), int(sg[k]), float(reach[k]), bool(mine[k]))
    for k, t in enumerate(tips):
        where = f"the rosette of fractures[{t.fracture}] end {t.end} (radius {t.h:g})"
        if short[k]:
            seg = t.h / ROSETTE_IN_SEGMENT
            return Problem(fracture_key(t.fracture), f"the segment at end {t.end} ({seg:.3g} m) is too short for a "
                                                     f"tip rosette (tip_size {tip:g})")
        if to_boundary[k]:
            dk = float(d_boundary[k])
            return Problem(key, f"{where} reaches the boundary: the tip is {dk:.7g} m "
                                f"({short_of(dk / t.h, TIP_CLEARANCE, 7)} radii) "
                                f"from it, it needs {TIP_CLEARANCE:g} radii")
        if k in seg_hit:
            dk, s, rk, own_fracture = seg_hit[k]
            what = f"segment {index[s]} of its own fracture" if own_fracture else f"fractures[{owner[s]}]"
            return Problem(key, f"{where} reaches {what}: the tip is {dk:.7g} m "
                                f"({short_of(dk / t.h, rk, 7)} radii) "
                                f"from it, it needs {rk:g} radii")
    if len(tips) > 1:
        pairs = cKDTree(x).query_pairs(float(rosettes_apart(h.max(), h.max())) + margin, output_type="ndarray")
        if len(pairs):
            i, j = pairs.min(axis=1), pairs.max(axis=1)
            dist = np.linalg.norm(x[j] - x[i], axis=1)
            need = rosettes_apart(h[i], h[j])
            close = np.flatnonzero(dist <= need + margin)
            if len(close):
                k = close[np.lexsort((j[close], i[close]))[0]]
                s, t = tips[i[k]], tips[j[k]]
                return Problem(key, f"the rosettes of fractures[{s.fracture}] end {s.end} and fractures[{t.fracture}] "
                                    f"end {t.end} (radii {s.h:g}, {t.h:g}) overlap: the tips are {dist[k]:.6g} m "
                                    f"apart, they need more than {need[k]:.6g} m")
    return None


def rosettes_apart(h_a, h_b):
    """The least distance between two tips with rosettes of radii h_a and h_b (numbers or arrays)."""
    return h_a + h_b + GAP * np.maximum(h_a, h_b)


def segments_hold_rosettes(polylines, tip: float, key: str = "mesh.tip_size") -> Problem | None:
    """Pre-existing fractures: every segment longer than tip_size, so that the
    first rosettes have their full radius."""
    for i, pts in enumerate(polylines):
        shortest = float(np.linalg.norm(np.diff(pts, axis=0), axis=1).min())
        if tip >= shortest:
            return Problem(key, f"must be smaller than the shortest segment of fractures[{i}] "
                                f"({tip:g} >= {shortest:g})")
    return None


# ---------------------------------------------------------------- boundary points


def bc_point(p, key: str, domain, polylines) -> Problem | None:
    """A point condition's place: on the boundary, not on a fracture's mouth."""
    tol = REL_TOL * float(domain.length_scale())
    if far_outside(domain, p):
        return Problem(key, f"({p[0]:g}, {p[1]:g}) is not on the boundary (it is far outside the domain)")
    q = np.asarray(p, dtype=np.float64)
    if not domain.on_boundary(q, tol):
        d = float(domain.distance_to_boundary(q))
        return Problem(key, f"({p[0]:g}, {p[1]:g}) is not on the boundary (it is {d:.3g} m away)")
    for i, pts in enumerate(polylines):
        if K.point_polyline_distance(q, pts) <= tol:
            return Problem(key, f"({p[0]:g}, {p[1]:g}) is the mouth of fractures[{i}]; a point condition there "
                                "is ambiguous")
    return None


def anchors_apart(domain, points, point_keys, polylines, tip: float) -> Problem | None:
    """Boundary points that become mesh nodes (the bc points, the crack
    mouths, the corners) coincide or are at least ANCHOR_GAP tip sizes apart."""
    tol = REL_TOL * float(domain.length_scale())
    gap = ANCHOR_GAP * tip
    named = [(np.asarray(p, dtype=np.float64), k, k) for p, k in zip(points, point_keys)]
    for f, end in fracture_ends(domain, polylines)[1]:
        i = 0 if end == 0 else len(polylines[f]) - 1
        named.append((np.asarray(polylines[f][i], dtype=np.float64), f"{fracture_key(f)}[{i}]",
                      f"the mouth of fractures[{f}]"))
    corners = np.asarray(domain.vertices(), dtype=np.float64).reshape(-1, 2)
    x = np.array([p for p, _, _ in named], dtype=np.float64).reshape(-1, 2)
    for a in range(len(named)):
        p, key, _ = named[a]
        d = np.linalg.norm(np.concatenate([x[:a], corners]) - p, axis=1)
        hit = np.flatnonzero((d > tol) & (d < gap))
        if len(hit):
            k = hit[0]
            what = named[k][2] if k < a else "the corner ({:g}, {:g})".format(*corners[k - a])
            return Problem(key, f"({p[0]:.10g}, {p[1]:.10g}) is {short_of(d[k], gap, 3)} m from {what}: boundary points that "
                                f"become mesh nodes coincide or lie at least {ANCHOR_GAP:g} tip_size "
                                f"({gap:g} m) apart")
    return None


def case_geometry(domain, polylines, points, point_keys, tip: float) -> Problem | None:
    """Everything the mesher needs of a case's initial geometry beyond each
    part alone: segments that hold rosettes, free ends clear of the
    fractures they do not lie on, rosettes that fit, junctions apart,
    boundary nodes apart (on the fractures as joined: fractures_meet's)."""
    margin = 4 * REL_TOL * float(domain.length_scale())
    net = joined(domain, polylines)
    return (segments_hold_rosettes(polylines, tip)
            or ends_on_or_apart(domain, net, polylines, tip)
            or rosettes(domain, net.polylines, free_tips(domain, polylines, tip, net), tip, margin=margin)
            or junctions_apart(domain, net, polylines, tip, margin=margin)
            or anchors_apart(domain, points, point_keys, polylines, tip))
