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

Multipliers mu act as nodal forces +mu v on the + node and -mu v on the -
node (v = n or t); mu >= 0 pushes the faces apart. Per unit length, the
normal traction on the faces is sigma_nn = -mu / w_p, with w_p the integral
of the node's P2 shape function along the face (its tributary length).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import wingcrack_kernels as K

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
    friction: np.ndarray = None   # (m,) mu_f on Coulomb rows (0 elsewhere)
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
        from .friction import FrictionRows

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


def _part(fracture, position, tol):
    """(faces, gap, slip-bearing polyline) of the part of `fracture` at
    `position`: its pre-existing polyline, or a wing grown from it (wings:
    fracture.wing_faces(), no gap, no slip). Case fractures have no wings."""
    pre = getattr(fracture, "pre_points", None)
    if pre is None:
        return fracture.faces, fracture.gap, np.asarray(fracture.points, float)
    if K.point_polyline_distance(np.asarray(position, float), pre) <= tol:
        return fracture.faces, fracture.gap, pre
    return fracture.wing_faces(), 0.0, None


def pre_existing_pairs(cm, fractures) -> np.ndarray:
    """(p,) bool: the pairs of `cm` on the pre-existing part of their
    fracture (not on a wing it grew), as _part tells them."""
    pairs = np.asarray(cm.pairs, dtype=np.int64).reshape(-1, 2)
    pfrac = np.asarray(cm.pair_fracture, dtype=np.int64)
    x = np.asarray(cm.x)
    tol = 1e-9 * float(np.ptp(x, axis=0).max()) if len(x) else 0.0
    return np.array([_part(fractures[pfrac[i]], x[pairs[i, 0]], tol)[2] is not None for i in range(len(pairs))],
                    bool)


def slip_profile(fracture, position, pts=None) -> float:
    """Prescribed slip (load factor 1) at `position` on `fracture`.

    "uniform": the value everywhere (a dislocation at the tips, as in the
    paper). "elliptic": slip * sqrt(1 - (xi/a)^2), xi the arc length from the
    fracture's middle and a its half-length: the slip of a crack under a
    uniform shear stress drop tau, slip = (kappa + 1) tau a / (2 mu)."""
    if fracture.slip_profile == "elliptic":
        pts = np.asarray(fracture.points if pts is None else pts, float)
        L = float(np.sum(np.linalg.norm(np.diff(pts, axis=0), axis=1)))
        xi = _arc_length(position, pts) - L / 2
        return fracture.slip * np.sqrt(max(0.0, 1.0 - (xi / (L / 2)) ** 2))
    return fracture.slip


#: normals closer to parallel than this (|sin|) add no second row: it would repeat the first
PARALLEL = 0.1


def _meeting_normals(cm, pairs, pfrac) -> dict:
    """{frozenset(plus, minus): [(fracture, unit left normal of its face,
    oriented from minus to plus)]} for the pairs whose two nodes are held by
    the faces of more than one fracture (fractures met end to end), the
    pair's own fracture first."""
    x = np.asarray(cm.x)
    plus_e = np.asarray(cm.crack_edges, dtype=np.int64).reshape(-1, 3)
    minus_e = np.asarray(cm.crack_edges_minus, dtype=np.int64).reshape(-1, 3)
    efrac = np.asarray(cm.crack_fracture, dtype=np.int64)
    touching: dict = {}   # node -> {fracture: (side, left normal)}
    for e in range(len(plus_e)):
        d = x[plus_e[e, 1]] - x[plus_e[e, 0]]
        n = np.array([-d[1], d[0]]) / np.linalg.norm(d)
        for side, edge in ((1.0, plus_e[e]), (-1.0, minus_e[e])):
            for v in edge[:2]:
                touching.setdefault(int(v), {})[int(efrac[e])] = (side, n)
    out = {}
    for i, (a, b) in enumerate(pairs):   # nodes a (plus) and b (minus)
        ta, tb = touching.get(int(a), {}), touching.get(int(b), {})
        shared = sorted(g for g in set(ta) & set(tb) if ta[g][0] != tb[g][0])
        if len(shared) > 1:   # the own fracture first
            shared.sort(key=lambda g: g != pfrac[i])
            out[frozenset((int(a), int(b)))] = [(g, ta[g][0] * ta[g][1]) for g in shared]
    return out


def _junction_pairs(pairs, pfrac) -> set:
    """Pairs with a node copy that pairs of another fracture share: at a
    T-junction the host's two pairs there and the joining fracture's (whose
    jump is the difference of the host's two), where fractures meet end to
    end the one pair of both. There the jumps have fewer independent
    components than the pairs have normal and tangential rows, so a Coulomb
    pair there keeps its normal row only (non-penetration stays on every
    face; the junction node itself slides without friction): with all rows
    the pair system is singular once they are all closed, and with the
    joining pair's rows dropped instead its faces interpenetrate at the
    junction while the host's slip."""
    owners = {}
    for i, (a, b) in enumerate(pairs):
        for v in (int(a), int(b)):
            owners.setdefault(v, set()).add(int(pfrac[i]))
    return {i for i, (a, b) in enumerate(pairs) if len(owners[int(a)]) > 1 or len(owners[int(b)]) > 1}


