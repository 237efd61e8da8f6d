"""Displacements at CrackMesh nodes, gathered from whichever rank holds them."""
from __future__ import annotations

import numpy as np


def nodal_displacements(fm, u, nodes) -> np.ndarray:
    """(len(nodes), 2) displacement of the given CrackMesh nodes, on every rank."""
    nodes = np.asarray(nodes, dtype=np.int64).ravel()
    comm = fm.mesh.comm
    found, blk = fm.block_dofs(nodes)
    vals = np.zeros((len(nodes), 2))
    arr = u.x.array
    vals[found, 0] = arr[2 * blk[found]]
    vals[found, 1] = arr[2 * blk[found] + 1]
    if comm.size > 1:
        from mpi4py import MPI  # here: its import starts MPI, and step imports this module before DOLFINx
        count = np.zeros(len(nodes))
        comm.Allreduce(found.astype(float), count, op=MPI.SUM)
        total = np.zeros_like(vals)
        comm.Allreduce(vals * found[:, None], total, op=MPI.SUM)
        if np.any(count == 0):
            raise KeyError("some nodes are on no rank")
        return total / count[:, None]
    if not np.all(found):
        raise KeyError(f"nodes not in the mesh: {nodes[~found][:5]}")
    return vals
