"""How fractures meet: the junctions of a set of fracture polylines.

Fractures (or two parts of one) meet where
- an end of one lies on another (a T-junction; on the other's end: the two
  meet end to end; several ends at one point: a star; a ring of fractures
  met end to end: a closed loop);
- their segments cross (an X), or a vertex of one lies on a segment or a
  vertex of another.
`join` makes every such point a vertex of every polyline through it, with
bitwise identical coordinates, so that the mesher builds one gmsh point
there and the face split (wingcrack_kernels.split_faces) gives the node one
copy for each sector between the fracture rays that leave it (four at an
X, three at a T). It reports which ends are junctions (no tips), the points
where fractures meet (nodes), and what no mesh can hold: segments that
overlap along a stretch, and a mouth (an end on the outer boundary) lying
on another fracture (the caller refuses both: meshing/admissibility.py).

The searches go through a k-d tree over short pieces of the segments
(near_segment_pairs, segments_near_points), so that a network of fractures
that are mostly apart costs time linear in its segments, not quadratic.

Lengths in metres; `tol` is "touching" (admissibility.REL_TOL times the
domain's length scale). Pure numpy and scipy; never the `wingcrack` package.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree


@dataclass
class Joined:
    """The fractures as the mesher takes them, and how they meet.

    polylines: every junction point inserted as a vertex of every polyline
    through it; the coordinates of a junction are the same bits in each.
    junction: (f, end) -> (host, vertex): the end lies on the host's polyline
    (at that vertex of `polylines`); met: the ends that a junction end met
    end to end (its host's end). partner: (f, end) -> the fracture each of
    those ends met. nodes: {vertex bits: [(f, vertex), ...]} every point
    where two or more polyline vertices coincide (T, X, end to end, a
    polyline closed on itself). overlaps: (f, g, p, q), fracture g runs
    along fracture f from p to q. mouths: (f, end, g), fracture f's end on
    the boundary lies on fracture g."""

    polylines: list
    junction: dict = field(default_factory=dict)
    met: set = field(default_factory=set)
    partner: dict = field(default_factory=dict)
    nodes: dict = field(default_factory=dict)
    overlaps: list = field(default_factory=list)
    mouths: list = field(default_factory=list)

    def node_points(self) -> np.ndarray:
        """(k, 2) the nodes' coordinates."""
        pts = [self.polylines[f][v] for f, v in (members[0] for members in self.nodes.values())]
        return np.array(pts, dtype=np.float64).reshape(-1, 2)

    def joined_ends(self) -> dict:
        """(f, end) -> the fracture it met, for every end that is no tip
        because it lies on a fracture (junction and met ends)."""
        return dict(self.partner)

    def group_of(self, f: int) -> list:
        """The sorted fractures that meet fracture f, directly or through
        others (at a T, end to end, at an X), f among them."""
        seen, todo = {f}, [f]
        while todo:
            g = todo.pop()
            for members in self.nodes.values():
                met = {h for h, _ in members}
                if g in met:
                    todo += sorted(met - seen)
                    seen |= met
        return sorted(seen)


# ---------------------------------------------------------------- searches


def segments(polylines):
    """Every segment of the polylines: (a (m, 2), b (m, 2), owner (m,), index (m,))
    in order of fracture, then of segment."""
    polylines = [np.asarray(p, dtype=np.float64) for p in polylines]
    if not polylines:
        z = np.zeros((0, 2))
        return z, z, np.zeros(0, np.int64), np.zeros(0, np.int64)
    a = np.concatenate([p[:-1] for p in polylines])
    b = np.concatenate([p[1:] for p in polylines])
    owner = np.concatenate([np.full(len(p) - 1, f, dtype=np.int64) for f, p in enumerate(polylines)])
    index = np.concatenate([np.arange(len(p) - 1, dtype=np.int64) for p in polylines])
    return a, b, owner, index


def _pieces(a, b):
    """The segments cut into pieces of at most about the median segment's
    length (and at most 5 m pieces in all, m segments): (midpoints, segment
    of each, the largest half-length of a piece). A point within r of a
    segment is within r + that half-length of one of its pieces' midpoints."""
    length = np.linalg.norm(b - a, axis=1)
    m = len(a)
    ell = max(float(np.median(length)), float(length.sum()) / (4 * m))
    if not ell > 0.0:
        ell = 1.0
    k = np.maximum(1, np.ceil(length / ell)).astype(np.int64)
    seg = np.repeat(np.arange(m), k)
    j = np.arange(int(k.sum())) - np.repeat(np.cumsum(k) - k, k)
    frac = (j + 0.5) / k[seg]
    mid = a[seg] + frac[:, None] * (b - a)[seg]
    return mid, seg, float(np.max(0.5 * length / k))


def near_segment_pairs(a, b, pad: float):
    """(i, j), i < j: every pair of segments [a, b] that may come within
    `pad` of each other (a superset: the caller measures)."""
    m = len(a)
    if m < 2:
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    mid, seg, half = _pieces(a, b)
    pairs = cKDTree(mid).query_pairs(2.0 * half + pad, output_type="ndarray")
    si, sj = seg[pairs[:, 0]], seg[pairs[:, 1]]
    keep = si != sj
    lo, hi = np.minimum(si, sj)[keep], np.maximum(si, sj)[keep]
    key = np.unique(lo * m + hi)
    return key // m, key % m


def segments_near_points(p, radius, a, b):
    """(point, segment) index pairs, each point with every segment that may
    pass within radius[point] of it (a superset), sorted by point, then
    segment."""

    p = np.asarray(p, dtype=np.float64).reshape(-1, 2)
    radius = np.broadcast_to(np.asarray(radius, dtype=np.float64), (len(p),))
    if not len(p) or not len(a):
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    mid, seg, half = _pieces(a, b)
    found = cKDTree(mid).query_ball_point(p, radius + half)
    counts = np.array([len(x) for x in found], dtype=np.int64)
    if not counts.sum():
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    pt = np.repeat(np.arange(len(p)), counts)
    sg = seg[np.concatenate([np.asarray(x, dtype=np.int64) for x in found if len(x)])]
    key = np.unique(pt * len(a) + sg)
    return key // len(a), key % len(a)


def point_segment(p, a, b):
    """(distance, parameter t in [0, 1] of the nearest point) of points p to
    segments [a, b], row by row."""
    ab = b - a
    den = np.einsum("ij,ij->i", ab, ab)
    t = np.clip(np.einsum("ij,ij->i", p - a, ab) / np.where(den > 0, den, 1.0), 0.0, 1.0)
    return np.linalg.norm(p - a - t[:, None] * ab, axis=1), t


def _cross(u, v):
    return u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]


