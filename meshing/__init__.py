"""Conforming second-order crack meshes with gmsh (no DOLFINx here).

`Domain` (meshing/domain.py) is pure numpy; `crack_mesh` (meshing/mesher.py)
builds a CrackMesh with gmsh and the compiled face kernels (wingcrack_kernels);
`start_crack_mesh` begins the same in the meshing worker and returns a
PendingMesh whose result() is the CrackMesh (it holds the worker's call
itself: meshing/timeout.py).
"""

from meshing.mesher import CrackMesh, PendingMesh, TipNodes, crack_mesh, start_crack_mesh
from meshing.domain import Domain
from meshing.worker import load_gmsh, start_worker

__all__ = ["Domain", "crack_mesh", "start_crack_mesh", "PendingMesh", "CrackMesh", "TipNodes", "load_gmsh",
           "start_worker"]
