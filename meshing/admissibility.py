"""What geometry can be meshed: the one set of rules that `wingcrack check`
(wingcrack/case.py), the mesher (meshing/crack_mesh.py), meshing.Domain and
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
0.2 and 32 sectors (tests/test_admissibility.py keeps the measurements):
the mesh of a rosette disc that comes within g h of something else has a
triangle of quality ~g (the rosette's own sectors: 0.33); at g = 0 the
mesh is invalid or gmsh aborts.

Pure numpy and the compiled kernels; never the `wingcrack` package.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: Relative tolerance (times the domain's length scale) for "on the
#: boundary", "touching" and "zero length".
REL_TOL = 1e-9
#: The domain sizes (m across) the mesher and solver take. The mesher hands
#: gmsh the geometry in a frame where the domain is 1e-3 to 1e3 units across
#: (crack_mesh._Frame): gmsh alone fails to recover edges ("Unable to
#: recover the edge", then aborts) at 6e-9 m and below.
LENGTH_RANGE = (1e-9, 1e9)
#: Coordinates at most this many domain sizes from the origin: beyond it the
#: rounding of a coordinate (|x| 2.2e-16) nears the geometric tolerance REL_TOL.
#: (gmsh itself sees the domain near its origin: crack_mesh._Frame.)
MAX_OFFSET = 1e6
#: mesh.tip_size at least this fraction of the domain size: a smaller rosette
#: lies within 1000 geometric tolerances of its tip.
MIN_TIP_FRACTION = 1e3 * REL_TOL

#: The room, in rosette radii, between a rosette disc and anything else (the
#: boundary, another fracture, a non-adjacent segment of its own, another
#: rosette). Measured: a tip 1.0 h from the boundary or another fracture
#: gives an inverted cell, 1.001 h quality 0.009, 1.01 h 0.09, 1.05 h the
#: rosette's own 0.33; two rosettes (of two fractures, or the two tips of
#: one short fracture) 2.0 h apart: gmsh aborts or an inverted cell, 2.01 h
#: quality 0.09, 2.05 h 0.33. Half a rosette leaves a graded layer of
#: triangles there, and is the join distance of growth (joining.py): a tip
#: that comes this close to something joins it.
GAP = 0.5
#: A tip's distance to the boundary, to other fractures and to the
#: non-adjacent segments of its own, in rosette radii.
TIP_CLEARANCE = 1.0 + GAP
#: A tip's distance to the segment before its own (they share the kink point,
#: so the disc need only stay off it). Measured: 1.0 h quality 0.016, 1.02 h
#: 0.23, 1.05 h 0.33; 0.5 h (a wing folding back onto its crack) invalid.
NEIGHBOUR_CLEARANCE = 1.05
#: A tip's rosette radius is at most this fraction of its last segment.
ROSETTE_IN_SEGMENT = 0.75
#: ... and at least this fraction of tip_size (else the segment is too short).
MIN_ROSETTE = 0.1
#: Points of the boundary that become mesh nodes (bc points, crack mouths,
#: corners) coincide (within REL_TOL) or are at least this many tip sizes
#: apart. Measured: a pin 1e-7 m from another (tip_size 0.02) makes a
#: boundary triangle of quality 2e-6 and MUMPS a null pivot; quality grows
#: as distance / size (0.1 at 0.005 m). tip_size is the finest element the
#: mesher makes anywhere else.
ANCHOR_GAP = 1.0


@dataclass(frozen=True)
class Problem:
    """Why a geometry cannot be meshed: the key it is about (``mesh.tip_size``,
    ``fractures[1].points``, ``bc[3].at``) and the reason."""

    key: str
    message: str

    def __str__(self) -> str:
        return f"{self.key}: {self.message}"


class Inadmissible(ValueError):
    """The mesher's refusal of a geometry that breaks a rule of this module."""

    def __init__(self, problem: Problem):
        super().__init__(str(problem))
        self.problem = problem


def require(problem: Problem | None) -> None:
    """Raise Inadmissible for a problem; nothing for None."""
    if problem is not None:
        raise Inadmissible(problem)


@dataclass(frozen=True)
class Rosette:
    """The rosette disc of one crack tip: fracture f, end (0: first point,
    1: last), centre x and radius h."""

    fracture: int
    end: int
    x: np.ndarray
    h: float


def _kernels():
    """The compiled geometry kernels (loaded on first use: `import meshing`
    must stay light)."""
    import wingcrack_kernels

    return wingcrack_kernels


