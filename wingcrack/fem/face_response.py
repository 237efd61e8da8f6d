"""The faces' linear response to a pressure field on the flow network and to
the pair forces, from the step's factorisation: the coupled step's
unknowns (the nodal pressures, the pair forces) live on the faces, and so
does everything it solves with.

Every force on the faces is a force on the face pairs (+g on a pair's +
copy, -g on its - copy: Bj g), and every jump it reads is a pair's jump
[u] = Bj^T u. So one compliance in the pairs' jump space (x and y of every
pair), C = Bj^T K^-1 Bj (2p x 2p, fem.compliance: the Schur complement
where the factorisation has it on the faces), gives them all:

    row jumps     j = j_fixed + S_rp p + S f,        S_rp = R^T C G
    edge openings w = w_fixed + W_p p + W_f f,       W_p = E C G,  W_f = E C R

f the pair rows' forces (R: each row's direction at its pair), p the flow
nodes' pressures (G: the pressure load of the network, loads of the hats
phi_i, as pair forces), w the opening [u].n at every edge node of the
network (E: the node's pair's normal, the contact's, at its pair; a tip has
no pair and no opening). S = R^T C R is the pair operator's own compliance. j_fixed and
w_fixed are those of the loads the pressure leaves (bc values, gravity,
the in-situ stress, other fractures' pressures): a solve at load factor 0.
"""
from __future__ import annotations

import numpy as np
from scipy import sparse

from .compliance import compliance, free_rows
from .nodal_functionals import NodalFunctionals


def _pair_jumps(problem, pairs: np.ndarray) -> sparse.csr_matrix:
    """Bj (owned dofs x 2p): column 2 q + c holds +1 at pair q's + copy's
    component c and -1 at its - copy's."""
    fm = problem.fm
    imap = fm.V.dofmap.index_map
    n_owned = imap.size_local * fm.V.dofmap.index_map_bs
    rows, cols, vals = [], [], []
    for nodes, sign in ((pairs[:, 0], 1.0), (pairs[:, 1], -1.0)):
        found, blk = fm.block_dofs(nodes)
        own = np.flatnonzero(found & (blk < imap.size_local))
        for c in (0, 1):
            rows.append(2 * blk[own] + c)
            cols.append(2 * own + c)
            vals.append(np.full(len(own), sign))
    return sparse.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                             shape=(n_owned, 2 * len(pairs)))


class FaceResponse:
    """The response matrices of the module doc for the network `net`
    (flow.network.FlowNetwork of the CrackMesh `cm`) and the contact rows
    `rows` of `problem` (factorised). Collective."""

    def __init__(self, problem, cm, rows, net):
        self.problem, self.net = problem, net
        pairs = np.asarray(cm.pairs, dtype=np.int64).reshape(-1, 2)
        npair = len(pairs)
        Bj = _pair_jumps(problem, pairs)
        self.C, _ = compliance(problem, free_rows(problem, Bj))
        # R: a row's force f acts as f d on its pair's + copy (d its direction)
        m = len(rows)
        self.R = sparse.csr_matrix((np.asarray(rows.direction, float).ravel(),
                                    ((2 * np.asarray(rows.pair, np.int64)[:, None] + [0, 1]).ravel(),
                                     np.repeat(np.arange(m), 2))), shape=(2 * npair, m))
        # E: the opening at an edge node is its node normal . its pair's jump (0 at a tip)
        k = net.num_edges
        q = net.pair.ravel()
        at = np.flatnonzero(q >= 0)

        def measure(normals):   # (3k, 2p): normals (k, 3, 2) . the edge nodes' pair jumps
            n = np.asarray(normals, float).reshape(-1, 2)[at]
            return sparse.csr_matrix((n.ravel(), (np.repeat(at, 2), (2 * q[at][:, None] + [0, 1]).ravel())),
                                     shape=(3 * k, 2 * npair))

        self.E = measure(net.node_normal)
        # G: the hats' pressure load as pair forces (each edge's own normal; where the fractures are
        # straight the transpose of the opening's volume: E^T Phi^T)
        edge = np.broadcast_to(net.normal[:, None, :], (k, 3, 2))
        self.G = (measure(edge).T @ net.volume_matrix().T).tocsr()
        CG = self.C @ self.G.toarray()
        CR = self.C @ self.R.toarray()
        self.S_rp = np.asarray(self.R.T @ CG)        # (m, n)
        self.W_p = np.asarray(self.E @ CG)           # (3k, n)
        self.W_f = np.asarray(self.E @ CR)           # (3k, m)
        self.S = np.asarray(self.R.T @ CR)           # (m, m): the pair operator's S
        # the opening of the solved displacement, for the fixed loads' part
        D = net.jump_matrix(len(cm.x))
        self._openings = NodalFunctionals(problem, D.T)

    def openings_of_solution(self) -> np.ndarray:
        """(3k,) the edge nodes' openings [u].n of the problem's current
        displacement (collective)."""
        return self._openings.values()
