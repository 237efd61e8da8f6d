"""The slip history of the fracture faces: what Coulomb friction remembers.

Friction is path dependent: the tangential law acts on the slip increment
s - s_ref from the last converged slip s_ref = [u].t of each face pair
(t = d, the fracture direction; docs/architecture.md). Every step of a run
grows wings and remeshes, so s_ref must outlive the mesh it was computed
on. A SlipHistory keeps it as a field along each fracture's arc length, the
one coordinate that two meshes of the same fracture share:

- `record`: the converged slip of every pair of a mesh, kept as the P2
  field the finite elements hold along each + face edge [a, b, mid]: the
  three nodal slips and the arc lengths of the three nodes. A tip is not a
  pair; its jump is zero.
- `at`: that field at the pairs of another mesh of the same fractures. For
  each new node, the old edge holding its arc length, the edge's parametric
  coordinate xi of that arc length (on a straight edge sigma(xi) =
  sum N_i(xi) sigma_i, quadratic in xi when the mid node is a quarter point
  next to a tip: inverted), then the three P2 shape functions. Beyond the
  recorded extent (a new wing segment) the slip is zero. On the mesh it was
  recorded on, `at` returns the recorded slip to round-off.

Arc length is signed and measured from the first point of a fracture's
pre-existing part, points[pre[0]] (negative along a wing grown at end 0):
a material coordinate that growing wings do not move. The history keeps that
point (`origin`) and finds it again on the later polyline, so a tip node
moved straight on (GrowingFracture.move_tip at end 0 of a fracture without
a wing there, which moves points[pre[0]] itself) does not shift it either.
A pair belongs to cm.pair_fracture: where fractures meet (a T-junction, two
fractures linked end to end) it takes the arc of that fracture, from the
edges of that fracture, so the host's two pairs on either side of a T keep
their own slips.

Plain numpy on arrays (cm is a meshing CrackMesh, fractures anything with
`points` (n, 2) and `pre` = (i0, i1), as propagation's GrowingFracture); the
checkpoint stores `to_arrays()`.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: a mesh node farther than this (times its fracture's length) from that
#: fracture's polyline means mesh and fractures do not belong together
ON_POLYLINE = 1e-7
#: how far (times the recorded extent) an edge end node looks into its own
#: edge to pick the old edge on its side of a shared node: far above the
#: round-off of arc lengths, far below any edge length
SIDE_PROBE = 1e-9

KEYS = ("slip_origin", "slip_edge_fracture", "slip_edge_arc", "slip_edge_slip")


@dataclass(frozen=True, eq=False)
class SlipHistory:
    """The converged slip along every fracture, as P2 edges in arc length.

    Edges are grouped by fracture and ascending in arc length within each;
    a fracture without edges has zero slip everywhere (its origin unused).
    """

    #: (F, 2) float64: the material origin of each fracture's arc length (m)
    origin: np.ndarray
    #: (k,) int64: the fracture of each recorded edge
    edge_fracture: np.ndarray
    #: (k, 3) float64: signed arc length of the edge's [a, b, mid] nodes (m)
    edge_arc: np.ndarray
    #: (k, 3) float64: slip s = [u].t at [a, b, mid] (m), 0 at a tip
    edge_slip: np.ndarray

    @property
    def n_fractures(self) -> int:
        return len(self.origin)

    @classmethod
    def zero(cls, n_fractures: int) -> "SlipHistory":
        """No slip yet on any of `n_fractures` fractures (the start of a run)."""
        return cls(np.zeros((int(n_fractures), 2)), np.zeros(0, np.int64), np.zeros((0, 3)), np.zeros((0, 3)))

    def is_zero(self) -> bool:
        return not np.any(self.edge_slip)

    @classmethod
    def record(cls, cm, fractures, slip_per_pair) -> "SlipHistory":
        """The history holding `slip_per_pair` ((p,) s = [u].t of every pair of
        `cm`, in cm.pairs order) on the fractures as meshed in `cm`."""
        fractures = list(fractures)
        slip = np.asarray(slip_per_pair, dtype=np.float64)
        if slip.shape != (len(cm.pairs),):
            raise ValueError(f"slip_per_pair: shape {slip.shape}, the mesh has {len(cm.pairs)} pairs")
        if not np.all(np.isfinite(slip)):
            raise ValueError("slip_per_pair: not finite")
        edge_f = _edge_fracture(cm, len(fractures))
        pair = _edge_pairs(cm)
        values = np.where(pair >= 0, slip[np.maximum(pair, 0)], 0.0)
        origin = np.array([np.asarray(f.points, float)[f.pre[0]] for f in fractures], float).reshape(-1, 2)
        arcs = np.zeros(values.shape)
        for f, fr in enumerate(fractures):
            here = edge_f == f
            if np.any(here):
                arcs[here] = _node_arcs(cm, here, fr, origin[f], f)
        order = np.lexsort((arcs[:, 0], edge_f))
        return cls(origin, edge_f[order], arcs[order], values[order])

    def at(self, cm, fractures) -> np.ndarray:
        """(p,) the recorded slip at every pair of the mesh `cm` of
        `fractures` (the same fractures, possibly grown; 0 where they grew)."""
        fractures = list(fractures)
        if len(fractures) != self.n_fractures:
            raise ValueError(f"slip history: recorded on {self.n_fractures} fractures, given {len(fractures)}")
        edge_f = _edge_fracture(cm, len(fractures))
        values = np.zeros((len(edge_f), 3))
        for f, fr in enumerate(fractures):
            old = self.edge_fracture == f
            new = edge_f == f
            if np.any(old) and np.any(new):
                values[new] = _evaluate(self.edge_arc[old], self.edge_slip[old],
                                        _node_arcs(cm, new, fr, self.origin[f], f))
        return _to_pairs(cm, edge_f, values)

    def to_arrays(self) -> dict:
        """{name: ndarray} for checkpoint.npz (float64 / int64, no objects)."""
        return dict(zip(KEYS, (self.origin, self.edge_fracture, self.edge_arc, self.edge_slip)))

    @classmethod
    def from_arrays(cls, arrays) -> "SlipHistory":
        """The history of `to_arrays()` (a dict or an np.load of it)."""
        missing = [k for k in KEYS if k not in arrays]
        if missing:
            raise ValueError(f"slip history: missing {', '.join(missing)}")
        origin, fracture, arc, slip = (np.asarray(arrays[k]) for k in KEYS)
        k = len(fracture)
        for key, a, shape in zip(KEYS, (origin, fracture, arc, slip), ((len(origin), 2), (k,), (k, 3), (k, 3))):
            if a.shape != shape or not np.all(np.isfinite(a)):
                raise ValueError(f"slip history: {key} has shape {a.shape} (want {shape}) or is not finite")
        if k and (fracture.min() < 0 or fracture.max() >= len(origin)):
            raise ValueError("slip history: slip_edge_fracture names a fracture it has no origin for")
        return cls(origin.astype(np.float64), fracture.astype(np.int64), arc.astype(np.float64),
                   slip.astype(np.float64))


def pair_arc_lengths(cm, fractures) -> np.ndarray:
    """(p,) signed arc length of every pair of `cm` along its fracture
    (cm.pair_fracture) from points[pre[0]] (m): where two meshes' pairs share
    a material point."""
    fractures = list(fractures)
    edge_f = _edge_fracture(cm, len(fractures))
    arcs = np.zeros((len(edge_f), 3))
    for f, fr in enumerate(fractures):
        here = edge_f == f
        if np.any(here):
            arcs[here] = _node_arcs(cm, here, fr, np.asarray(fr.points, float)[fr.pre[0]], f)
    return _to_pairs(cm, edge_f, arcs)


def _edge_fracture(cm, n_fractures: int) -> np.ndarray:
    edge_f = np.asarray(cm.crack_fracture, dtype=np.int64).reshape(-1)
    if len(edge_f) and (edge_f.min() < 0 or edge_f.max() >= n_fractures):
        raise ValueError(f"slip history: the mesh has fracture {edge_f.max()}, given {n_fractures} fractures")
    return edge_f


def _edge_pairs(cm) -> np.ndarray:
    """(k, 3) the pair of each + face edge node [a, b, mid], found by its
    (plus, minus) copies (a node of a T has two pairs on the host: the plus
    copy alone does not tell them apart); -1 at a tip (one copy, no pair)."""
    plus = np.asarray(cm.crack_edges, dtype=np.int64).reshape(-1, 3)
    minus = np.asarray(cm.crack_edges_minus, dtype=np.int64).reshape(-1, 3)
    pairs = np.asarray(cm.pairs, dtype=np.int64).reshape(-1, 2)
    n = max(len(cm.x), 1)
    keys = pairs[:, 0] * n + pairs[:, 1]
    order = np.argsort(keys)
    sorted_keys = keys[order]
    wanted = plus * n + minus
    pos = np.minimum(np.searchsorted(sorted_keys, wanted), max(len(keys) - 1, 0))
    found = (sorted_keys[pos] == wanted) if len(keys) else np.zeros(wanted.shape, bool)
    if np.any(~found & (plus != minus)):
        raise ValueError("slip history: a crack edge node with two copies is no pair of the mesh")
    return np.where(found, order[pos] if len(keys) else -1, -1)


def _to_pairs(cm, edge_f, values) -> np.ndarray:
    """(p,) the value of each pair from the edge nodes of its own fracture."""
    pair = _edge_pairs(cm)
    pair_f = np.asarray(cm.pair_fracture, dtype=np.int64)
    own = pair >= 0
    own[own] = pair_f[pair[own]] == np.broadcast_to(edge_f[:, None], pair.shape)[own]
    out = np.zeros(len(pair_f))
    reached = np.zeros(len(pair_f), bool)
    out[pair[own]] = values[own]
    reached[pair[own]] = True
    if not np.all(reached):
        raise ValueError(f"slip history: pair {int(np.argmin(reached))} is on no crack edge of its fracture")
    return out


def _polyline_arc(points: np.ndarray, xy: np.ndarray, segment=None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(arc length from points[0] of the nearest point on the polyline,
    distance to it, its segment) for each row of xy (n, 2); on the given
    `segment` of each row instead, if given. Ties go to the first segment."""
    seg = np.diff(points, axis=0)
    length = np.linalg.norm(seg, axis=1)
    start = np.concatenate([[0.0], np.cumsum(length)[:-1]])
    if segment is not None:
        rel = xy - points[segment]
        t = np.clip(np.einsum("ij,ij->i", rel, seg[segment]) / length[segment] ** 2, 0.0, 1.0)
        d = np.linalg.norm(rel - t[:, None] * seg[segment], axis=1)
        return start[segment] + t * length[segment], d, segment
    best_d = np.full(len(xy), np.inf)
    best_s = np.zeros(len(xy))
    best_i = np.zeros(len(xy), np.int64)
    for i in range(len(seg)):   # a loop over segments, each vectorised over all nodes
        rel = xy - points[i]
        t = np.clip(rel @ seg[i] / length[i] ** 2, 0.0, 1.0)
        d = np.linalg.norm(rel - t[:, None] * seg[i], axis=1)
        better = d < best_d
        best_d[better] = d[better]
        best_s[better] = start[i] + t[better] * length[i]
        best_i[better] = i
    return best_s, best_d, best_i


