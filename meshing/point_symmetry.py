"""Point-symmetric meshes for point-symmetric crack geometries.

When the domain, the fractures and the tips map onto themselves under the
half turn R(x) = 2c - x about the domain's centre c (the cracked Brazilian
disc, a centre-cracked plate, the paper's 4.3 layout), an unstructured mesh
of the whole domain still breaks the symmetry: the two tips see slightly
different meshes and a symmetric problem grows slightly unsymmetric wings
(their tips part by a few thousandths of a step within ten steps).

Here a straight divider through c cuts the domain into two halves; gmsh
meshes the half on the left of the divider only (the divider's second half is
a periodic copy of its first, so the divider's nodes mirror), and the other
half is the exact image R of the first. The glued mesh maps onto itself node
for node, so the discrete solution, the SIFs, the kinks and the next
geometry are point-symmetric to round-off.

With a patch circle about the centre (crack_mesh's `patch`) the divider
has two parts, one outside the circle chosen from what lies outside only
and one inside (Inner), both ending on nodes of the circle: the far field's
half stays the same whatever the fractures inside do to the divider there.

Pure numpy: the geometry tests (is it symmetric, where may the divider go),
the insertion of the divider's crossings into the fractures, and the gluing
of the meshed half to its image.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from meshing.records import RawMesh

#: directions tried for the divider (degrees, from the x axis)
CANDIDATES = np.deg2rad(np.arange(0.0, 180.0, 1.0) + 0.5)
#: the divider stays this many tip sizes away from every tip (rosette radius <= 1 tip size)
TIP_CLEARANCE = 3.0
#: a crossing of the divider and a fracture is this many tip sizes from the fracture's vertices
VERTEX_CLEARANCE = 0.5
#: the divider's ends stay this many tip sizes from every bc point, crack mouth and corner
ANCHOR_CLEARANCE = 1.0
#: sine of the smallest angle allowed between the divider and a fracture it crosses
MIN_CROSSING_SINE = math.sin(math.radians(30.0))


def rotate(x, c) -> np.ndarray:
    """R(x) = 2c - x, for one point (2,) or many (n, 2)."""
    return 2.0 * np.asarray(c, dtype=np.float64) - np.asarray(x, dtype=np.float64)


@dataclass
class Inner:
    """The divider inside a patch circle (crack_mesh's `patch`): a diameter of
    its own, so that the divider outside (Half.u, chosen from what lies
    outside the circle only) stays the same whatever the fractures inside."""

    radius: float
    u: np.ndarray  # direction; inside the circle gmsh meshes the half on its left
    k: int  # the circle node at c + radius u (patch.Circle.points)
    points: np.ndarray  # (2j+1, 2) vertices from R(c + radius u) to c + radius u: crossings, centre
    angle: float


@dataclass
class Half:
    """The divider of a point-symmetric geometry and what R maps onto what."""

    center: np.ndarray
    u: np.ndarray  # divider direction; gmsh meshes the half on its left
    # (2k+1, 2) divider vertices from R(p) to p: ends, crossings, centre. With
    # a patch (inner): (2k+2, 2), no centre: R(p), crossings, R(q), q, crossings,
    # p, where q = c + radius u is circle node k_out; the part between R(q)
    # and q is no divider (inner's is).
    points: np.ndarray
    fracture_image: list[tuple[int, bool]]  # f -> (g, reversed): R(fracture f) is fracture g
    angle: float  # of u, radians
    inner: Inner | None = None
    k_out: int = -1

    def left(self, x) -> np.ndarray | bool:
        """True for points strictly on the meshed side (inside a patch circle:
        on the left of the inner divider)."""
        d = np.asarray(x, dtype=np.float64) - self.center
        s = self.u[0] * d[..., 1] - self.u[1] * d[..., 0]
        if self.inner is None:
            return s > 0.0
        u = self.inner.u
        inside = np.hypot(d[..., 0], d[..., 1]) < self.inner.radius
        out = np.where(inside, u[0] * d[..., 1] - u[1] * d[..., 0] > 0.0, s > 0.0)
        return bool(out) if out.ndim == 0 else out

    def crossings(self) -> list[np.ndarray]:
        """The divider's inner vertices (where it may cross fractures)."""
        out = list(self.points[1:-1])
        if self.inner is not None:
            out += list(self.inner.points[1:-1])
        return out


def domain_center(domain) -> np.ndarray | None:
    """The centre of a point-symmetric domain, None when it has none."""
    if domain.shape == "disc":
        return np.array(domain.center, dtype=np.float64)
    if domain.shape == "rectangle":
        return np.asarray(domain.corner, dtype=np.float64) + 0.5 * np.asarray(domain.size, dtype=np.float64)
    v = domain.vertices()
    n = len(v)
    if n % 2:
        return None
    c = v.mean(axis=0)
    if np.max(np.linalg.norm(rotate(v, c) - np.roll(v, -n // 2, axis=0), axis=1)) > 1e-9 * domain.length_scale():
        return None
    return c


def fracture_images(polylines, c, tol) -> list[tuple[int, bool]] | None:
    """For every fracture f, (g, reversed) with R(points of f) = points of g
    (in reverse order when reversed); None when some fracture has no image."""
    out = []
    for f, pts in enumerate(polylines):
        image = rotate(pts, c)
        found = None
        for g, other in enumerate(polylines):
            if len(other) != len(pts):
                continue
            for rev in (True, False):
                cand = other[::-1] if rev else other
                if np.max(np.linalg.norm(image - cand, axis=1)) <= tol:
                    found = (g, rev)
                    break
            if found:
                break
        if found is None:
            return None
        out.append(found)
    for f, (g, rev) in enumerate(out):  # R is an involution
        if out[g] != (f, rev):
            return None
    return out


def _symmetric(domain, polylines, tips, anchors):
    """(centre, tolerance, fracture images, tip positions (t, 2), points a
    divider must keep clear of) of a point-symmetric geometry, None when it
    is not one: no centre, a fracture or a tip without its image."""
    c = domain_center(domain)
    if c is None:
        return None
    tol = 1e-9 * domain.length_scale()
    images = fracture_images(polylines, c, tol)
    if images is None:
        return None
    tip_x = np.array([t[0] for t in tips], dtype=np.float64).reshape(-1, 2)
    if len(tip_x) and np.max(np.min(np.linalg.norm(rotate(tip_x, c)[:, None] - tip_x[None], axis=2), axis=1)) > tol:
        return None
    fixed = [np.asarray(a, dtype=np.float64) for a in anchors]
    fixed += [rotate(a, c) for a in fixed] + list(domain.vertices())
    return c, tol, images, tip_x, fixed


def _best(trials):
    """(key, u, points) of the trial of the highest score among `trials`
    ((key, u, (points, score) or None), tried lazily in turn): a later one
    must beat the best so far by 1e-12, and a score of 1 ends the search."""
    best, best_score = None, 0.0
    for key, u, found in trials:
        if found is not None and found[1] > best_score + 1e-12:
            best, best_score = (key, u, found[0]), found[1]
            if best_score >= 1.0:
                break
    return best


def find_half(domain, polylines, tips, anchors, tip_size: float) -> Half | None:
    """The divider for a point-symmetric geometry, or None (not symmetric, or
    no line through the centre keeps clear of tips, vertices and anchors).

    polylines: the plan's fractures; tips: (x, h) of every tip; anchors:
    boundary points that must stay nodes (bc points, crack mouths)."""
    found = _symmetric(domain, polylines, tips, anchors)
    if found is None:
        return None
    c, tol, images, tip_x, fixed = found
    def trials():
        for psi in CANDIDATES:
            u = np.array([math.cos(psi), math.sin(psi)])
            yield psi, u, _divider(domain, polylines, tip_x, fixed, c, u, tip_size, tol)

    best = _best(trials())
    if best is None:
        return None
    psi, u, points = best
    return Half(center=c, u=u, points=points, fracture_image=images, angle=float(psi))


def _divider(domain, polylines, tip_x, fixed, c, u, tip_size, tol):
    """(divider points from R(p) to p, score in (0, 1]) for direction u, or None."""
    p = _boundary_hit(domain, c, u)
    for a in fixed:
        if np.linalg.norm(a - p) < ANCHOR_CLEARANCE * tip_size or np.linalg.norm(a - rotate(p, c)) < ANCHOR_CLEARANCE * tip_size:
            return None
    # the divider's vertices along u: ends, crossings and the centre, symmetric by construction
    found = _line_vertices(polylines, tip_x, c, u, tip_size, tol, 0.0, float((p - c) @ u))
    if found is None:
        return None
    ts, sines = found
    positive = [c + t * u for t in ts] + [p]
    # the crossings on the far side are the exact images of those on the near side
    points = np.array([rotate(x, c) for x in positive[::-1]] + [c] + positive)
    return points, _score(sines, tip_x, c, u, tip_size)


def find_half_patched(domain, polylines, tips, anchors, tip_size: float, radius: float, circle) -> Half | None:
    """The divider of a point-symmetric geometry with a patch circle of
    `radius` about the domain's centre (crack_mesh's `patch`): outside the
    circle a divider chosen from what lies outside only (the outer fractures
    and tips, the anchors), inside another (Half.inner) chosen from what
    lies inside; both end on nodes of the circle (`circle`, (N, 2), N even,
    counter-clockwise, node k + N/2 the image of node k), which splits there.
    Every fracture lies wholly inside or wholly outside the circle (the
    caller's rule). None when the geometry is not symmetric or either
    divider finds no direction."""
    found = _symmetric(domain, polylines, tips, anchors)
    if found is None:
        return None
    c, tol, images, tip_x, fixed = found
    inside = [np.linalg.norm(p[0] - c) < radius for p in polylines]
    tip_in = np.linalg.norm(tip_x - c, axis=1) < radius
    n = len(circle)
    picks = []
    for outer in (True, False):
        lines = [p for p, i in zip(polylines, inside) if i != outer]
        def trials(outer=outer, lines=lines):
            for k in range(n // 2):  # the nodes' directions cover [0, pi) once
                q = np.asarray(circle[k], dtype=np.float64)
                u = (q - c) / np.linalg.norm(q - c)
                if outer:
                    yield k, u, _outer_piece(domain, lines, tip_x[~tip_in], fixed, c, u, q, tip_size, radius, tol)
                else:
                    yield k, u, _inner_piece(lines, tip_x[tip_in], c, u, q, tip_size, radius, tol)

        best = _best(trials())
        if best is None:
            return None
        picks.append(best)
    (k_out, u_out, points), (k_in, u_in, inner_points) = picks
    inner = Inner(radius=float(radius), u=u_in, k=k_in, points=inner_points,
                  angle=float(math.atan2(u_in[1], u_in[0])))
    return Half(center=c, u=u_out, points=points, fracture_image=images, angle=float(math.atan2(u_out[1], u_out[0])),
                inner=inner, k_out=k_out)


def _line_vertices(polylines, tip_x, c, u, tip_size, tol, start: float, end: float):
    """(distances t along u of the crossings, sines of all crossings) of a
    divider piece from c + start u to c + end u, or None where it cannot go:
    a tip too near the line, a crossing breaking a rule of
    _crossings_along, or crossings closer than VERTEX_CLEARANCE tip sizes
    to each other or to the piece's ends."""
    normal = np.array([-u[1], u[0]])
    if len(tip_x) and np.min(np.abs((tip_x - c) @ normal)) < TIP_CLEARANCE * tip_size:
        return None
    found = _crossings_along(polylines, c, u, tip_size, tol)
    if found is None:
        return None
    ts, sines = found
    gap = VERTEX_CLEARANCE * tip_size
    if ts and (ts[0] - start < gap or end - ts[-1] < gap):
        return None
    if np.any(np.diff(ts) < gap):
        return None
    return ts, sines


def _crossings_along(polylines, c, u, tip_size, tol):
    """(distances t > tol along u of the crossings with the line c + t u, the
    sines of all crossings), or None when a vertex (other than the centre)
    is near the line or a crossing is too flat or too near a vertex: the
    rules of _divider."""
    normal = np.array([-u[1], u[0]])
    crossings, sines = [], [1.0]
    for pts in polylines:
        side = (pts - c) @ normal
        for i, s in enumerate(side):
            if abs(s) < VERTEX_CLEARANCE * tip_size and np.linalg.norm(pts[i] - c) > tol:
                return None  # a vertex on (or near) the line, other than the centre itself
        for i in range(len(pts) - 1):
            a, b = pts[i], pts[i + 1]
            if side[i] * side[i + 1] >= 0.0:
                continue  # no crossing (a vertex at the centre is one already)
            t = side[i] / (side[i] - side[i + 1])
            x = a + t * (b - a)
            sine = abs((b - a) / np.linalg.norm(b - a) @ normal)
            if sine < MIN_CROSSING_SINE:
                return None
            if min(np.linalg.norm(x - a), np.linalg.norm(x - b)) < VERTEX_CLEARANCE * tip_size:
                return None
            crossings.append(x)
            sines.append(sine)
    return sorted(set(float((x - c) @ u) for x in crossings if (x - c) @ u > tol)), sines


def _score(sines, tip_x, c, u, tip_size) -> float:
    """A divider's score in (0, 1]: its flattest crossing against 60 degrees
    and its nearest tip against twice the clearance, 1 when both suffice."""
    normal = np.array([-u[1], u[0]])
    clearance = np.min(np.abs((tip_x - c) @ normal)) if len(tip_x) else np.inf
    return min(1.0, min(sines) / math.sin(math.radians(60.0)), clearance / (2.0 * TIP_CLEARANCE * tip_size))


def _outer_piece(domain, polylines, tip_x, fixed, c, u, q, tip_size, radius, tol):
    """(vertices R(p), crossings, R(q), q, crossings, p; score) of the divider
    outside the circle along u (q: its circle node), or None."""
    p = _boundary_hit(domain, c, u)
    for a in fixed:
        if min(np.linalg.norm(a - p), np.linalg.norm(a - rotate(p, c))) < ANCHOR_CLEARANCE * tip_size:
            return None
    found = _line_vertices(polylines, tip_x, c, u, tip_size, tol, radius, float((p - c) @ u))
    if found is None:
        return None
    ts, sines = found
    positive = [q] + [c + t * u for t in ts] + [p]
    points = np.array([rotate(x, c) for x in positive[::-1]] + positive)
    return points, _score(sines, tip_x, c, u, tip_size)


def _inner_piece(polylines, tip_x, c, u, q, tip_size, radius, tol):
    """(vertices R(q), crossings, centre, crossings, q; score) of the divider
    inside the circle along u (q: its circle node), or None."""
    found = _line_vertices(polylines, tip_x, c, u, tip_size, tol, 0.0, radius)
    if found is None:
        return None
    ts, sines = found
    positive = [c + t * u for t in ts] + [q]
    points = np.array([rotate(x, c) for x in positive[::-1]] + [c] + positive)
    return points, _score(sines, tip_x, c, u, tip_size)


def _boundary_hit(domain, c, u) -> np.ndarray:
    """Where the ray c + t u (t > 0) leaves the (convex, centred) domain."""
    if domain.shape == "disc":
        return c + domain.radius * u
    v = domain.vertices()
    best = np.inf
    for a, b in zip(v, np.roll(v, -1, axis=0)):
        e = b - a
        den = u[0] * (-e[1]) - u[1] * (-e[0])
        if abs(den) < 1e-300:
            continue
        r = a - c
        t = (r[0] * (-e[1]) - r[1] * (-e[0])) / den
        s = (u[0] * r[1] - u[1] * r[0]) / den
        if t > 0.0 and -1e-12 <= s <= 1.0 + 1e-12:
            best = min(best, t)
    return c + best * u


def sizes_for_half(tri, vals, half: Half, tol: float):
    """The size field (triangles (m, 3, 2), values (m, 3)) made point-symmetric,
    min(h(x), h(R x)), on the triangles that reach the meshed half; None when
    the triangles themselves are not point-symmetric (the caller then bounds
    the sizes by the field and its image)."""
    tri = np.asarray(tri, dtype=np.float64)
    vals = np.asarray(vals, dtype=np.float64).reshape(len(tri), 3)
    if not len(tri):
        return None
    cen = tri.mean(axis=1)
    d, j = cKDTree(cen).query(rotate(cen, half.center))
    if d.max() > tol:
        return None
    image = rotate(tri[j], half.center)
    dist = np.linalg.norm(tri[:, :, None, :] - image[:, None, :, :], axis=3)  # vertex k of i vs l of j
    pick = dist.argmin(axis=2)
    if np.take_along_axis(dist, pick[..., None], 2).max() > tol:
        return None
    sym = np.minimum(vals, np.take_along_axis(vals[j], pick, 1))
    rel = tri - half.center
    side = half.u[0] * rel[..., 1] - half.u[1] * rel[..., 0]
    keep = np.any(side >= -tol, axis=1)  # a triangle holding a point of the half has a vertex there
    if half.inner is not None:
        # and every triangle that may reach into the circle, whatever the inner divider (which changes
        # with the fractures inside, while the far field's grid must not): a triangle holding a point
        # within the radius has a vertex within the radius plus its longest edge
        edge = np.linalg.norm(tri - np.roll(tri, 1, axis=1), axis=2).max(axis=1)
        near = np.linalg.norm(rel, axis=2).min(axis=1) <= half.inner.radius + edge + tol
        keep |= near
    return tri[keep], sym[keep]


def insert_divider(polylines, junction, half: Half, tol: float):
    """Insert the divider's crossings into the fractures. Returns (polylines,
    junction with host vertex indices shifted)."""
    out, shift = [], []
    for pts in polylines:
        rows, index = [], []
        for i in range(len(pts)):
            index.append(len(rows))
            rows.append(pts[i])
            if i == len(pts) - 1:
                break
            a, b = pts[i], pts[i + 1]
            hits = []
            for x in half.crossings():
                ab = b - a
                t = float(np.dot(x - a, ab) / np.dot(ab, ab))
                if 0.0 < t < 1.0 and np.linalg.norm(a + t * ab - x) <= tol:
                    hits.append((t, x))
            rows.extend(x.copy() for _, x in sorted(hits, key=lambda h: h[0]))
        out.append(np.array(rows, dtype=np.float64))
        shift.append(index)
    junction = {key: (g, shift[g][v]) for key, (g, v) in junction.items()}
    return out, junction


def glue(raw: RawMesh, half: Half, domain, tip_image: list[int], point_image: list[int], tol: float) -> RawMesh:
    """The whole mesh from the mesh of one half (gmsh's): every node of the
    half but those on the divider gets an image R(x); cells, boundary and
    crack edges are copied through the node map.

    raw.divider_nodes: the nodes on the divider; tip_image / point_image:
    for every tip / bc point of the plan, -1 when it is in the meshed half
    (its node is in raw), else the index of the tip / point whose image it
    is."""
    x = raw.x
    n = len(x)
    on_div = np.asarray(raw.divider_nodes, dtype=np.int64)
    image_of = np.full(n, -1, dtype=np.int64)
    if len(on_div):
        xd, rd = x[on_div], rotate(x[on_div], half.center)
        dist = np.linalg.norm(rd[:, None, :] - xd[None, :, :], axis=2)
        j = np.argmin(dist, axis=1)
        if np.max(dist[np.arange(len(on_div)), j]) > tol:
            raise RuntimeError("symmetric mesh: the divider's nodes do not mirror")
        image_of[on_div] = on_div[j]
    fresh = np.flatnonzero(image_of < 0)
    image_of[fresh] = n + np.arange(len(fresh))
    x_all = np.concatenate([x, rotate(x[fresh], half.center)])

    cells = np.concatenate([raw.cells, image_of[raw.cells]])  # a half turn keeps orientation

    b = raw.boundary_edges
    b_img = image_of[b]
    names = list(raw.boundary_name)
    for e in b_img:
        name = domain.boundary_name_at(x_all[e[2]], 1e-6 * domain.length_scale())
        if name is None:
            raise RuntimeError("symmetric mesh: a boundary edge's image is off the boundary")
        names.append(name)

    ce = raw.crack_edges
    frac = np.asarray(raw.crack_fracture, dtype=np.int64)
    img_frac = np.array([half.fracture_image[f][0] for f in frac], dtype=np.int64)
    flip = np.array([half.fracture_image[f][1] for f in frac], dtype=bool)
    ce_img = image_of[ce]
    ce_img[flip] = ce_img[flip][:, [1, 0, 2]]

    ce_all, frac_all = _along_fractures(np.concatenate([ce, ce_img]), np.concatenate([frac, img_frac]))

    def through(values, images):
        values = list(values)
        return [values[i] if k < 0 else int(image_of[values[k]]) for i, k in enumerate(images)]

    return RawMesh(
        x=x_all,
        cells=cells,
        boundary_edges=np.concatenate([b, b_img]).astype(np.int64),
        boundary_name=tuple(names),
        crack_edges=ce_all,
        crack_fracture=frac_all,
        tip_node=np.array(through(raw.tip_node.tolist(), tip_image), dtype=np.int64),
        tip_corner=np.array(through(raw.tip_corner.tolist(), tip_image), dtype=np.int64),
        point_nodes=np.array(through(raw.point_nodes, point_image), dtype=np.int64),
        divider_nodes=np.zeros(0, np.int64),
        far=None if raw.far is None else np.concatenate([raw.far, raw.far]),
        far_reused=raw.far_reused,
    )


def _along_fractures(edges: np.ndarray, fracture: np.ndarray):
    """Crack edges (oriented along their fracture) grouped by fracture and
    chained from its first point to its last, as the mesher gives them."""
    out_e, out_f = [], []
    for f in np.unique(fracture):
        e = edges[fracture == f]
        starts = {int(a): k for k, a in enumerate(e[:, 0])}
        ends = set(e[:, 1].tolist())
        first = [k for k, a in enumerate(e[:, 0].tolist()) if a not in ends]
        if len(first) != 1 or len(starts) != len(e):
            raise RuntimeError(f"symmetric mesh: the edges of fracture {f} do not form one path")
        order, seen, k = [], set(), first[0]
        for _ in range(len(e)):
            order.append(k)
            seen.add(k)
            k = starts.get(int(e[k, 1]), -1)
            if k < 0 or k in seen:
                break
        if len(order) != len(e):
            raise RuntimeError(f"symmetric mesh: the edges of fracture {f} do not form one path")
        out_e.append(e[order])
        out_f.append(np.full(len(e), f, dtype=np.int64))
    if not out_e:
        return edges.reshape(0, 3).astype(np.int64), fracture.astype(np.int64)
    return np.concatenate(out_e).astype(np.int64), np.concatenate(out_f)