def fracture_key(f: int) -> str:
    return f"fractures[{f}].points"


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
    K = _kernels()
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
    for j in range(1, n - 2):  # the closing edge (n-1 -> 0) against every edge not adjacent to it
        if K.segment_intersection(pts[n - 1], pts[0], pts[j], pts[j + 1], REL_TOL)[0]:
            return Problem(key, f"the polygon intersects itself (edge{n - 1} meets edge{j})")
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


def _strictly_inside(domain, p, tol) -> bool:
    return bool(domain.contains(p)) and not domain.on_boundary(p, tol)


def far_outside(domain, p) -> bool:
    """p outside the domain's bounding box grown by its size: decided without
    the distance computations, whose squares overflow for p ~ 1e200."""
    L = float(domain.length_scale())
    if domain.shape == "disc":
        lo, hi = domain.center - domain.radius, domain.center + domain.radius
    else:
        lo, hi = domain.vertices().min(axis=0), domain.vertices().max(axis=0)
    return bool(np.any(np.asarray(p) < lo - L) or np.any(np.asarray(p) > hi + L))


def fracture(pts: np.ndarray, key: str, domain) -> Problem | None:
    """One pre-existing fracture: inside the domain (only an end may lie on the
    boundary, not both), segments of non-zero length, not crossing itself or
    the boundary."""
    K = _kernels()
    tol = REL_TOL * float(domain.length_scale())
    for i, p in enumerate(pts):
        if far_outside(domain, p):
            return Problem(f"{key}[{i}]", f"({p[0]:g}, {p[1]:g}) is outside the domain")
    seg = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    for i, s in enumerate(seg):
        if s <= tol:
            return Problem(key, f"segment {i} (points {i} and {i + 1}) has zero length")
    if len(pts) > 2 and K.polyline_self_intersects(pts, REL_TOL):
        return Problem(key, "the polyline intersects itself")
    n = len(pts)
    for i, p in enumerate(pts):
        if (i == 0 or i == n - 1) and domain.on_boundary(p, tol):
            continue  # an edge crack's mouth
        if not _strictly_inside(domain, p, tol):
            where = "on the boundary (only an end may be)" if domain.on_boundary(p, tol) else "outside the domain"
            return Problem(f"{key}[{i}]", f"({p[0]:g}, {p[1]:g}) is {where}")
    # Every point inside does not keep a segment inside: a chord between two
    # boundary ends may run along the boundary, and a polygon may be concave.
    for i in range(n - 1):
        if not _strictly_inside(domain, 0.5 * (pts[i] + pts[i + 1]), tol):
            return Problem(key, f"segment {i} runs along or outside the boundary")
    if domain.shape == "polygon":  # rectangles and discs are convex
        poly = domain.vertices()
        m = len(poly)
        for i in range(n - 1):
            for j in range(m):
                hit, _, _, x = K.segment_intersection(pts[i], pts[i + 1], poly[j], poly[(j + 1) % m], REL_TOL)
                if not hit:
                    continue
                x = np.asarray(x)
                at_mouth = (i == 0 and np.linalg.norm(x - pts[0]) <= tol) or (
                    i == n - 2 and np.linalg.norm(x - pts[-1]) <= tol
                )
                if not at_mouth:
                    return Problem(key, f"segment {i} crosses the boundary edge{j}")
    if domain.on_boundary(pts[0], tol) and domain.on_boundary(pts[-1], tol):
        return Problem(key, "both ends lie on the boundary: the fracture cuts the domain in two")
    return None


def fractures_apart(polylines) -> Problem | None:
    """Pre-existing fractures neither cross nor touch (junctions come from growth only)."""
    K = _kernels()
    for i in range(len(polylines)):
        for j in range(i + 1, len(polylines)):
            if K.polylines_intersect(polylines[i], polylines[j], REL_TOL):
                return Problem(fracture_key(j), f"crosses or touches fractures[{i}]")
    return None


def _short(d: float, need: float, digits: int) -> str:
    """d (< need, or <= need) with `digits` digits, or as many more as it takes
    not to read as `need` or beyond ("is 0.0005 m from ..., at least 0.0005 m")."""
    text = f"{d:.{digits}g}"
    while float(text) >= need and d < need and digits < 17:
        digits += 1
        text = f"{d:.{digits}g}"
    return text


def rosette_radius(tip: float, segment: float) -> float:
    """The mesher's rosette radius at a tip whose segment is `segment` long."""
    return min(tip, ROSETTE_IN_SEGMENT * segment)


