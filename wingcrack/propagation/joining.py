"""Where a growing tip ends up: free, on another fracture (a T), or on the
outer boundary (paper section 3.2, Fig. 5).

The proposed new segment [tip, tip + L d] is checked, in this order:
1. does it cross a fracture (another one, or its own polyline away from the
   tip) or the outer boundary? Then it is cut at the first crossing and the
   tip is "joined" / "boundary" there: fractures never cross;
2. does the new tip come within `reach` of a fracture or the boundary? Then
   the crack is stretched along its direction onto it when that is within
   reach + L, or else sent to the closest point of it;
3. does it come so near another free tip that their rosettes would overlap
   (meshing.admissibility.rosettes_apart)? Then it meets that tip.
`reach` is the join distance: the rosette radius h in the paper; wingcrack
uses admissibility.TIP_CLEARANCE h, the closest the mesher lets a rosette
come to another fracture or the boundary: a tip that does not join keeps
the clearances the next mesh needs.
"""
from __future__ import annotations

import numpy as np

from meshing import admissibility

import wingcrack_kernels as K


def _segments_of(fset, skip):
    """(owner (k,), a (k, 2), b (k, 2)): every fracture segment [a, b] and
    the index of its polyline, except the one at the growing tip (skip =
    (fracture, end))."""
    fi, end = skip
    owner, a, b = [], [], []
    for i, f in enumerate(fset.fractures):
        pts = np.asarray(f.points, float)
        lo, hi = 0, len(pts) - 1
        if i == fi:
            lo, hi = (lo, hi - 1) if end == 1 else (lo + 1, hi)
        owner.append(np.full(max(hi - lo, 0), i))
        a.append(pts[lo:hi])
        b.append(pts[lo + 1:hi + 1])
    return np.concatenate(owner), np.concatenate(a).reshape(-1, 2), np.concatenate(b).reshape(-1, 2)


def _first_hit(a, b, p, q, after: float):
    """(index, t) of the first of the segments [p, q] (k, 2) that a -> b
    hits at t > after (t along a -> b; the first listed of equal t), or
    None."""
    k = len(p)
    hit, t, _, _ = K.segment_intersections(np.tile(a, (k, 1)), np.tile(b, (k, 1)), p, q, 1e-12)
    hits = np.flatnonzero(hit & (t > after))
    if not len(hits):
        return None
    first = hits[np.argmin(t[hits])]
    return int(first), float(t[first])


def _boundary_hit(domain, a, b):
    """First crossing (t in [0, 1]) of segment a->b with the outer boundary."""
    d = b - a
    if domain.shape == "disc":
        c = np.asarray(domain.center, float)
        R = float(domain.radius)
        f = a - c
        A, B, C = d @ d, 2 * f @ d, f @ f - R * R
        disc = B * B - 4 * A * C
        if disc < 0:
            return None
        for t in sorted(((-B - np.sqrt(disc)) / (2 * A), (-B + np.sqrt(disc)) / (2 * A))):
            if 0 < t <= 1:
                return t
        return None
    v = np.asarray(domain.vertices(), float)
    first = _first_hit(a, b, v, np.roll(v, -1, axis=0), 1e-12)
    return None if first is None else first[1]


def place_tip(fset, fi: int, end: int, direction, length: float, domain, reach: float):
    """(new tip point, state) for tip `end` of fracture `fi` growing by
    `length` along the unit `direction`; state is "tip", "joined" or
    "boundary"."""
    p, state, _ = placement(fset, fi, end, direction, length, domain, reach)
    return p, state


def placement(fset, fi: int, end: int, direction, length: float, domain, reach: float):
    """place_tip's (point, state) and the index of the fracture a "joined"
    tip ended on (None otherwise; `fi` itself when it is its own polyline,
    which the caller refuses as a join)."""
    f = fset.fractures[fi]
    a = f.tip(end)
    d = np.asarray(direction, float)
    # look a little beyond the step so that "stretching" onto a close
    # fracture or boundary is found as a crossing along the direction
    b_far = a + d * (length + reach)
    best_t, state, met = None, "tip", None
    owner, p, q = _segments_of(fset, (fi, end))
    first = _first_hit(a, b_far, p, q, 1e-9)
    if first is not None:
        best_t, state, met = first[1], "joined", int(owner[first[0]])
    tb = _boundary_hit(domain, a, b_far)
    if tb is not None and (best_t is None or tb < best_t):
        best_t, state, met = tb, "boundary", None
    if best_t is not None:
        return a + best_t * (b_far - a), state, met
    b = a + d * length
    # close to something without reaching it along the direction
    dmin, foot, near = np.inf, None, None
    for i, g in enumerate(fset.fractures):
        pts = g.points
        if i == fi:
            # all of its own polyline but the segment at the tip: after the step
            # that segment is the new tip's neighbour, the one before it is the
            # mesher's (meshing.admissibility.rosettes) like any other fracture
            pts = pts[:-1] if end == 1 else pts[1:]
            if len(pts) < 2:
                continue
        dist, point, _, _ = K.closest_point_on_polyline(b, pts)
        if dist < dmin:
            dmin, foot, near = dist, np.asarray(point), i
    db = domain.distance_to_boundary(b)
    if db < reach and db <= dmin:
        return np.asarray(domain.project(b)[0]), "boundary", None
    if dmin < reach:
        return foot, "joined", near
    # the rosette radius the reach is made of; the next mesh's is at most this
    h = reach / admissibility.TIP_CLEARANCE
    for i, g in enumerate(fset.fractures):
        for e in (0, 1):
            if (i, e) != (fi, end) and g.ends[e] == "tip" and \
                    np.linalg.norm(g.tip(e) - b) <= admissibility.rosettes_apart(h, h):
                # its own other tip: the caller sees a join on its own fracture (no growth)
                return g.tip(e).copy(), "joined", i
    return b, "tip", None
