"""Pieces of the body that only contact holds.

A network that cuts out a block leaves a piece whose stiffness has rigid-body
modes that no displacement condition fixes (wingcrack.free_pieces finds
them). Rock holds such blocks by contact and friction; so does wingcrack,
as FETI-type contact solvers do (Dostal, Horak & Kucera 2006): a generalised
inverse of the piece's stiffness and its rigid modes R, with the piece's
equilibrium as a condition on the contact forces.

- The generalised inverse: a gauge, homogeneous displacement conditions on
  as many dofs of the piece as it has free modes, chosen where those modes
  are independent (away from the faces); the gauged stiffness K_g is then
  regular and K_g^-1 is a generalised inverse of K.
- The solution: u = K_g^-1 (f + B forces) + R alpha, with the pair forces
  and the rigid amplitudes alpha from the contact problem, whose jumps are
  jump0 + S forces + G alpha (G = B^T R) and whose equilibrium is
  R^T (f + B forces) = 0, i.e. G^T forces + e = 0 with e = R^T f (contact.friction,
  Rigid). Where no admissible contact force meets it, the piece is a
  mechanism (contact.friction.Mechanism) and describe() names its motion.

Pure numpy on the CrackMesh and the constraint rows, identical on every
process (every process holds the whole crack mesh); the fem layer adds R
alpha to u and measures e = R^T f on its right-hand side.
"""
from __future__ import annotations

from dataclasses import dataclass
from itertools import combinations

import numpy as np

from .free_pieces import FreePiece


@dataclass
class Floating:
    """The pieces only contact holds: pieces (FreePiece), and per rigid
    mode (column) k: piece[k], the nodes nodes[k] of its piece and the mode's
    displacement values[k] (len(nodes[k]), 2) there; gauge: (node, comp)
    of the homogeneous displacement conditions that make the stiffness regular."""
    pieces: list
    piece: list
    nodes: list
    values: list
    gauge: list
    outer: np.ndarray = None   # (n_nodes,) bool: on the outer boundary (a piece there is not a "block")

    @property
    def r(self) -> int:
        return len(self.piece)

    @classmethod
    def of(cls, cm, pieces: list[FreePiece], pair_nodes) -> Floating:
        """The modes and gauge of `pieces`; pair_nodes: the nodes of the
        faces' pairs (no gauge there: a prescribed dof takes no pair force)."""
        x = np.asarray(cm.x, float)
        avoid = np.zeros(len(x), bool)
        avoid[np.asarray(pair_nodes, np.int64).ravel()] = True
        for t in getattr(cm, "tips", ()):   # a tip is a face node too
            avoid[int(t.node)] = True
        piece, nodes, values, gauge = [], [], [], []
        for i, p in enumerate(pieces):
            modes = _mode_values(x[p.nodes], p)   # (k, n, 2)
            for k in range(len(modes)):
                piece.append(i)
                nodes.append(p.nodes)
                values.append(modes[k])
            gauge += _gauge(x, p, modes, avoid)
        outer = np.zeros(len(x), bool)
        outer[np.asarray(cm.boundary_edges, np.int64).ravel()] = True
        return cls(list(pieces), piece, nodes, values, gauge, outer)

    def jumps(self, rows) -> np.ndarray:
        """G (m, r): the jump of every constraint row under each unit mode."""
        m = len(rows)
        G = np.zeros((m, self.r))
        for k in range(self.r):
            at = {int(n): j for j, n in enumerate(self.nodes[k])}
            for nodes, sign in ((rows.plus, 1.0), (rows.minus, -1.0)):
                idx = np.array([at.get(int(n), -1) for n in nodes], np.int64)
                on = idx >= 0
                G[on, k] += sign * np.einsum("ij,ij->i", self.values[k][idx[on]], rows.direction[on])
        return G

    def describe(self, residual, rows, closed=None) -> str:
        """What the piece whose equilibrium fails worst does: the generalised
        force left over, or the motion nothing resists (residual, (r,)),
        moves it one way; it slides along the fracture closest to parallel
        to that way among those it presses on, or is pulled off its faces
        where it presses on none (closed: (m,) the normal rows in contact
        at the end, where known: none on the piece is the same)."""
        residual = np.asarray(residual, float)
        piece = np.asarray(self.piece)
        worst = max(range(len(self.pieces)), key=lambda i: float(np.linalg.norm(residual[piece == i])))
        p = self.pieces[worst]
        cols = np.flatnonzero(piece == worst)
        g = p.modes.T @ residual[cols]       # (fx, fy, moment / size) the unbalanced load
        what = "piece" if self.outer is not None and self.outer[p.nodes].any() else "block"
        where = f"the {what} around ({p.centre[0]:.4g}, {p.centre[1]:.4g})"
        if abs(g[2]) > np.hypot(g[0], g[1]):
            return f"{where} rotates: contact cannot hold it"
        d = g[:2] / max(float(np.hypot(g[0], g[1])), 1e-300)
        inside = np.zeros(int(max(np.max(rows.plus, initial=0), np.max(rows.minus, initial=0))) + 1, bool)
        inside[p.nodes[p.nodes < len(inside)]] = True
        normal = rows.normal
        mine = normal & (inside[rows.plus] ^ inside[rows.minus])
        if closed is not None and not np.any(np.asarray(closed, bool) & mine):
            return f"{where} is pulled away from its faces: contact cannot hold it"
        best, pressed = None, False
        for f in np.unique(rows.fracture[normal]):
            on = normal & (rows.fracture == f) & (inside[rows.plus] ^ inside[rows.minus])
            if not on.any():
                continue
            # the face normal out of the piece: n points from the - face into the + side
            n_out = np.mean(np.where(inside[rows.plus[on]], -1.0, 1.0)[:, None] * rows.direction[on], axis=0)
            n_out /= max(float(np.linalg.norm(n_out)), 1e-300)
            into = float(d @ n_out)
            if into > -0.5:
                pressed = True
            along = abs(float(d[0] * n_out[1] - d[1] * n_out[0]))
            if into > -0.5 and (best is None or along > best[0]):
                best = (along, int(f))
        if not pressed or best is None:
            return f"{where} is pulled away from its faces: contact cannot hold it"
        return f"{where} slides along fracture {best[1]}: contact cannot hold it"