def constraint_rows(cm, fractures) -> ConstraintRows:
    """Rows for every pair of the CrackMesh `cm`; `fractures` are the case's
    Fracture objects (faces, gap, slip, slip_profile) or the propagation's
    GrowingFracture objects (whose wings get their own faces), in mesh order."""
    pairs = np.asarray(cm.pairs, dtype=np.int64).reshape(-1, 2)
    normals = np.asarray(cm.pair_normal, float).reshape(-1, 2)
    pfrac = np.asarray(cm.pair_fracture, dtype=np.int64)
    w_pair = pair_tributary_lengths(cm, pfrac)
    rows = {k: [] for k in ("plus", "minus", "direction", "kind", "pair", "fracture", "gap", "slip", "weight", "position",
                            "coulomb", "partner", "friction", "cohesion")}

    def add(i, v, kind, gap, slip, weight=None, law=None):
        """law: (normal row, friction, cohesion) of a Coulomb row."""
        plus, minus = pairs[i]
        rows["plus"].append(plus)
        rows["minus"].append(minus)
        rows["direction"].append(v)
        rows["kind"].append(kind)
        rows["pair"].append(i)
        rows["fracture"].append(pfrac[i])
        rows["gap"].append(gap)
        rows["slip"].append(slip)
        rows["weight"].append(w_pair[i] if weight is None else weight)
        rows["position"].append(cm.x[plus])
        rows["coulomb"].append(law is not None)
        rows["partner"].append(-1 if law is None else law[0])
        rows["friction"].append(0.0 if law is None else law[1])
        rows["cohesion"].append(0.0 if law is None else law[2])

    x = np.asarray(cm.x)
    tol = 1e-9 * float(np.ptp(x, axis=0).max()) if len(x) else 0.0
    parts = [_part(fractures[pfrac[i]], x[pairs[i, 0]], tol) for i in range(len(pairs))]
    # At a T-junction a node copy belongs to pairs of two fractures. If the
    # host prescribes slip there, the joining fracture's own pair would repeat
    # a combination of the host's rows (a singular pair system): it gets none.
    slip_nodes = {int(v) for i, part in enumerate(parts) if part[0] == "slip" for v in pairs[i]}
    junction = _junction_pairs(pairs, pfrac)
    # Where two fractures meet end to end, both own the same two node copies:
    # one pair (the first); its rows get each fracture's normal (unless
    # parallel), since the copies must not overlap across either face.
    seen, meeting = set(), _meeting_normals(cm, pairs, pfrac)
    w_of = {}   # fracture -> pair lengths over its faces only (meeting nodes)
    for i in range(len(pairs)):
        f = fractures[pfrac[i]]
        faces, gap, pts = parts[i]
        if faces == "open" or (faces != "slip" and slip_nodes.intersection(pairs[i].tolist())):
            continue
        key = frozenset(pairs[i].tolist())
        if key in seen:
            continue
        seen.add(key)
        n = normals[i]
        if key in meeting:
            # fractures meeting end to end: a row per fracture's own normal (the
            # pair's normal is their average), each with its own face length
            used = []
            for g, n_g in meeting[key]:
                if all(abs(n_g[0] * u[1] - n_g[1] * u[0]) > PARALLEL for u in used):
                    used.append(n_g)
                    if g not in w_of:
                        w_of[g] = pair_tributary_lengths(cm, np.full(len(pairs), g))
                    add(i, n_g, NORMAL, gap, 0.0, weight=w_of[g][i])
            n = used[0]
            first = len(rows["plus"]) - len(used)
            if len(used) > 1:
                # two normals that are not parallel fix both components of the jump when closed: a
                # tangential row would repeat them (a singular pair system where the fractures meet
                # at a right angle, t of one being n of the other); the meeting node slides without
                # friction, as a T-junction's does
                continue
        else:
            first = len(rows["plus"])
            add(i, n, NORMAL, gap, 0.0)
        t = np.array([n[1], -n[0]])
        if faces == "slip":
            add(i, t, TANGENTIAL, 0.0, slip_profile(f, x[pairs[i, 0]], pts))
        elif faces == "coulomb" and i not in junction:
            add(i, t, TANGENTIAL, 0.0, 0.0, law=(first, float(f.friction), float(f.cohesion)))
    m = len(rows["plus"])
    return ConstraintRows(
        plus=np.array(rows["plus"], dtype=np.int64), minus=np.array(rows["minus"], dtype=np.int64),
        direction=np.array(rows["direction"], float).reshape(m, 2), kind=np.array(rows["kind"], dtype=np.int8),
        pair=np.array(rows["pair"], dtype=np.int64), fracture=np.array(rows["fracture"], dtype=np.int64),
        gap=np.array(rows["gap"], float), slip=np.array(rows["slip"], float),
        weight=np.array(rows["weight"], float), position=np.array(rows["position"], float).reshape(m, 2),
        coulomb=np.array(rows["coulomb"], bool), partner=np.array(rows["partner"], dtype=np.int64),
        friction=np.array(rows["friction"], float), cohesion=np.array(rows["cohesion"], float))
