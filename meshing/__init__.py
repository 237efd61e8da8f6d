"""Conforming second-order crack meshes with gmsh (no DOLFINx here).

`Domain` (meshing/domain.py) is pure numpy; `crack_mesh` (meshing/crack_mesh.py)
builds a CrackMesh with gmsh and the compiled face kernels (wingcrack_kernels).
"""

from meshing.crack_mesh import CrackMesh, TipNodes, crack_mesh
from meshing.domain import Domain

__all__ = ["Domain", "crack_mesh", "CrackMesh", "TipNodes"]
