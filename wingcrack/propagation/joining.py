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
    """(polyline index, a, b) of every fracture segment, except the one at
    the growing tip (skip = (fracture, end))."""
    out = []
    fi, end = skip
    for i, f in enumerate(fset.fractures):
        pts = f.points
        n = len(pts) - 1
        for s in range(n):
            if i == fi and ((end == 1 and s == n - 1) or (end == 0 and s == 0)):
                continue
            out.append((i, pts[s], pts[s + 1]))
    return out


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
    v = domain.vertices()
    best = None
    for k in range(len(v)):
        hit, t, _, _ = K.segment_intersection(a, b, v[k], v[(k + 1) % len(v)], 1e-12)
        if hit and t > 1e-12 and (best is None or t < best):
            best = t
    return best


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
    for i, p, q in _segments_of(fset, (fi, end)):
        hit, t, _, _ = K.segment_intersection(a, b_far, p, q, 1e-12)
        if hit and t > 1e-9 and (best_t is None or t < best_t):
            best_t, state, met = t, "joined", i
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