# ---------------------------------------------------------------- joining


def join(polylines, free_ends, tol: float, mouths=()) -> Joined:
    """The fractures with their junction points inserted (Joined).

    free_ends: the (f, end) not on the outer boundary, in order; mouths: the
    (f, end) on it. An end within `tol` of a fracture (of another, or of a
    part of its own beyond its segment and the one before) is a T-junction
    there: the point is inserted into the host (unless it is a vertex
    already) and the end takes the host vertex's coordinates; on the host's
    free end the two meet end to end (neither is a tip). Then segments that
    cross or touch away from the ends get the point of contact as a vertex
    of each (the same bits: a vertex's own, or the crossing computed once)."""
    polylines = [np.array(p, dtype=np.float64) for p in polylines]
    out = Joined(polylines)
    if not polylines:
        return out
    _join_ends(out, list(free_ends), tol)
    _join_crossings(out, set(free_ends), set(mouths), tol)
    out.nodes = _nodes(out.polylines)
    return out


def _join_ends(out: Joined, free_ends, tol: float) -> None:
    """T-junctions and ends met end to end (the first stage of join)."""
    polylines = out.polylines
    if not free_ends:
        return
    a, b, owner, index = segments(polylines)
    p = np.array([polylines[f][0 if e == 0 else -1] for f, e in free_ends])
    pt, sg = segments_near_points(p, 2.0 * tol, a, b)
    fe = np.array(free_ends, dtype=np.int64).reshape(-1, 2)
    f_of, e_of, g, s = fe[pt, 0], fe[pt, 1], owner[sg], index[sg]
    n = np.array([len(q) - 1 for q in polylines])[g]
    own = (g == f_of) & np.where(e_of == 0, s <= 1, s >= n - 2)   # the end's segment and its neighbour
    pt, sg = pt[~own], sg[~own]
    dist, t = point_segment(p[pt], a[sg], b[sg])
    near = dist <= tol
    pt, sg, dist, t = pt[near], sg[near], dist[near], t[near]
    order = np.lexsort((sg, dist, pt))   # per end: the nearest segment, the first of equals
    first = order[np.r_[True, pt[order][1:] != pt[order][:-1]]] if len(order) else order
    hits = [(free_ends[int(pt[k])][0], free_ends[int(pt[k])][1], int(owner[sg[k]]), int(index[sg[k]]), float(t[k]))
            for k in sorted(first.tolist(), key=lambda k: int(pt[k]))]
    if not hits:
        return
    by_segment: dict = {}
    for k, (_, _, h, seg, tt) in enumerate(hits):
        by_segment.setdefault((h, seg), []).append((tt, k))
    hosts = {h for _, _, h, _, _ in hits}
    new_index: dict = {}
    rows_of = {}
    for h in sorted(hosts):
        pts = polylines[h]
        last = len(pts) - 1
        rows, index_of_vertex = [], {}
        for v in range(last + 1):
            index_of_vertex[v] = len(rows)
            rows.append(pts[v])
            if v == last:
                break
            for tt, k in sorted(by_segment.get((h, v), [])):
                x = pts[v] + tt * (pts[v + 1] - pts[v])
                if np.linalg.norm(x - pts[v]) <= tol:
                    new_index[k] = -1 - v            # on vertex v (resolved below)
                elif np.linalg.norm(x - pts[v + 1]) <= tol:
                    new_index[k] = -2 - v            # on vertex v + 1
                else:
                    f, end = hits[k][0], hits[k][1]
                    new_index[k] = len(rows)
                    rows.append(polylines[f][0 if end == 0 else -1].copy())
        rows_of[h] = rows
        for k in [k for k, (_, _, hk, _, _) in enumerate(hits) if hk == h]:
            if new_index[k] < 0:
                new_index[k] = index_of_vertex[-1 - new_index[k]]
    for h, rows in rows_of.items():
        polylines[h] = np.array(rows, dtype=np.float64)
    free = set(free_ends)
    junction, met = out.junction, out.met
    for k, (f, end, h, _, _) in enumerate(hits):
        if (f, end) in met:
            continue   # the other half of an end-to-end meeting, recorded from its partner
        vertex = new_index[k]
        if vertex in (0, len(polylines[h]) - 1):
            other = (h, 0 if vertex == 0 else 1)
            if other not in free:   # on a mouth: refused (admissibility.joins)
                out.mouths.append((h, other[1], f))
                continue
            met.add(other)   # end meets end: the two link, neither end is a tip
            junction.pop(other, None)
            out.partner[other] = f
        junction[(f, end)] = (h, vertex)
        out.partner[(f, end)] = h
    for (f, end), (h, vertex) in junction.items():   # the same coordinates, bit for bit
        polylines[f][0 if end == 0 else -1] = polylines[h][vertex]