def _mode_values(x, p: FreePiece) -> np.ndarray:
    """(k, n, 2) displacement of each free mode of piece p at the points x:
    modes are rows [ux, uy, rotation] with the rotation (-y, x) about the
    piece's centre, scaled by its size (free_pieces' basis)."""
    r = (x - p.centre) / p.size
    rot = np.c_[-r[:, 1], r[:, 0]]
    return np.stack([m[0] * np.array([1.0, 0.0]) + m[1] * np.array([0.0, 1.0]) + m[2] * rot for m in p.modes])


def _gauge(x, p: FreePiece, modes, avoid) -> list:
    """(node, comp) of len(modes) dofs of piece p off the faces that fix its
    free modes: among both components of the node farthest from the centre
    and of the node farthest from that one, those whose rows of the mode
    matrix are the best conditioned."""
    nodes = p.nodes[~avoid[p.nodes]]
    if len(nodes) < 2:
        nodes = p.nodes
    a = nodes[int(np.argmax(np.linalg.norm(x[nodes] - p.centre, axis=1)))]
    b = nodes[int(np.argmax(np.linalg.norm(x[nodes] - x[a], axis=1)))]
    at = {int(n): j for j, n in enumerate(p.nodes)}
    cand = [(int(n), c) for n in (a, b) for c in (0, 1)]
    rows = np.array([[modes[k][at[n], c] for k in range(len(modes))] for n, c in cand])
    k = len(modes)
    best = max(combinations(range(len(cand)), k), key=lambda s: np.linalg.svd(rows[list(s)], compute_uv=False)[-1])
    return [cand[i] for i in best]
