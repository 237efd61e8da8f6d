"""The rules of how fractures meet (meshing.admissibility's part on
junctions): what no mesh holds (a common stretch, a meeting on the
boundary), and what makes poor cells (junction angles, junctions too near
each other, the boundary or a vertex, an end a hair off a fracture). The
fractures are joined as the mesher joins them (meshing/network.py)."""
from __future__ import annotations

import math

import numpy as np
from scipy.spatial import cKDTree

from meshing import network
from meshing.rules import (JUNCTION_GAP, MIN_JUNCTION_ANGLE, NEAR_MISS, REL_TOL, TIP_CLEARANCE, Problem,
                           fracture_key, short_of)


def fracture_ends(domain, polylines):
    """(free ends, mouths): the (f, end) strictly inside the domain and those on its boundary."""
    tol = REL_TOL * float(domain.length_scale())
    ends = [(f, end) for f in range(len(polylines)) for end in (0, 1)]
    x = np.array([polylines[f][0 if end == 0 else -1] for f, end in ends], dtype=np.float64).reshape(-1, 2)
    on = np.atleast_1d(domain.on_boundary(x, tol)) if len(x) else np.zeros(0, bool)
    return [e for e, o in zip(ends, on) if not o], [e for e, o in zip(ends, on) if o]


def joined(domain, polylines) -> network.Joined:
    """The fractures as the mesher joins them (network.join): junction points
    inserted, the ends that lie on a fracture, the points where they meet."""
    free, mouths = fracture_ends(domain, polylines)
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
                                            f"{short_of(math.degrees(gap), MIN_JUNCTION_ANGLE, 3)} degrees: "
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
        return Problem(key, f"fractures meet at ({x[0]:.6g}, {x[1]:.6g}), {short_of(float(d[near[0]]), gap, 3)} m from "
                            f"the boundary: a junction keeps at least {JUNCTION_GAP:g} tip_size ({gap:g} m) from it")
    pairs = cKDTree(nodes).query_pairs(gap + margin, output_type="ndarray") if len(nodes) > 1 else ()
    if len(pairs):
        i, j = min((int(min(p)), int(max(p))) for p in pairs)
        key, x = where(j)
        y = nodes[i]
        dist = float(np.linalg.norm(x - y))
        return Problem(key, f"fractures meet at ({x[0]:.6g}, {x[1]:.6g}) and at ({y[0]:.6g}, {y[1]:.6g}), "
                            f"{short_of(dist, gap, 3)} m apart: junctions coincide or lie at least {JUNCTION_GAP:g} "
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
                                       f"({pts[w][0]:.6g}, {pts[w][1]:.6g}) is {short_of(dist, gap, 3)} m along "
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
        return Problem(key, f"fractures meet at ({x[0]:.6g}, {x[1]:.6g}), {short_of(float(dist[h]), gap, 3)} m from "
                            f"fractures[{owner[sg[h]]}] without it: a junction keeps at least {JUNCTION_GAP:g} "
                            f"tip_size ({gap:g} m) from the fractures not through it")
    return None


def ends_on_or_apart(domain, net: network.Joined, polylines, tip: float) -> Problem | None:
    """An end that is no junction lies NEAR_MISS tip sizes or more from every
    fracture (beyond its own segment and the one before): nearer, it reads
    as a junction missed by a little, which the mesher would take as a tip
    with a rosette squeezed against the other fracture."""
    free, _ = fracture_ends(domain, polylines)
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
