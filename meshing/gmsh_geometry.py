"""The gmsh geometry of a mesh: the outer boundary split at the anchors,
the tips' rosettes, the fracture curves, the divider of a point-symmetric
half; mesh_with_gmsh builds and meshes the whole domain (or its half) in
the current gmsh session. patch.py builds a patched mesh from the same
pieces."""

from __future__ import annotations

import math

import numpy as np

from meshing import point_symmetry
from meshing.domain import Domain
from meshing.p2_readback import extract, rim
from meshing.plan import ON_BOUNDARY, Plan
from meshing.records import RawMesh
from meshing.size_field import size_field


def mesh_with_gmsh(domain, plan: Plan, size, tip_size, sectors, sizes, algorithm, half=None,
                   mirror_sizes=False, scratch=None) -> RawMesh:
    """The mesh of the whole domain, or with `half` (a point_symmetry.Half) of
    the half on the left of the divider only; the other half's tips and crack
    curves are then free geometry that only shapes the size field. scratch: a
    directory for the size grid file (needed when `sizes` is given)."""
    import gmsh  # 0.6 s: loaded by the first mesh (worker.load_gmsh), never by check

    geo = gmsh.model.geo
    gmsh.model.add("wingcrack")
    meshed = (lambda x: True) if half is None else half.left

    anchor_tag, boundary_curves = outer_curves(geo, domain, plan, half)
    outer = [c for c, _ in boundary_curves]

    # Rosettes: one transfinite triangle per sector, spoke 0 along the crack.
    rosettes, holes = [], []
    tip_point, spoke_on_crack = [None] * len(plan.tips), [None] * len(plan.tips)
    tip_of = {(t.fracture, t.end): k for k, t in enumerate(plan.tips)}
    for k, t in enumerate(plan.tips):   # the other half's tips: a point for the size field only
        loops, hole = rosette_curves(geo, t, sectors, meshed, tip_point, spoke_on_crack, k)
        rosettes += [(geo.addPlaneSurface([loop]), corners) for loop, corners in loops]
        if hole is not None:
            holes.append(hole)

    # Fracture curves outside the rosettes, in order along each fracture.
    # Vertex tags first (a T-junction end takes its host's vertex), then lines.
    vertex_tags, curves_of = {}, {}
    embedded, elsewhere = fracture_curves(geo, plan, range(len(plan.fractures)), anchor_tag, tip_of, tip_point,
                                          spoke_on_crack, meshed, vertex_tags, curves_of, {})
    crack_curves = [c for f in range(len(plan.fractures)) for c in curves_of[f]]  # (curve, fracture, d)

    divider: list[int] = []
    if half is not None:  # from R(p) through the crossings and the centre to p
        tags = [vertex_at(plan, anchor_tag, vertex_tags, geo, q) for q in half.points]
        divider = [geo.addLine(a, b) for a, b in zip(tags[:-1], tags[1:])]
        outer += divider
    surface = geo.addPlaneSurface([geo.addCurveLoop(outer)] + holes)
    for s, corners in rosettes:
        geo.mesh.setTransfiniteSurface(s, "Left", list(corners))
    geo.synchronize()
    if half is not None:
        mirror_dividers(half, [divider])
    if embedded:
        gmsh.model.mesh.embed(1, embedded, 2, surface)

    size_field(plan, [centre for centre, _ in tip_point], embedded + elsewhere, size, tip_size, sectors,
               sizes, half.center if mirror_sizes else None, box(domain), scratch)
    gmsh.option.setNumber("Mesh.Algorithm", algorithm)
    gmsh.model.mesh.generate(2)
    points = point_tags(plan, anchor_tag, half)
    return extract(boundary_curves, crack_curves, tip_point, points, divider, rim=rim(domain, boundary_curves))


def point_tags(plan, anchor_tag, half) -> list[int]:
    """The point tag of each bc point (plan.point_anchor's order); with
    `half`, a bc point of the other half gets the point of its image, whose
    node mesher._glue maps back."""
    points = [anchor_tag[a] for a in plan.point_anchor]
    if half is not None:
        points = [tag if half.left(plan.anchors[a][2]) else
                  anchor_at(plan, anchor_tag, point_symmetry.rotate(plan.anchors[a][2], half.center))
                  for tag, a in zip(points, plan.point_anchor)]
    return points