def _join_crossings(out: Joined, free: set, mouths: set, tol: float) -> None:
    """Crossings and touching vertices away from the junction ends (the
    second stage of join): each point of contact becomes a vertex of every
    polyline through it."""
    polylines = out.polylines
    a, b, owner, index = segments(polylines)
    i, j = near_segment_pairs(a, b, 2.0 * tol)
    consecutive = (owner[i] == owner[j]) & (np.abs(index[i] - index[j]) == 1)
    i, j = i[~consecutive], j[~consecutive]
    if not len(i):
        return
    P0, P1, Q0, Q1 = a[i], b[i], a[j], b[j]
    # the four ends against the other segment: (distance, parameter on the other)
    ends = [point_segment(P0, Q0, Q1), point_segment(P1, Q0, Q1), point_segment(Q0, P0, P1),
            point_segment(Q1, P0, P1)]
    touch = np.stack([d <= tol for d, _ in ends], axis=1)        # (k, 4)
    where = np.stack([P0, P1, Q0, Q1], axis=1)                    # (k, 4, 2)
    r, s = P1 - P0, Q1 - Q0
    den = _cross(r, s)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = _cross(Q0 - P0, s) / den
        u = _cross(Q0 - P0, r) / den
    proper = (den != 0) & (t > 0) & (t < 1) & (u > 0) & (u < 1) & ~touch.any(axis=1)

    items = []   # (point, [(f, vertex)], [(f, segment, parameter)])
    for k in np.flatnonzero(touch.any(axis=1)):
        hit = np.flatnonzero(touch[k])
        pts = where[k, hit]
        if np.max(np.linalg.norm(pts - pts[0], axis=1)) > tol:   # two points of contact: a common stretch
            q = pts[np.argmax(np.linalg.norm(pts - pts[0], axis=1))]
            out.overlaps.append((int(owner[i[k]]), int(owner[j[k]]), pts[0].copy(), q.copy()))
            continue
        for c in hit:
            mine, other = (i[k], j[k]) if c < 2 else (j[k], i[k])
            v = int(index[mine]) + (c % 2)
            param = ends[c][1][k]   # where on the other segment
            vertices = [(int(owner[mine]), v)]
            interior = []
            q0, q1 = a[other], b[other]
            if np.linalg.norm(where[k, c] - q0) <= tol:
                vertices.append((int(owner[other]), int(index[other])))
            elif np.linalg.norm(where[k, c] - q1) <= tol:
                vertices.append((int(owner[other]), int(index[other]) + 1))
            else:
                interior.append((int(owner[other]), int(index[other]), float(param)))
            items.append((where[k, c].copy(), vertices, interior))
    for k in np.flatnonzero(proper):
        x = P0[k] + t[k] * r[k]
        items.append((x, [], [(int(owner[i[k]]), int(index[i[k]]), float(t[k])),
                              (int(owner[j[k]]), int(index[j[k]]), float(u[k]))]))
    if not items:
        return
    clusters = _clusters(np.array([x for x, _, _ in items]), tol)
    inserts: dict = {}    # (f, segment) -> [(parameter, point)]
    moves = []            # (f, vertex, point)
    for members in clusters:
        vertices = sorted({v for m in members for v in items[m][1]})
        interior = {}
        for m in members:
            for f, sgm, param in items[m][2]:
                interior.setdefault((f, sgm), param)
        for f, v in vertices:
            last = len(polylines[f]) - 1
            end = 0 if v == 0 else 1 if v == last else None
            if end is not None and (f, end) in mouths:
                g = next((g for g, _ in vertices if g != f), None)
                if g is None:
                    g = next(iter(interior))[0]
                out.mouths.append((f, end, g))
        rep = polylines[vertices[0][0]][vertices[0][1]].copy() if vertices else items[members[0]][0]
        for f, v in vertices:
            if not np.array_equal(polylines[f][v], rep):
                moves.append((f, v, rep))
        for (f, sgm), param in interior.items():
            # a segment whose vertex is in this cluster already passes through it
            if (f, sgm) in {(g, w) for g, w in vertices} or (f, sgm + 1) in {(g, w) for g, w in vertices}:
                continue
            inserts.setdefault((f, sgm), []).append((param, rep))
    for f, v, rep in moves:
        polylines[f][v] = rep
    if not inserts:
        return
    shift = {}
    for f in sorted({f for f, _ in inserts}):
        pts = polylines[f]
        rows, index_of_vertex = [], []
        for v in range(len(pts)):
            index_of_vertex.append(len(rows))
            rows.append(pts[v])
            for _, x in sorted(inserts.get((f, v), []), key=lambda q: q[0]):
                rows.append(x.copy())
        polylines[f] = np.array(rows, dtype=np.float64)
        shift[f] = index_of_vertex
    out.junction = {key: (h, shift[h][v] if h in shift else v) for key, (h, v) in out.junction.items()}


def _clusters(x, tol) -> list:
    """Groups of the points x (k, 2) linked by distances <= tol (transitively),
    each sorted, in order of their first member."""
    pairs = cKDTree(x).query_pairs(tol, output_type="ndarray") if len(x) > 1 else np.zeros((0, 2), np.int64)
    n = len(x)
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    _, label = connected_components(graph, directed=False)
    groups: dict = {}
    for m, c in enumerate(label.tolist()):
        groups.setdefault(c, []).append(m)
    return sorted(groups.values(), key=lambda g: g[0])


def _nodes(polylines) -> dict:
    """{bits of a point: [(f, vertex), ...]} for the points that are a vertex
    of two or more polylines, or twice of one."""
    if not polylines:
        return {}
    x = np.concatenate(polylines)
    who = [(f, v) for f, p in enumerate(polylines) for v in range(len(p))]
    keys = np.ascontiguousarray(x).view(np.dtype((np.void, 16))).ravel()
    uniq, inverse, counts = np.unique(keys, return_inverse=True, return_counts=True)
    out: dict = {}
    for k in np.flatnonzero(counts[inverse.ravel()] > 1):
        out.setdefault(bytes(keys[k]), []).append(who[k])
    return out
