"""The fluid's network on the fracture faces: where the flow lives.

A flow node is a point of the faces: every copy of a face node (the + and
- copy of a pair, the three copies of a T-junction, the two of fractures
met end to end, a tip's single node) is one flow node, found by its
coordinates (the mesher gives every copy the same ones). So the pressure is
continuous where fractures meet, and the flux is conserved there (the weak
form sums every segment at a node).

Each P2 crack edge [a, b, mid] (its + and - copies) carries two straight
flow segments, a-mid and mid-b: the pressure is piecewise linear in arc
length (P1 on the edges' nodes). P1 keeps every storage weight positive on
the quarter-point edges next to the tips (a P2 pressure on an edge whose mid
node sits at a quarter has a negative weight at the tip) and the
conductance matrix an M-matrix: a steep pressure front does not oscillate.

The faces' opening w = [u].n is the mechanics' P2 field on the isoparametric
edge (its sqrt(r) profile on the quarter-point edges). The network's
functionals are exact for it: on each half of an edge the hat functions are
linear in arc length s, s quadratic in the edge coordinate xi, the opening
quadratic and the Jacobian linear, so 4 Gauss points a half integrate
   V_i = int phi_i w ds     (degree 5: the volume held at node i),
   int phi_i N_k n ds       (the load of a nodal pressure: its transpose),
   int w^3 ds               (degree 7: the cubic law's conductance)
exactly. The load of the pressure field sum p_i phi_i and the volume
functional are transposes of each other: the pressure's work is p . V.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import sparse

#: Gauss-Legendre points a half edge: exact to degree 7 (the conductance's w^3 J)
GAUSS_POINTS = 4


def _gauss(n: int):
    g, w = np.polynomial.legendre.leggauss(n)
    return (g + 1) / 2, w / 2


def _p2(xi):
    """P2 shape functions and derivatives on [0, 1] in the edge order a, b, mid."""
    xi = np.asarray(xi, float)
    N = np.stack([(1 - xi) * (1 - 2 * xi), xi * (2 * xi - 1), 4 * xi * (1 - xi)], axis=-1)
    dN = np.stack([4 * xi - 3, 4 * xi - 1, 4 - 8 * xi], axis=-1)
    return N, dN


def edge_normals(cm) -> np.ndarray:
    """(k, 2) the unit normal n of each crack edge of `cm`: the left normal of
    its direction a -> b, oriented as the pair normal of its mid node (a mid
    node is never a tip): n points from the - face into the + side, the
    direction of the opening w = [u].n."""
    x = np.asarray(cm.x, float)
    plus = np.asarray(cm.crack_edges, dtype=np.int64).reshape(-1, 3)
    d = x[plus[:, 1]] - x[plus[:, 0]]
    n = np.c_[-d[:, 1], d[:, 0]] / np.linalg.norm(d, axis=1)[:, None]
    pairs = np.asarray(cm.pairs, dtype=np.int64).reshape(-1, 2)
    pn = np.asarray(cm.pair_normal, float).reshape(-1, 2)
    order = np.argsort(pairs[:, 0])
    ref = pn[order[np.searchsorted(pairs[order, 0], plus[:, 2])]]
    return n * np.sign(np.sum(n * ref, axis=1))[:, None]


def edge_pairs(cm, plus, minus) -> np.ndarray:
    """(k, 3) the row of cm.pairs holding each edge node's + copy `plus`
    (k, 3) and - copy `minus`; -1 at a tip (one node, both faces): every
    other edge node's copies face each other as a pair."""
    pairs = np.asarray(cm.pairs, dtype=np.int64).reshape(-1, 2)
    n = len(cm.x)
    keys = pairs[:, 0] * n + pairs[:, 1]
    order = np.argsort(keys)
    want = (np.asarray(plus, np.int64) * n + np.asarray(minus, np.int64)).ravel()
    at = np.minimum(np.searchsorted(keys[order], want), max(len(keys) - 1, 0))
    found = keys[order][at] == want if len(keys) else np.zeros(len(want), bool)
    out = np.where(found, order[at] if len(keys) else -1, -1)
    tip = (np.asarray(plus) == np.asarray(minus)).ravel()
    if np.any(~found & ~tip):
        raise ValueError("a crack edge's face copies are no pair of the mesh (a bug in the mesher)")
    return out.reshape(-1, 3)