def rosette_curves(geo, t, sectors, meshed, tip_point, spoke, k):
    """The points and curves of tip t's rosette (as mesh_with_gmsh builds
    them) and its sectors' loops [(loop, corners)], the surfaces left to the
    caller; fills tip_point[k], spoke[k]. Returns (loops, hole loop), the
    hole None (and no loops) for a tip not meshed here."""
    centre = geo.addPoint(t.x[0], t.x[1], 0.0)
    if not meshed(t.x):
        tip_point[k] = (centre, None)
        return [], None
    phi0 = math.atan2(t.back[1], t.back[0])
    ring_pts = []
    for j in range(sectors):
        phi = phi0 + 2.0 * math.pi * j / sectors
        p = t.x + t.h * (t.back if j == 0 else np.array([math.cos(phi), math.sin(phi)]))
        ring_pts.append(geo.addPoint(p[0], p[1], 0.0))
    spokes = [geo.addLine(centre, q) for q in ring_pts]
    chords = [geo.addLine(ring_pts[j], ring_pts[(j + 1) % sectors]) for j in range(sectors)]
    loops = [(geo.addCurveLoop([spokes[j], chords[j], -spokes[(j + 1) % sectors]]),
              (centre, ring_pts[j], ring_pts[(j + 1) % sectors])) for j in range(sectors)]
    for cv in spokes + chords:
        geo.mesh.setTransfiniteCurve(cv, 2)
    tip_point[k] = (centre, ring_pts[0])
    spoke[k] = spokes[0]
    return loops, geo.addCurveLoop(chords)


def fracture_curves(geo, plan, group, anchor_tag, tip_of, tip_point, spoke, meshed, vertex_tags, curves_of,
                    shared):
    """The crack curves of the fractures in `group` (as mesh_with_gmsh builds
    them): fills vertex_tags[f] and curves_of[f] ([(curve, f, d)] in order
    along f, the rosettes' spokes on the crack included), and shared (the
    bits of a vertex's coordinates -> its point tag: vertices of several
    fractures at one place are one point); returns (curves to embed, the
    other half's curves)."""
    for f in group:
        pts = plan.fractures[f]
        tags = [0] * len(pts)
        for end, i in ((0, 0), (1, len(pts) - 1)):
            if (f, end) in plan.mouth_anchor:
                tags[i] = anchor_tag[plan.mouth_anchor[(f, end)]]
            elif (f, end) in tip_of and spoke[tip_of[(f, end)]] is not None:
                tags[i] = tip_point[tip_of[(f, end)]][1]
        joined = {0 if end == 0 else len(pts) - 1 for (g, end) in plan.junction if g == f}
        for i in range(len(pts)):
            if not tags[i] and i not in joined:
                # one point where vertices of several fractures coincide (an X: network.join
                # gave them the same bits)
                key = pts[i].tobytes()
                if key not in shared:
                    shared[key] = geo.addPoint(pts[i][0], pts[i][1], 0.0)
                tags[i] = shared[key]
        vertex_tags[f] = tags
    for (f, end), (g, vertex) in plan.junction.items():
        if f in group:  # a junction joins fractures of one side (they touch)
            vertex_tags[f][0 if end == 0 else -1] = vertex_tags[g][vertex]
    embedded, elsewhere = [], []
    for f in group:
        pts, tags, own = plan.fractures[f], vertex_tags[f], []
        if (f, 0) in tip_of and spoke[tip_of[(f, 0)]] is not None:
            own.append((spoke[tip_of[(f, 0)]], f, pts[1] - pts[0]))
        for s in range(len(pts) - 1):
            line = geo.addLine(tags[s], tags[s + 1])
            if meshed(0.5 * (pts[s] + pts[s + 1])):
                own.append((line, f, pts[s + 1] - pts[s]))
                embedded.append(line)
            else:
                elsewhere.append(line)
        if (f, 1) in tip_of and spoke[tip_of[(f, 1)]] is not None:
            own.append((spoke[tip_of[(f, 1)]], f, pts[-1] - pts[-2]))
        curves_of[f] = own
    return embedded, elsewhere


def vertex_at(plan, anchor_tag, vertex_tags, geo, q) -> int:
    """The point tag at divider vertex q: an anchor (its ends), a fracture
    vertex built so far (vertex_tags: f -> tags; a crossing, inserted with
    q's coordinates), or a new point (the centre off every fracture)."""
    for k, (_, _, a) in enumerate(plan.anchors):
        if np.array_equal(a, q):
            return anchor_tag[k]
    for f, tags in vertex_tags.items():
        hit = np.flatnonzero(np.all(plan.fractures[f] == q, axis=1))
        if len(hit):
            return tags[int(hit[0])]
    return geo.addPoint(q[0], q[1], 0.0)