def _node_arcs(cm, edges, fracture, origin, f: int) -> np.ndarray:
    """(e, 3) signed arc length from `origin` of the [a, b, mid] nodes of
    the crack edges selected by the mask `edges`, all on `fracture`. An
    edge's nodes are measured on the segment that holds its mid node: an end
    node can also lie on another segment (where a fracture ends on itself)."""
    points = np.asarray(fracture.points, dtype=np.float64)
    scale = float(np.linalg.norm(np.diff(points, axis=0), axis=1).sum())
    nodes = np.asarray(cm.crack_edges, dtype=np.int64)[edges]
    x = np.asarray(cm.x, float)
    segment = _polyline_arc(points, x[nodes[:, 2]])[2]
    s, dist, _ = _polyline_arc(points, x[nodes.ravel()], np.repeat(segment, 3))
    s0, d0, _ = _polyline_arc(points, np.asarray(origin, float).reshape(1, 2))
    if dist.max() > ON_POLYLINE * scale:
        raise ValueError(f"slip history: fracture {f}'s mesh nodes lie off its polyline (mesh of other fractures?)")
    if d0[0] > ON_POLYLINE * scale:
        raise ValueError(f"slip history: fracture {f} no longer passes through its arc-length origin")
    return (s - s0[0]).reshape(-1, 3)


