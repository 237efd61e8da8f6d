"""Conforming second-order crack meshes with gmsh (no DOLFINx here).

`Domain` (meshing/domain.py) is pure numpy; `crack_mesh` (meshing/crack_mesh.py)
builds a CrackMesh with gmsh and the compiled face kernels (wingcrack_kernels).
"""

from meshing.crack_mesh import CrackMesh, TipNodes, crack_mesh
from meshing.domain import Domain

__all__ = ["Domain", "crack_mesh", "CrackMesh", "TipNodes", "load_gmsh"]


def load_gmsh() -> None:
    """Import gmsh into this process now (gmsh is imported in meshing/ only).
    Its import resets SIGINT to the default action (the process dies on
    Ctrl-C), so whoever installs a SIGINT handler calls this first: a later
    `import gmsh` in this process (an in-process mesh) is then a no-op that
    cannot undo the handler."""
    import gmsh  # noqa: F401
