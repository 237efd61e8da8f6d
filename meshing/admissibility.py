"""What geometry can be meshed: the one set of rules that `wingcrack check`
(wingcrack/case.py), the mesher (meshing/mesher.py), meshing.Domain and
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

Pure numpy, scipy and the compiled kernels; never the `wingcrack` package.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from meshing import network

#: Relative tolerance (times the domain's length scale) for "on the
#: boundary", "touching" and "zero length".
REL_TOL = 1e-9
#: The domain sizes (m across) the mesher and solver take. The mesher hands
#: gmsh the geometry in a frame where the domain is 1e-3 to 1e3 units across
#: (frame.Frame): gmsh alone fails to recover edges ("Unable to
#: recover the edge", then aborts) at 6e-9 m and below.
LENGTH_RANGE = (1e-9, 1e9)
#: Coordinates at most this many domain sizes from the origin: beyond it the
#: rounding of a coordinate (|x| 2.2e-16) nears the geometric tolerance REL_TOL.
#: (gmsh itself sees the domain near its origin: frame.Frame.)
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
#: The least angle (degrees) between two fractures where they meet (an X, a
#: T, ends met end to end): every sector between two neighbouring fracture
#: rays at a junction is at least this wide. The worst cell of a sector of
#: angle a is the isosceles triangle at its apex, of quality
#: sqrt(3) sin a / (1 + 2 sin^2(a/2)); measured (an X, a T and a V at the
#: mesher's defaults): 20 deg 0.51, 15 deg 0.42, 10 deg 0.30, 5 deg 0.15,
#: 1 deg 0.03, 0.1 deg 0.003. 15 degrees keeps the sector's cells above
#: the rosette's own (0.33 at the default 32 sectors).
MIN_JUNCTION_ANGLE = 15.0
#: Points where fractures meet (junctions) coincide (REL_TOL) or keep this
#: many tip sizes from each other, from the boundary, from the vertices next
#: to them along the fractures through them and from the fractures not
#: through them (tip_size is the finest element the mesher makes away from
#: the rosettes). Measured: the worst cell's quality falls as distance /
#: tip_size below half a tip size (two X's 0.3 tip sizes apart 0.26, an X
#: 0.1 tip sizes from the boundary 0.08, 0.01 from a third fracture 0.005);
#: from 1 tip size on it is that of the mesh away from junctions (0.60 to
#: 0.72). The value of ANCHOR_GAP, for the same reason.
JUNCTION_GAP = 1.0
#: A fracture end that is no junction keeps at least this many tip sizes
#: from every fracture it does not lie on (to REL_TOL): an end nearer reads
#: as a junction missed by a little and is refused as such (a tip there
#: would be refused anyway: its rosette keeps TIP_CLEARANCE radii from
#: every other fracture).
NEAR_MISS = 0.1


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
    K = _kernels()
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
        if K.polyline_self_intersects(ring, REL_TOL) or any(
                K.segment_intersection(pts[-2], pts[-1], pts[j], pts[j + 1], REL_TOL)[0] for j in range(1, n - 3)):
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
    return None


# ---------------------------------------------------------------- how fractures meet


def _ends(domain, polylines):
    """(free ends, mouths): the (f, end) strictly inside the domain and those on its boundary."""
    tol = REL_TOL * float(domain.length_scale())
    ends = [(f, end) for f in range(len(polylines)) for end in (0, 1)]
    x = np.array([polylines[f][0 if end == 0 else -1] for f, end in ends], dtype=np.float64).reshape(-1, 2)
    on = np.atleast_1d(domain.on_boundary(x, tol)) if len(x) else np.zeros(0, bool)
    return [e for e, o in zip(ends, on) if not o], [e for e, o in zip(ends, on) if o]


def joined(domain, polylines) -> network.Joined:
    """The fractures as the mesher joins them (network.join): junction points
    inserted, the ends that lie on a fracture, the points where they meet."""
    free, mouths = _ends(domain, polylines)
    return network.join(polylines, free, REL_TOL * float(domain.length_scale()), mouths=mouths)


def joined_ends(domain, polylines) -> dict:
    """(f, end) -> the fracture it met, for every fracture end that lies on a
    fracture (a T-junction, or end to end): no tip."""
    return joined(domain, polylines).joined_ends()


def _point_key(f: int, vertex: int, counts) -> str:
    """The case key of vertex `vertex` of fracture f's joined polyline when it
    is one of its given points (an end), else the fracture's key."""
    if vertex == 0:
        return f"{fracture_key(f)}[0]"
    if counts is not None and vertex == counts[f][1] - 1:
        return f"{fracture_key(f)}[{counts[f][0] - 1}]"
    return fracture_key(f)


