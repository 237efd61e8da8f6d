"""Conforming second-order crack meshes with gmsh (no DOLFINx here).

`Domain` (meshing/domain.py) is pure numpy; `crack_mesh` (meshing/mesher.py)
builds a CrackMesh with gmsh and the compiled face kernels (wingcrack_kernels);
`start_crack_mesh` begins the same in the meshing worker and returns a
PendingMesh whose result() is the CrackMesh.
"""

from meshing.mesher import CrackMesh, PendingMesh, TipNodes, crack_mesh, start_crack_mesh
from meshing.domain import Domain

__all__ = ["Domain", "crack_mesh", "start_crack_mesh", "PendingMesh", "CrackMesh", "TipNodes", "load_gmsh",
           "start_worker"]


def load_gmsh() -> None:
    """Import gmsh into this process now (gmsh is imported in meshing/ only),
    keeping the SIGINT handler: gmsh's import sets SIGINT to the default
    action (the process would die on Ctrl-C instead of raising
    KeyboardInterrupt, and a run's own handler would be gone). Everything
    that meshes in-process calls this before gmsh is first used; later
    imports are no-ops."""
    import sys

    if "gmsh" in sys.modules:
        return
    import signal
    import threading

    main = threading.current_thread() is threading.main_thread()
    old = signal.getsignal(signal.SIGINT) if main else None
    import gmsh  # noqa: F401
    if main and old is not None:   # None: a handler set outside Python, which gmsh's import replaced
        signal.signal(signal.SIGINT, old)


def load_worker_modules() -> None:
    """What the meshing worker imports at its start (overlapping its
    caller's start-up): gmsh and the compiled kernels that finish a mesh."""
    import gmsh  # noqa: F401
    import wingcrack_kernels  # noqa: F401


def start_worker() -> None:
    """Start the meshing worker now, without waiting (it imports gmsh while
    the caller goes on); meshing with a time limit uses it."""
    from meshing import worker

    worker.start()