@dataclass(frozen=True, eq=False)
class FlowNetwork:
    """The flow's nodes and segments on a crack mesh's faces (module doc).

    Edges are the mesh's crack edges of the network's fractures, in the
    mesh's order; segment 2 e is edge e's a-mid half, 2 e + 1 its mid-b
    half, each oriented along the fracture direction."""

    #: (n, 2) the flow nodes' coordinates (m)
    x: np.ndarray
    #: (k, 3) the flow nodes [a, b, mid] of each edge
    edges: np.ndarray
    #: (k,) each edge's row in the CrackMesh's crack_edges
    edge_index: np.ndarray
    #: (k,) each edge's fracture
    fracture: np.ndarray
    #: (k, 3) the mesh nodes of each edge's + face copy, and (k, 3) of its - copy
    plus: np.ndarray
    minus: np.ndarray
    #: (k, 2) each edge's unit normal n (edge_normals)
    normal: np.ndarray
    #: (k, 3) the CrackMesh pair (row of cm.pairs) of each edge node's + and - copies; -1 at a tip
    pair: np.ndarray
    #: (k, 3, 2) the normal an edge node's opening is measured along: its pair's (the contact rows'
    #: normal: at a kink of a polyline the mean of its two edges'), the edge's at a tip
    node_normal: np.ndarray
    #: (2k, 2) the flow nodes at each segment's ends, and (2k,) its length (m)
    segments: np.ndarray
    length: np.ndarray
    #: (2k, q, 3) the edge's P2 shape functions at each segment's quadrature points,
    #: (2k, q) their weights times the Jacobian (ds), (2k, q, 2) the segment's two hats there
    shape: np.ndarray
    ds: np.ndarray
    hat: np.ndarray

    @classmethod
    def of(cls, cm, fractures=None) -> "FlowNetwork":
        """The network of the crack edges of `fractures` (indices; None:
        every fracture of `cm`)."""
        x = np.asarray(cm.x, float)
        plus_all = np.asarray(cm.crack_edges, dtype=np.int64).reshape(-1, 3)
        minus_all = np.asarray(cm.crack_edges_minus, dtype=np.int64).reshape(-1, 3)
        frac_all = np.asarray(cm.crack_fracture, dtype=np.int64)
        keep = np.ones(len(plus_all), bool) if fractures is None else np.isin(frac_all, np.asarray(fractures))
        index = np.flatnonzero(keep)
        plus, minus = plus_all[index], minus_all[index]
        normal = edge_normals(cm)[index] if len(index) else np.zeros((0, 2))
        pair = edge_pairs(cm, plus, minus)
        pn = np.asarray(cm.pair_normal, float).reshape(-1, 2)
        node_normal = np.where((pair >= 0)[:, :, None], pn[np.maximum(pair, 0)], normal[:, None, :])
        # one flow node per distinct point of the faces (every copy of a mesh node has its coordinates)
        pts, inverse = np.unique(x[plus].reshape(-1, 2), axis=0, return_inverse=True)
        edges = inverse.reshape(-1, 3).astype(np.int64)
        segments = np.stack([edges[:, [0, 2]], edges[:, [2, 1]]], axis=1).reshape(-1, 2)
        g, w = _gauss(GAUSS_POINTS)
        X = x[plus]                                                      # (k, 3, 2)
        shape, ds, hat = [], [], []
        for half in (0, 1):
            xi = (half + g) / 2
            N, dN = _p2(xi)                                              # (q, 3)
            jac = np.linalg.norm(np.einsum("qi,kid->kqd", dN, X), axis=2)   # (k, q)
            start, end = (X[:, 0], X[:, 2]) if half == 0 else (X[:, 2], X[:, 1])
            seg = end - start
            h = np.linalg.norm(seg, axis=1)
            s = np.einsum("kqd,kd->kq", np.einsum("qi,kid->kqd", N, X) - start[:, None], seg) / h[:, None] ** 2
            shape.append(np.broadcast_to(N, (len(X),) + N.shape))
            ds.append(jac * w / 2)
            hat.append(np.stack([1 - s, s], axis=-1))
        k = len(X)

        def interleave(a, b):   # segment 2 e from half 0, 2 e + 1 from half 1
            out = np.empty((2 * k,) + a.shape[1:], a.dtype)
            out[0::2], out[1::2] = a, b
            return out

        length = np.linalg.norm(pts[segments[:, 1]] - pts[segments[:, 0]], axis=1)
        return cls(pts, edges, index, frac_all[index], plus, minus, normal, pair, node_normal, segments, length,
                   interleave(*shape), interleave(*ds), interleave(*hat))

    @property
    def num_nodes(self) -> int:
        return len(self.x)

    @property
    def num_edges(self) -> int:
        return len(self.edges)

    def volume_matrix(self, where=None) -> sparse.csr_matrix:
        """(n, 3k) sparse: V = this @ w.ravel() for edge-node values w (k, 3)
        (in the edges' node order a, b, mid) is V_i = int phi_i w ds, the
        volume node i holds of an aperture field w, m^2 per metre; with
        `where` ((2k, q) bool), the integral over the quadrature points where
        it holds only."""
        k = self.num_edges
        seg_edge = np.repeat(np.arange(k), 2)
        # (2k, 2, 3): int hat_a N_m ds over each segment
        ds = self.ds if where is None else self.ds * where
        vals = np.einsum("sqa,sqm,sq->sam", self.hat, self.shape, ds)
        rows = np.broadcast_to(self.segments[:, :, None], vals.shape)
        cols = np.broadcast_to(3 * seg_edge[:, None, None] + np.arange(3)[None, None, :], vals.shape)
        return sparse.csr_matrix((vals.ravel(), (rows.ravel(), cols.ravel())), shape=(self.num_nodes, 3 * k))

    def integrate(self, a_q: np.ndarray) -> np.ndarray:
        """(n,) int phi_i a ds of a field given at each segment's quadrature
        points (2k, q): volume_matrix's integral (volume_matrix() @ w is
        integrate(at_quadrature(w))), for a field that is no P2 one (a
        floored aperture)."""
        vals = np.einsum("sqa,sq,sq->sa", self.hat, np.asarray(a_q, float), self.ds)
        out = np.zeros(self.num_nodes)
        np.add.at(out, self.segments.ravel(), vals.ravel())
        return out

    def tributary(self) -> np.ndarray:
        """(n,) int phi_i ds: the faces' length each node stands for (m)."""
        out = np.zeros(self.num_nodes)
        np.add.at(out, self.segments.ravel(), np.repeat(self.length / 2, 2))
        return out

    def at_quadrature(self, w: np.ndarray) -> np.ndarray:
        """(2k, q) an edge-node field w (k, 3) at each segment's quadrature points."""
        w = np.asarray(w, float).reshape(-1, 3)
        return np.einsum("sqm,sm->sq", self.shape, np.repeat(w, 2, axis=0))

    def jump_matrix(self, num_mesh_nodes: int, normals=None) -> sparse.csr_matrix:
        """(3k, 2 num_mesh_nodes) sparse D: D @ u (u the mesh's nodal
        displacements, row 2 node + component) is the opening w = [u].n at
        each edge node, (k, 3) raveled, along its node_normal (the contact's
        opening: w + gap >= 0), or along `normals` (k, 3, 2); zero at a tip
        (both faces share its node)."""
        k = self.num_edges
        rows = np.repeat(np.arange(3 * k), 4)
        nodes = np.stack([self.plus.ravel(), self.plus.ravel(), self.minus.ravel(), self.minus.ravel()], axis=1)
        comp = np.tile([0, 1, 0, 1], (3 * k, 1))
        n = (self.node_normal if normals is None else np.asarray(normals, float)).reshape(-1, 2)   # (3k, 2)
        vals = np.stack([n[:, 0], n[:, 1], -n[:, 0], -n[:, 1]], axis=1)
        return sparse.csr_matrix((vals.ravel(), (rows, (2 * nodes + comp).ravel())),
                                 shape=(3 * k, 2 * int(num_mesh_nodes)))

    def load_matrix(self, num_mesh_nodes: int) -> sparse.csr_matrix:
        """(2 num_mesh_nodes, n) sparse: column i holds the nodal forces (N/m)
        of the unit pressure phi_i on the faces, +p n on the + face, -p n on
        the - face (n each edge's own normal: it pushes them apart): the
        consistent P2 load of the pressure field sum p_i phi_i. Where the
        fractures are straight (every node's normal its edges') it is the
        transpose of the volume of the opening, (D^T volume_matrix^T): the
        pressure's work is p . V; at a kink the opening is measured along
        the contact's normal (the mean of the edges'), the load pushes along
        each edge's."""
        edge = np.broadcast_to(self.normal[:, None, :], (self.num_edges, 3, 2))
        return (self.jump_matrix(num_mesh_nodes, edge).T @ self.volume_matrix().T).tocsr()

    def components(self) -> np.ndarray:
        """(n,) the connected group of each node (0, 1, ...)."""
        from scipy.sparse.csgraph import connected_components

        n = self.num_nodes
        a = sparse.coo_matrix((np.ones(len(self.segments)), (self.segments[:, 0], self.segments[:, 1])),
                              shape=(n, n))
        return connected_components(a, directed=False)[1]

    def point_weights(self, point, fracture: int | None = None) -> np.ndarray:
        """(n,) the hat functions at `point` (the segment nearest it, of
        `fracture`'s edges where given): where a point source enters the
        network, or what a pressure given at the point constrains."""
        p = np.asarray(point, float)
        seg = np.arange(len(self.segments))
        if fracture is not None:
            seg = seg[np.repeat(self.fracture, 2) == fracture]
        if not len(seg):
            raise ValueError(f"the flow network has no edge on fracture {fracture}")
        a, b = self.x[self.segments[seg, 0]], self.x[self.segments[seg, 1]]
        d = b - a
        t = np.clip(np.einsum("sd,sd->s", p - a, d) / np.einsum("sd,sd->s", d, d), 0.0, 1.0)
        dist = np.linalg.norm(a + t[:, None] * d - p, axis=1)
        j = int(np.argmin(dist))
        out = np.zeros(self.num_nodes)
        out[self.segments[seg[j], 0]] += 1 - t[j]
        out[self.segments[seg[j], 1]] += t[j]
        return out
