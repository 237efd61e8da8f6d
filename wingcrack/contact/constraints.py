"""Constraint rows on the matched node pairs of the fracture faces.

Each pair (plus, minus) of coinciding nodes on the + and - faces gives
- a normal row: the opening w = (u+ - u-).n, with n the unit left normal of
  the fracture direction (pointing from the - face into the + side);
  non-penetration w + g >= 0 (g the initial gap), on "frictionless",
  "slip" and "coulomb" faces;
- a tangential row on "slip" faces: the slip s = (u+ - u-).t,
  t = fracture direction, equals the prescribed slip times the load factor;
- a tangential row on "coulomb" faces (normal row first, then this one):
  the friction law on the slip increment (contact.friction), with the
  fracture's friction coefficient and cohesion (wings: the same).
Pairs on "open" faces carry no row. Tips are not pairs.

The rows' forces (the contact multipliers) act as nodal forces +f v on the
+ node and -f v on the - node (v = n or t); f >= 0 pushes the faces apart.
Per unit length, the normal traction on the faces is sigma_nn = -f / w_p,
with w_p the integral of the node's P2 shape function along the face (its
tributary length).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import wingcrack_kernels as K

from ..face_law import FACES

NORMAL, TANGENTIAL = 0, 1


@dataclass
class ConstraintRows:
    plus: np.ndarray       # (m,) CrackMesh node on the + face
    minus: np.ndarray      # (m,) node on the - face
    direction: np.ndarray  # (m, 2) n (normal rows) or t (tangential rows)
    kind: np.ndarray       # (m,) NORMAL | TANGENTIAL
    pair: np.ndarray       # (m,) index into CrackMesh.pairs
    fracture: np.ndarray   # (m,)
    gap: np.ndarray        # (m,) initial gap g (normal rows; 0 otherwise)
    slip: np.ndarray       # (m,) prescribed slip at load factor 1 (tangential rows)
    weight: np.ndarray     # (m,) tributary length of the pair's nodes (m)
    position: np.ndarray   # (m, 2)
    coulomb: np.ndarray = None    # (m,) bool: tangential rows under the friction law
    partner: np.ndarray = None    # (m,) a Coulomb row's normal row (-1 elsewhere)
    friction: np.ndarray = None   # (m,) the Coulomb coefficient on Coulomb rows (0 elsewhere)
    cohesion: np.ndarray = None   # (m,) c (Pa) on Coulomb rows (0 elsewhere)

    def __len__(self):
        return len(self.plus)

    def __post_init__(self):
        m = len(self.plus)
        if self.coulomb is None:
            self.coulomb = np.zeros(m, bool)
            self.partner = np.full(m, -1, np.int64)
            self.friction = np.zeros(m)
            self.cohesion = np.zeros(m)

    @property
    def normal(self) -> np.ndarray:
        return self.kind == NORMAL

    def friction_law(self):
        """contact.friction.FrictionRows of these rows."""
        from .friction import FrictionRows   # overlap: its scipy.optimize loads at the first solve, not with the step

        return FrictionRows(self.coulomb, self.partner, self.friction, self.cohesion * self.weight)


def _gauss3():
    x = np.array([-np.sqrt(0.6), 0.0, np.sqrt(0.6)])
    return (x + 1) / 2, np.array([5.0, 8.0, 5.0]) / 18


def tributary_lengths(x: np.ndarray, edges: np.ndarray, num_nodes: int) -> np.ndarray:
    """int N_k ds over the P2 face edges [a, b, mid], per node (quarter-point
    edges included: the isoparametric map is integrated, not assumed affine)."""
    contrib = edge_integrals(x, edges)
    w = np.zeros(num_nodes)
    np.add.at(w, edges.ravel(), contrib.ravel())
    return w


def pair_tributary_lengths(cm, fracture=None) -> np.ndarray:
    """(p,) int N ds of each pair of `cm` over the face edges that hold both
    of its nodes (at a T-junction a node copy also borders the other
    fracture's faces: those do not count), of fracture[i] only when given
    (where two fractures meet end to end they share the pair's nodes)."""
    plus_e = np.asarray(cm.crack_edges, dtype=np.int64).reshape(-1, 3)
    minus_e = np.asarray(cm.crack_edges_minus, dtype=np.int64).reshape(-1, 3)
    pairs = np.asarray(cm.pairs, dtype=np.int64).reshape(-1, 2)
    n = len(cm.x)
    contrib = edge_integrals(np.asarray(cm.x), plus_e)
    if fracture is not None:   # a pair's key also carries its fracture
        nf = int(max(np.max(cm.crack_fracture, initial=0), np.max(fracture, initial=0))) + 1
        efrac = np.repeat(np.asarray(cm.crack_fracture, dtype=np.int64), 3)
        edge_keys = (plus_e * n + minus_e).ravel() * nf + efrac
        pair_keys = (pairs[:, 0] * n + pairs[:, 1]) * nf + np.asarray(fracture, dtype=np.int64)
        return _sum_by_key(edge_keys, pair_keys, contrib)
    edge_keys = (plus_e * n + minus_e).ravel()
    pair_keys = pairs[:, 0] * n + pairs[:, 1]
    return _sum_by_key(edge_keys, pair_keys, contrib)


def _sum_by_key(edge_keys, pair_keys, contrib):
    """Sum the edge-node contributions onto the pairs with the same key."""
    order = np.argsort(pair_keys)
    where = np.searchsorted(pair_keys[order], edge_keys)
    where = np.minimum(where, len(order) - 1) if len(order) else where
    found = pair_keys[order][where] == edge_keys if len(order) else np.zeros(0, bool)
    w = np.zeros(len(pair_keys))
    np.add.at(w, order[where[found]], contrib.ravel()[found])
    return w


def edge_integrals(x: np.ndarray, edges: np.ndarray) -> np.ndarray:
    """(k, 3) int N_i ds of the 3 nodes of each P2 edge."""
    s, wq = _gauss3()
    # 1D P2 shape functions on [0, 1] in the order a (0), b (1), mid (1/2)
    N = np.stack([(1 - s) * (1 - 2 * s), s * (2 * s - 1), 4 * s * (1 - s)])   # (3, q)
    dN = np.stack([4 * s - 3, 4 * s - 1, 4 - 8 * s])
    X = x[edges]                                     # (k, 3, 2)
    dx = np.einsum("iq,kid->kqd", dN, X)             # (k, q, 2)
    jac = np.linalg.norm(dx, axis=2)                 # (k, q)
    return np.einsum("iq,kq,q->ki", N, jac, wq)     # (k, 3)


def _arc_length(p, pts) -> float:
    dist, _, seg, t = K.closest_point_on_polyline(np.asarray(p, float), pts)
    lengths = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    return float(np.sum(lengths[:seg]) + t * lengths[seg])


def _parts(fractures, position, pfrac, tol):
    """(laws, lines, part): the face laws of the fractures' parts, laws[2 g]
    fracture g's own (its pre-existing polyline, lines[2 g]) and laws[2 g
    + 1] its wings' (law.wings(): no gap, no slip; lines[2 g + 1] None),
    and part (p,) the part each pair at `position` (p, 2) of fracture pfrac
    lies on: a case fracture has no wings; a growing one's pair lies on its
    pre-existing polyline when within tol of it."""
    laws, lines = [], []
    part = 2 * pfrac
    for g, f in enumerate(fractures):
        law = f.law
        pre = getattr(f, "pre_points", None)
        laws += [law, law.wings()]
        lines += [np.asarray(f.points if pre is None else pre, float), None]
        if pre is not None:
            mine = np.flatnonzero(pfrac == g)
            part[mine[K.point_polyline_distances(position[mine], pre) > tol]] += 1
    return laws, lines, part


def pre_existing_pairs(cm, fractures) -> np.ndarray:
    """(p,) bool: the pairs of `cm` on the pre-existing part of their
    fracture (not on a wing it grew), as _parts tells them."""
    pairs = np.asarray(cm.pairs, dtype=np.int64).reshape(-1, 2)
    pfrac = np.asarray(cm.pair_fracture, dtype=np.int64)
    x = np.asarray(cm.x)
    tol = 1e-9 * float(np.ptp(x, axis=0).max()) if len(x) else 0.0
    return _parts(fractures, x[pairs[:, 0]], pfrac, tol)[2] % 2 == 0


def least_apertures(cm, fractures, residual: float) -> np.ndarray:
    """(p,) the least aperture of each pair for the flow along the
    fractures (m): `residual` (the case's residual aperture) on the wings
    of fractures whose faces the contact holds apart (every law but
    "open"), 0 elsewhere. A wing the contact shuts still leaves the fluid
    its rough faces' path; without one its flow nodes stored and conducted
    nothing, an equation without a derivative (the stimulation network's
    flow failed at its second growth, and with a thousandth or a
    hundredth of the residual aperture at its second or fourth). An open
    fracture's faces never touch: its wings hold their opening (the
    viscous tip's asymptote); a pre-existing face holds its residual
    aperture on top of its opening (flow_march.apertures)."""
    held = np.array([f.law.faces != "open" for f in fractures], bool)
    pfrac = np.asarray(cm.pair_fracture, dtype=np.int64)
    return residual * (held[pfrac] & ~pre_existing_pairs(cm, fractures))


def slip_profile(law, position, pts) -> float:
    """Prescribed slip (load factor 1) at `position` on the polyline `pts`
    of faces under `law`.

    "uniform": law.slip everywhere (a dislocation at the tips, as in the
    paper). "elliptic": slip * sqrt(1 - (xi/a)^2), xi the arc length from the
    fracture's middle and a its half-length: the slip of a crack under a
    uniform shear stress drop tau, slip = (kappa + 1) tau a / (2 G), G the
    shear modulus."""
    if law.slip_profile == "elliptic":
        pts = np.asarray(pts, float)
        L = float(np.sum(np.linalg.norm(np.diff(pts, axis=0), axis=1)))
        xi = _arc_length(position, pts) - L / 2
        return law.slip * np.sqrt(max(0.0, 1.0 - (xi / (L / 2)) ** 2))
    return law.slip


#: normals closer to parallel than this (|sin|) add no second row: it would repeat the first
PARALLEL = 0.1


def _meeting_normals(cm, pairs, pfrac) -> dict:
    """{frozenset(plus, minus): [(fracture, unit left normal of its face,
    oriented from minus to plus)]} for the pairs whose two nodes are held by
    the faces of more than one fracture (fractures met end to end), the
    fracture of the pair listed last for those nodes first. Only the face
    edges at nodes that faces of two fractures hold are looked at, one by
    one (few: where fractures meet)."""
    x = np.asarray(cm.x)
    plus_e = np.asarray(cm.crack_edges, dtype=np.int64).reshape(-1, 3)
    minus_e = np.asarray(cm.crack_edges_minus, dtype=np.int64).reshape(-1, 3)
    efrac = np.asarray(cm.crack_fracture, dtype=np.int64)
    shared = _shared_nodes(np.concatenate([plus_e[:, :2], minus_e[:, :2]]), np.tile(efrac, 2), len(x))
    touching: dict = {}   # node -> {fracture: (side, left normal)}
    for e in np.flatnonzero(shared[plus_e[:, :2]].any(axis=1) | shared[minus_e[:, :2]].any(axis=1)):
        d = x[plus_e[e, 1]] - x[plus_e[e, 0]]
        n = np.array([-d[1], d[0]]) / np.linalg.norm(d)
        for side, edge in ((1.0, plus_e[e]), (-1.0, minus_e[e])):
            for v in edge[:2]:
                touching.setdefault(int(v), {})[int(efrac[e])] = (side, n)
    out = {}
    for i in np.flatnonzero(shared[pairs].all(axis=1)):   # nodes a (plus) and b (minus)
        a, b = pairs[i]
        ta, tb = touching.get(int(a), {}), touching.get(int(b), {})
        held = sorted(g for g in set(ta) & set(tb) if ta[g][0] != tb[g][0])
        if len(held) > 1:   # the own fracture first
            held.sort(key=lambda g: g != pfrac[i])
            out[frozenset((int(a), int(b)))] = [(g, ta[g][0] * ta[g][1]) for g in held]
    return out


def _shared_nodes(nodes, owner, num_nodes) -> np.ndarray:
    """(num_nodes,) bool: the nodes that the rows of `nodes` (k, c) of more
    than one owner (k,) hold."""
    held = np.unique(np.stack([nodes.ravel(), np.repeat(owner, nodes.shape[1])], axis=1), axis=0)
    return np.bincount(held[:, 0], minlength=num_nodes) > 1


def _junction_pairs(pairs, pfrac, num_nodes) -> np.ndarray:
    """(p,) bool: the pairs with a node copy that pairs of another fracture
    share: at a T-junction the host's two pairs there and the joining
    fracture's (whose jump is the difference of the host's two), where
    fractures meet end to end the one pair of both. There the jumps have
    fewer independent components than the pairs have normal and tangential
    rows, so a Coulomb pair there keeps its normal row only
    (non-penetration stays on every face; the junction node itself slides
    without friction): with all rows the pair system is singular once they
    are all closed, and with the joining pair's rows dropped instead its
    faces interpenetrate at the junction while the host's slip."""
    return _shared_nodes(pairs, pfrac, num_nodes)[pairs].any(axis=1)


_FACE_CODE = {name: code for code, name in enumerate(FACES)}
_OPEN, _SLIP, _COULOMB = _FACE_CODE["open"], _FACE_CODE["slip"], _FACE_CODE["coulomb"]


def constraint_rows(cm, fractures) -> ConstraintRows:
    """Rows for every pair of the CrackMesh `cm`; `fractures`, in mesh
    order, are the case's Fracture objects or the propagation's
    GrowingFracture objects (whose wings get their own faces): what is read
    of each is its face law (`law`, wingcrack.face_law.FaceLaw) and its
    polylines.

    A pair's rows: a normal row (where fractures meet end to end, one per
    fracture's normal that is not parallel to another's), then, on "slip"
    faces, the prescribed tangential row, on "coulomb" faces away from
    junctions the friction row."""
    pairs = np.asarray(cm.pairs, dtype=np.int64).reshape(-1, 2)
    normals = np.asarray(cm.pair_normal, float).reshape(-1, 2)
    pfrac = np.asarray(cm.pair_fracture, dtype=np.int64)
    w_pair = pair_tributary_lengths(cm, pfrac)
    x = np.asarray(cm.x)
    tol = 1e-9 * float(np.ptp(x, axis=0).max()) if len(x) else 0.0
    laws, lines, part = _parts(fractures, x[pairs[:, 0]], pfrac, tol)
    faces = np.array([_FACE_CODE[law.faces] for law in laws], dtype=np.int64)[part] if len(laws) else part
    # At a T-junction a node copy belongs to pairs of two fractures. If the
    # host prescribes slip there, the joining fracture's own pair would repeat
    # a combination of the host's rows (a singular pair system): it gets none.
    on_slip = np.zeros(len(x), bool)
    on_slip[pairs[faces == _SLIP].ravel()] = True
    keep = (faces != _OPEN) & ((faces == _SLIP) | ~on_slip[pairs].any(axis=1))
    # Where two fractures meet end to end, both own the same two node copies:
    # one pair (the first) gets rows; they get each fracture's normal (unless
    # parallel), since the copies must not overlap across either face.
    kept = np.flatnonzero(keep)
    if len(kept):
        _, first = np.unique(np.sort(pairs[kept], axis=1), axis=0, return_index=True)
        kept = np.sort(kept[first])
    n = normals[kept]   # the normal each kept pair's tangential row turns
    tangential = (faces[kept] == _SLIP) | ((faces[kept] == _COULOMB) & ~_junction_pairs(pairs, pfrac, len(x))[kept])
    n_normal = np.ones(len(kept), dtype=np.int64)
    used = {}   # kept pair -> [(normal, weight)] of its rows where fractures meet end to end
    w_of = {}   # fracture -> pair lengths over its faces only (meeting nodes)
    ends = np.sort(pairs[kept], axis=1)
    for key, held in _meeting_normals(cm, pairs, pfrac).items():
        for j in np.flatnonzero((ends[:, 0] == min(key)) & (ends[:, 1] == max(key))):
            i, rows = kept[j], []
            for g, n_g in held:
                if all(abs(n_g[0] * u[1] - n_g[1] * u[0]) > PARALLEL for u, _ in rows):
                    if g not in w_of:
                        w_of[g] = pair_tributary_lengths(cm, np.full(len(pairs), g))
                    rows.append((n_g, w_of[g][i]))
            used[j], n[j], n_normal[j] = rows, rows[0][0], len(rows)
            # two normals that are not parallel fix both components of the jump when closed: a tangential
            # row would repeat them (a singular pair system where the fractures meet at a right angle, t of
            # one being n of the other); the meeting node slides without friction, as a T-junction's does
            tangential[j] &= len(rows) == 1
    # the rows: per kept pair its normal rows, then its tangential row
    count = n_normal + tangential
    start = np.cumsum(count) - count   # the pair's first (normal) row
    pair = np.repeat(kept, count)
    normal = np.arange(len(pair)) - np.repeat(start, count) < np.repeat(n_normal, count)
    direction = normals[pair]
    direction[~normal] = np.stack([n[tangential, 1], -n[tangential, 0]], axis=1)
    weight = w_pair[pair]
    for j, rows in used.items():
        direction[start[j]:start[j] + len(rows)] = [v for v, _ in rows]
        weight[start[j]:start[j] + len(rows)] = [w for _, w in rows]
    row_part = part[pair]
    law_of = np.array([[law.gap, law.friction, law.cohesion, law.slip] for law in laws]).reshape(-1, 4)[row_part]
    code = faces[pair]
    coulomb = ~normal & (code == _COULOMB)
    slip = np.zeros(len(pair))
    prescribed = np.flatnonzero(~normal & (code == _SLIP))
    slip[prescribed] = law_of[prescribed, 3]
    elliptic = np.array([law.slip_profile == "elliptic" for law in laws], bool)
    for r in prescribed[elliptic[row_part[prescribed]]]:   # the arc length of each along its fracture
        slip[r] = slip_profile(laws[row_part[r]], x[pairs[pair[r], 0]], lines[row_part[r]])
    return ConstraintRows(
        plus=pairs[pair, 0], minus=pairs[pair, 1], direction=direction,
        kind=np.where(normal, NORMAL, TANGENTIAL).astype(np.int8), pair=pair,
        fracture=pfrac[pair], gap=np.where(normal, law_of[:, 0], 0.0), slip=slip, weight=weight,
        position=x[pairs[pair, 0]].reshape(-1, 2), coulomb=coulomb,
        partner=np.where(coulomb, np.repeat(start, count), -1),
        friction=np.where(coulomb, law_of[:, 1], 0.0), cohesion=np.where(coulomb, law_of[:, 2], 0.0))