def joins(net: network.Joined, sizes=None) -> Problem | None:
    """What no mesh holds, in fractures as joined (network.join): segments of
    two fractures along a common stretch (their faces would be one), and a
    fracture meeting another at its mouth on the boundary. sizes: the number
    of given points of each fracture, for the keys (None: the joined ones)."""
    for f, g, p, q in net.overlaps:
        i, j = sorted((f, g))
        what = "itself" if i == j else f"fractures[{i}]"
        return Problem(fracture_key(j), f"runs along {what} from ({p[0]:.6g}, {p[1]:.6g}) to ({q[0]:.6g}, "
                                        f"{q[1]:.6g}): fractures may cross or meet at points, not overlap")
    for f, end, g in sorted(net.mouths, reverse=True)[:1]:   # named by the last fracture's mouth
        n = len(net.polylines[f]) if sizes is None else sizes[f]
        p = net.polylines[f][0 if end == 0 else -1]
        return Problem(f"{fracture_key(f)}[{0 if end == 0 else n - 1}]",
                       f"the end ({p[0]:.6g}, {p[1]:.6g}) on the boundary lies on fractures[{g}]: fractures "
                       "may meet inside the domain, not on its boundary")
    return None


def _rays(net: network.Joined, members):
    """[(angle, fracture, vertex, is its segment before)] of the fracture
    segments leaving a node (members: its [(f, vertex)])."""
    import math

    out = []
    for f, v in members:
        pts = net.polylines[f]
        x = pts[v]
        for w, before in ((v - 1, True), (v + 1, False)):
            if 0 <= w < len(pts):
                d = pts[w] - x
                out.append((math.atan2(d[1], d[0]), f, v, before))
    return sorted(out)


def junction_angles(net: network.Joined) -> Problem | None:
    """At every point where fractures meet, each sector between two
    neighbouring fracture rays at least MIN_JUNCTION_ANGLE wide (the two
    segments of one polyline at its own vertex excepted: a kink is the
    polyline's own, as it is away from junctions)."""
    import math

    least = math.radians(MIN_JUNCTION_ANGLE)
    for members in net.nodes.values():
        rays = _rays(net, members)
        for k in range(len(rays)):
            a, b = rays[k], rays[(k + 1) % len(rays)]
            gap = (b[0] - a[0]) % (2 * math.pi)
            if gap >= least or (a[1] == b[1] and a[2] == b[2]):
                continue
            x = net.polylines[members[0][0]][members[0][1]]
            f, g = sorted((a[1], b[1]))
            other = "itself" if f == g else f"fractures[{f}]"
            return Problem(fracture_key(g), f"meets {other} at ({x[0]:.6g}, {x[1]:.6g}) at "
                                            f"{_short(math.degrees(gap), MIN_JUNCTION_ANGLE, 3)} degrees: "
                                            f"fractures meet at {MIN_JUNCTION_ANGLE:g} degrees or more (the cells "
                                            "between two fractures at a smaller angle are slivers)")
    return None


def fractures_meet(domain, polylines) -> Problem | None:
    """Pre-existing fractures may cross and touch (X, T, end to end, several
    at one point, closed loops): refused are common stretches, meetings on
    the boundary and junction angles under MIN_JUNCTION_ANGLE."""
    net = joined(domain, polylines)
    return joins(net, [len(p) for p in polylines]) or junction_angles(net)


def _vertex_counts(polylines, net):
    """(given points, joined points) of each fracture."""
    return [(len(p), len(q)) for p, q in zip(polylines, net.polylines)]