def _evaluate(old_arc: np.ndarray, old_slip: np.ndarray, new_arc: np.ndarray) -> np.ndarray:
    """The P2 field of the old edges (ascending, contiguous) at the arc
    lengths new_arc (n, 3) of new [a, b, mid] nodes; 0 outside their extent."""
    sa, sb, sm = old_arc[:, 0], old_arc[:, 1], old_arc[:, 2]
    lo, hi = sa[0], sb[-1]
    length = sb - sa
    probe_step = min(SIDE_PROBE * max(abs(lo), abs(hi), hi - lo), 0.25 * float(length.min()))
    # an end node looks into its own new edge: at a node two old edges share
    # it reads the old edge on the same side (the two host pairs at a T differ),
    # and a new wing's first node past an old tip reads nothing
    probe = new_arc + np.array([probe_step, -probe_step, 0.0])
    slack = np.array([0.0, 0.0, probe_step])
    inside = (probe >= lo - slack) & (probe <= hi + slack)
    e = np.clip(np.searchsorted(sa, probe, side="right") - 1, 0, len(sa) - 1)
    # a node within the probe of an old node is that node: next to a tip the
    # field goes as sqrt(rho), which would turn round-off into sqrt(round-off)
    u = np.clip((new_arc - sa[e]) / length[e], 0.0, 1.0)
    u = np.where(new_arc - sa[e] <= probe_step, 0.0, np.where(sb[e] - new_arc <= probe_step, 1.0, u))
    # u(xi) = xi (2 xi - 1) + 4 r xi (1 - xi), r the mid node's place (1/2;
    # 1/4 or 3/4 for a quarter point, the extremes a valid edge can have): the
    # root in [0, 1], in the form without cancellation (and without dividing by
    # A = 0 on a plain edge). r is not rounded to 1/4 or 3/4: u = r must give
    # xi = 1/2 exactly for the mid node to read back its own value.
    r = (sm[e] - sa[e]) / length[e]
    A, B = 2.0 - 4.0 * r, 4.0 * r - 1.0
    den = B + np.sqrt(np.maximum(B * B + 4.0 * A * u, 0.0))
    xi = np.divide(2.0 * u, den, out=np.zeros_like(u), where=den > 0.0)
    shape = np.stack([(1 - xi) * (1 - 2 * xi), xi * (2 * xi - 1), 4 * xi * (1 - xi)], axis=-1)
    value = np.einsum("nqi,nqi->nq", shape, old_slip[e])
    return np.where(inside, value, 0.0)
