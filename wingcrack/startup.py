"""A command's start-up, overlapped.

Before its first step can solve, a `sif` or `run` waits for three slow
starts: the meshing worker's (a fresh interpreter importing gmsh), the
drawing process's (matplotlib), and here the import of DOLFINx and the FE
modules (then MPI's start and the forms' compilation). One after the other
they add up; so each is begun as early as its caller can, and they run at
once:

1. api.sif and api.run start the two processes first (start_processes),
   before their own imports and the output folder's preparation;
2. the first step's mesh is sent to the meshing worker before DOLFINx is
   imported: the loop begins it, then enters solving_modules();
   step.discretise (`sif`'s step) begins its mesh before it imports the FE
   modules (its imports marked "overlap");
3. solving_modules() imports DOLFINx and the FE modules while gmsh meshes,
   and freezes their objects for the garbage collector (gc.freeze: never
   scanned, never collected): every step of a run ends with a full
   collection (the loop's release of the last step's factors, whose
   DOLFINx objects sit in reference cycles), which would otherwise scan
   the modules' objects each time.

A process that only checks a case (`wingcrack check`) starts none of them.
"""
from __future__ import annotations

import contextlib
import gc

from . import drawing
from .mesh_request import MESH_TIMEOUT, start_meshing


def start_processes(mesh_timeout: float | None = MESH_TIMEOUT, pictures: bool = False) -> None:
    """Start the meshing worker (where meshing has a time limit) and, with
    `pictures`, the drawing process, without waiting for either."""
    start_meshing(mesh_timeout)
    if pictures:
        drawing.start()


@contextlib.contextmanager
def solving_modules():
    """Within: DOLFINx and the FE modules imported (fem.preload) and their
    objects frozen for the collector."""
    from .fem import preload   # lazy: overlap (ffcx's 0.3 s after the worker starts; no step, no FE)

    preload()
    gc.freeze()
    try:
        yield
    finally:
        gc.unfreeze()