def junctions_apart(domain, net: network.Joined, polylines, tip: float, margin: float = 0.0) -> Problem | None:
    """Points where fractures meet keep JUNCTION_GAP tip sizes from each
    other, from the boundary, from the vertices next to them along each
    fracture through them and from every fracture segment not through them."""
    nodes = net.node_points()
    if not len(nodes):
        return None
    gap = JUNCTION_GAP * tip
    counts = _vertex_counts(polylines, net)
    members = list(net.nodes.values())

    def where(k):   # named by the last fracture through it
        f, v = max(members[k])
        return _point_key(f, v, counts), nodes[k]

    d = np.atleast_1d(domain.distance_to_boundary(nodes))
    near = np.flatnonzero(d < gap + margin)
    if len(near):
        key, x = where(int(near[0]))
        return Problem(key, f"fractures meet at ({x[0]:.6g}, {x[1]:.6g}), {_short(float(d[near[0]]), gap, 3)} m from "
                            f"the boundary: a junction keeps at least {JUNCTION_GAP:g} tip_size ({gap:g} m) from it")
    from scipy.spatial import cKDTree

    pairs = cKDTree(nodes).query_pairs(gap + margin, output_type="ndarray") if len(nodes) > 1 else ()
    if len(pairs):
        i, j = min((int(min(p)), int(max(p))) for p in pairs)
        key, x = where(j)
        y = nodes[i]
        dist = float(np.linalg.norm(x - y))
        return Problem(key, f"fractures meet at ({x[0]:.6g}, {x[1]:.6g}) and at ({y[0]:.6g}, {y[1]:.6g}), "
                            f"{_short(dist, gap, 3)} m apart: junctions coincide or lie at least {JUNCTION_GAP:g} "
                            f"tip_size ({gap:g} m) apart")
    for k, group in enumerate(members):
        for f, v in group:
            pts = net.polylines[f]
            for w in (v - 1, v + 1):
                if 0 <= w < len(pts):
                    dist = float(np.linalg.norm(pts[w] - pts[v]))
                    if dist < gap + margin:
                        x = pts[v]
                        return Problem(_point_key(f, w, counts),
                                       f"({pts[w][0]:.6g}, {pts[w][1]:.6g}) is {_short(dist, gap, 3)} m along "
                                       f"fractures[{f}] from where fractures meet at ({x[0]:.6g}, {x[1]:.6g}): "
                                       f"a junction keeps at least {JUNCTION_GAP:g} tip_size ({gap:g} m) from the "
                                       "points next to it")
    a, b, owner, _ = network.segments(net.polylines)
    pt, sg = network.segments_near_points(nodes, gap + margin, a, b)
    through = np.all(a[sg] == nodes[pt], axis=1) | np.all(b[sg] == nodes[pt], axis=1)
    pt, sg = pt[~through], sg[~through]
    dist, _ = network.point_segment(nodes[pt], a[sg], b[sg])
    hit = np.flatnonzero(dist < gap + margin)
    if len(hit):
        h = hit[0]
        key, x = where(int(pt[h]))
        return Problem(key, f"fractures meet at ({x[0]:.6g}, {x[1]:.6g}), {_short(float(dist[h]), gap, 3)} m from "
                            f"fractures[{owner[sg[h]]}] without it: a junction keeps at least {JUNCTION_GAP:g} "
                            f"tip_size ({gap:g} m) from the fractures not through it")
    return None


def ends_on_or_apart(domain, net: network.Joined, polylines, tip: float) -> Problem | None:
    """An end that is no junction lies NEAR_MISS tip sizes or more from every
    fracture (beyond its own segment and the one before): nearer, it reads
    as a junction missed by a little, which the mesher would take as a tip
    with a rosette squeezed against the other fracture."""
    free, _ = _ends(domain, polylines)
    ends = [fe for fe in free if fe not in net.partner]
    if not ends:
        return None
    tol = REL_TOL * float(domain.length_scale())
    p = np.array([net.polylines[f][0 if e == 0 else -1] for f, e in ends])
    a, b, owner, index = network.segments(net.polylines)
    pt, sg = network.segments_near_points(p, NEAR_MISS * tip, a, b)
    f_of = np.array([f for f, _ in ends])[pt]
    e_of = np.array([e for _, e in ends])[pt]
    n = np.array([len(q) - 1 for q in net.polylines])[owner[sg]]
    own = (owner[sg] == f_of) & np.where(e_of == 0, index[sg] <= 1, index[sg] >= n - 2)
    pt, sg = pt[~own], sg[~own]
    dist, _ = network.point_segment(p[pt], a[sg], b[sg])
    hit = np.flatnonzero(dist < NEAR_MISS * tip)
    if not len(hit):
        return None
    h = hit[0]
    f, e = ends[int(pt[h])]
    x = p[pt[h]]
    i = 0 if e == 0 else len(polylines[f]) - 1
    return Problem(f"{fracture_key(f)}[{i}]", f"the end ({x[0]:.10g}, {x[1]:.10g}) is {float(dist[h]):.3g} m from "
                                              f"fractures[{owner[sg[h]]}]: an end on a fracture lies on it (within "
                                              f"{tol:.3g} m: a T-junction), a free end keeps {TIP_CLEARANCE:g} "
                                              "rosette radii from it")


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


def free_tips(domain, polylines, tip: float, net: network.Joined | None = None) -> list[Rosette]:
    """The rosettes of the fracture ends that are tips: not on the boundary,
    not on a fracture (net: the fractures joined, joined() when None; the
    radius from the end's segment there, as the mesher has it)."""
    net = joined(domain, polylines) if net is None else net
    free, _ = _ends(domain, net.polylines)
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
                                f"({_short(dk / t.h, TIP_CLEARANCE, 7)} radii) "
                                f"from it, it needs {TIP_CLEARANCE:g} radii")
        if k in seg_hit:
            dk, s, rk, own_fracture = seg_hit[k]
            what = f"segment {index[s]} of its own fracture" if own_fracture else f"fractures[{owner[s]}]"
            return Problem(key, f"{where} reaches {what}: the tip is {dk:.7g} m "
                                f"({_short(dk / t.h, rk, 7)} radii) "
                                f"from it, it needs {rk:g} radii")
    if len(tips) > 1:
        from scipy.spatial import cKDTree

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
    for f, end in _ends(domain, polylines)[1]:
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
            return Problem(key, f"({p[0]:.10g}, {p[1]:.10g}) is {_short(d[k], gap, 3)} m from {what}: boundary points that "
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