def mirror_dividers(half, dividers) -> None:
    """Each divider's second half mirrors its first, node for node (gmsh
    periodic curves under the half turn about the centre)."""
    import gmsh  # 0.6 s: loaded by the first mesh (worker.load_gmsh), never by check

    cx, cy = half.center
    turn = [-1.0, 0.0, 0.0, 2.0 * cx, 0.0, -1.0, 0.0, 2.0 * cy, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0]
    for divider in dividers:
        for k in range(len(divider) // 2):
            gmsh.model.mesh.setPeriodic(1, [divider[len(divider) - 1 - k]], [divider[k]], turn)


def outer_curves(geo, domain, plan: Plan, half) -> tuple[list[int], list[tuple[int, str]]]:
    """The outer boundary in gmsh: the anchors' point tags and the boundary
    curves [(curve, name)] counter-clockwise, all of them, or with `half`
    those from the divider's end p to its other end R(p)."""
    anchor_tag = [geo.addPoint(p[0], p[1], 0.0) for _, _, p in plan.anchors]
    ring = _boundary_ring(domain, plan, geo, anchor_tag)  # [(point tag, name of the curve after it)]
    center = geo.addPoint(*domain.center, 0.0) if domain.shape == "disc" else None
    if half is None:
        pieces = list(zip(ring, ring[1:] + ring[:1]))
    else:
        tags = [tag for tag, _ in ring]
        start = tags.index(anchor_at(plan, anchor_tag, half.points[-1]))
        stop = tags.index(anchor_at(plan, anchor_tag, half.points[0]))
        arc = ring[start:] + ring[:start]
        arc = arc[: (stop - start) % len(ring) + 1]
        pieces = list(zip(arc[:-1], arc[1:]))
    boundary_curves = []
    for (a, name), (b, _) in pieces:
        curve = geo.addCircleArc(a, center, b) if center is not None else geo.addLine(a, b)
        boundary_curves.append((curve, name))
    return anchor_tag, boundary_curves


def _boundary_ring(domain, plan, geo, anchor_tag) -> list[tuple[int, str]]:
    """The outer boundary's points counter-clockwise, each with the name of the
    boundary curve that starts at it (a disc's arcs are filled to <= pi/2)."""
    if domain.shape == "disc":
        angles = [(t, tag) for (_, t, _), tag in zip(plan.anchors, anchor_tag)]
        return [(tag, "rim") for _, tag in _fill_arc_gaps(sorted(angles), domain, geo)]
    corners, names = domain.vertices(), domain.edge_names()
    tol = ON_BOUNDARY * domain.length_scale()
    ring = []
    for i, corner in enumerate(corners):
        on_corner = [k for k, (_, _, p) in enumerate(plan.anchors) if np.linalg.norm(p - corner) <= tol]
        ring.append((anchor_tag[on_corner[0]] if on_corner else geo.addPoint(*corner, 0.0), names[i]))
        inner = sorted(
            (t, anchor_tag[k])
            for k, (e, t, p) in enumerate(plan.anchors)
            if e == i and k not in on_corner and np.linalg.norm(p - corners[(i + 1) % len(corners)]) > tol
        )
        ring.extend((tag, names[i]) for _, tag in inner)
    return ring


def anchor_at(plan, anchor_tag, p) -> int:
    k = int(np.argmin([np.linalg.norm(a - p) for _, _, a in plan.anchors]))
    return anchor_tag[k]


def _fill_arc_gaps(angles, domain, geo):
    """Circle arcs must be shorter than pi: add rim points so that no arc spans
    more than pi/2. angles: sorted [(angle, point tag)]; returns the same, filled."""
    if not angles:
        angles = [(-math.pi, _rim_point(-math.pi, domain, geo))]
    out = []
    for i, (t, tag) in enumerate(angles):
        out.append((t, tag))
        t_next = angles[(i + 1) % len(angles)][0] + (2.0 * math.pi if i == len(angles) - 1 else 0.0)
        n = max(1, math.ceil((t_next - t) / (0.5 * math.pi) - 1e-9))
        out.extend((s, _rim_point(s, domain, geo)) for s in (t + (t_next - t) * j / n for j in range(1, n)))
    return out


def _rim_point(angle, domain, geo) -> int:
    p = domain.center + domain.radius * np.array([math.cos(angle), math.sin(angle)])
    return geo.addPoint(p[0], p[1], 0.0)


def box(domain: Domain) -> tuple[np.ndarray, np.ndarray]:
    """The domain's bounding box (lo, hi)."""
    if domain.shape == "disc":
        return domain.center - domain.radius, domain.center + domain.radius
    v = domain.vertices()
    return v.min(axis=0), v.max(axis=0)