def free_tips(domain, polylines, tip: float) -> list[Rosette]:
    """The rosettes of the fracture ends not on the boundary (pre-existing
    fractures, which touch nothing: no junctions)."""
    tol = REL_TOL * float(domain.length_scale())
    out = []
    for f, pts in enumerate(polylines):
        for end, (i, j) in ((0, (0, 1)), (1, (-1, -2))):
            if domain.on_boundary(pts[i], tol):
                continue
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
    if polylines:  # every segment at once: (m, 2) ends, fracture and index of each
        a = np.concatenate([p[:-1] for p in polylines])
        ab = np.concatenate([p[1:] for p in polylines]) - a
        owner = np.concatenate([np.full(len(p) - 1, f) for f, p in enumerate(polylines)])
        index = np.concatenate([np.arange(len(p) - 1) for p in polylines])
    for t in tips:
        where = f"the rosette of fractures[{t.fracture}] end {t.end} (radius {t.h:g})"
        if t.h < MIN_ROSETTE * tip:
            seg = t.h / ROSETTE_IN_SEGMENT
            return Problem(fracture_key(t.fracture), f"the segment at end {t.end} ({seg:.3g} m) is too short for a "
                                                     f"tip rosette (tip_size {tip:g})")
        d = float(domain.distance_to_boundary(t.x))
        if d <= TIP_CLEARANCE * t.h + margin:
            return Problem(key, f"{where} reaches the boundary: the tip is {d:.7g} m "
                                f"({_short(d / t.h, TIP_CLEARANCE, 7)} radii) "
                                f"from it, it needs {TIP_CLEARANCE:g} radii")
        if not polylines:
            continue
        u = np.clip(np.einsum("ij,ij->i", t.x - a, ab) / np.einsum("ij,ij->i", ab, ab), 0.0, 1.0)
        d = np.linalg.norm(t.x - a - u[:, None] * ab, axis=1)
        n = len(polylines[t.fracture]) - 1
        mine = owner == t.fracture
        own = mine & (index == (0 if t.end == 0 else n - 1))
        # the segment before its own shares the kink point: the disc must only stay off it
        neighbour = mine & (index == (1 if t.end == 0 else n - 2))
        reach = np.where(neighbour, NEIGHBOUR_CLEARANCE, TIP_CLEARANCE)
        hit = np.flatnonzero((d <= reach * t.h + margin) & ~own)
        if len(hit):
            k = hit[0]
            what = f"segment {index[k]} of its own fracture" if mine[k] else f"fractures[{owner[k]}]"
            return Problem(key, f"{where} reaches {what}: the tip is {d[k]:.7g} m "
                                f"({_short(d[k] / t.h, reach[k], 7)} radii) "
                                f"from it, it needs {reach[k]:g} radii")
    x = np.array([t.x for t in tips], dtype=np.float64).reshape(-1, 2)
    h = np.array([t.h for t in tips], dtype=np.float64)
    for i in range(len(tips) - 1):
        d = np.linalg.norm(x[i + 1:] - x[i], axis=1)
        need = rosettes_apart(h[i], h[i + 1:])
        hit = np.flatnonzero(d <= need + margin)
        if len(hit):
            k = hit[0]
            s, t = tips[i], tips[i + 1 + k]
            return Problem(key, f"the rosettes of fractures[{s.fracture}] end {s.end} and fractures[{t.fracture}] "
                                f"end {t.end} (radii {s.h:g}, {t.h:g}) overlap: the tips are {d[k]:.6g} m apart, "
                                f"they need more than {need[k]:.6g} m")
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
    K = _kernels()
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
    for f, pts in enumerate(polylines):
        for i in (0, len(pts) - 1):
            if domain.on_boundary(pts[i], tol):
                named.append((np.asarray(pts[i], dtype=np.float64), f"{fracture_key(f)}[{i}]",
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
            return Problem(key, f"({p[0]:.10g}, {p[1]:.10g}) is {_short(d[k], gap, 3)} m from {what}: boundary points that "
                                f"become mesh nodes coincide or lie at least {ANCHOR_GAP:g} tip_size "
                                f"({gap:g} m) apart")
    return None


def case_geometry(domain, polylines, points, point_keys, tip: float) -> Problem | None:
    """Everything the mesher needs of a case's initial geometry beyond each
    part alone: rosettes that fit, boundary nodes apart."""
    margin = 4 * REL_TOL * float(domain.length_scale())
    return (segments_hold_rosettes(polylines, tip)
            or rosettes(domain, polylines, free_tips(domain, polylines, tip), tip, margin=margin)
            or anchors_apart(domain, points, point_keys, polylines, tip))

