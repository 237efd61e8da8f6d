"""Linear functionals of the displacement given by weights at CrackMesh
nodes: values = W^T u, W (2 n_nodes, k) with row 2 node + component (the
opening integral of each fracture's faces, loads.opening_functionals).
Each process sums over the dofs it owns; the sum over processes is the
value on every one."""
from __future__ import annotations

import numpy as np
from scipy import sparse


class NodalFunctionals:
    def __init__(self, problem, weights):
        """problem: the ElasticProblem whose displacement the functionals read;
        weights: (2 n_nodes, k) sparse, in CrackMesh nodes."""
        self.problem = problem
        fm = problem.fm
        W = sparse.coo_matrix(weights)
        nodes = W.row // 2
        found, blk = fm.block_dofs(nodes)
        size = fm.V.dofmap.index_map.size_local
        own = found & (blk < size)
        n_owned = size * fm.V.dofmap.index_map_bs
        self.W = sparse.csr_matrix((W.data[own], (2 * blk[own] + W.row[own] % 2, W.col[own])),
                                   shape=(n_owned, W.shape[1]))
        self.blocks = np.unique(blk[found])   # the local block dofs read (expanded first where deferred)

    def values(self) -> np.ndarray:
        """(k,) W^T u of the problem's current displacement (collective)."""
        u = self.problem.u_at(self.blocks)
        local = self.W.T @ u.x.array[:self.W.shape[0]]
        return self.problem.fm.mesh.comm.allreduce(np.asarray(local, float))
