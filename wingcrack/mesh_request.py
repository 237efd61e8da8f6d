"""The step's first stage: the crack mesh of some fractures, begun in the
meshing worker (rank 0 meshes) and collected by every rank when the step
needs it.

Between the propagation loop and the worker there are two layers: this
request (which fractures, sizes and patch it is for; rank 0's mesh shared
with every rank) and meshing's PendingMesh (gmsh's time limit and its one
retry), which holds the worker's call (procs.worker.Call) itself.
"""
from __future__ import annotations

import numpy as np

from meshing import mesher, start_worker
from .parallel import on_root, on_world_root, world_rank

#: seconds gmsh may take for one mesh; then it is retried once, coarser, and
#: then the step fails (meshing/timeout.py)
MESH_TIMEOUT = 120.0


class MeshRequest:
    """The crack mesh of some fractures, begun (start_mesh) and not yet
    collected: discretise(..., mesh=request) waits for it. Under MPI rank 0
    meshes; collecting is collective (every rank gets the mesh or the error,
    also an error of the start, which is kept and raised there, not before:
    rank 0 alone raising while the others go on would leave them waiting for
    it in the next collective call forever)."""

    def __init__(self, case, fractures, sizes, timeout, patch=None):
        self.polylines = [np.asarray(f.points, float).copy() for f in fractures]
        self.sizes = sizes
        self.patch = patch
        self._pending, self._error = None, None   # rank 0's meshing PendingMesh, or the error its start raised
        if on_world_root():
            try:
                self._pending = mesher.start_crack_mesh(
                    case.domain, self.polylines, case.bc_points(), case.mesh.size, case.mesh.tip_size,
                    sectors=case.mesh.sectors, sizes=sizes, timeout=timeout,
                    patch=None if patch is None else patch.for_mesher())
            except Exception as err:  # noqa: BLE001 - raised again by result(), on every rank
                self._error = err

    def is_for(self, polylines, sizes, patch=None) -> bool:
        return sizes is self.sizes and patch == self.patch and len(polylines) == len(self.polylines) and \
            all(np.array_equal(a, b) for a, b in zip(polylines, self.polylines))

    def result(self):
        """The CrackMesh (collective)."""
        def collect():
            if self._error is not None:
                raise self._error
            pending, self._pending = self._pending, None
            return pending.result()
        return on_root(collect)

    def cancel(self) -> None:
        """Abandon it (the meshing worker stops); local, no communication."""
        if self._pending is not None:
            self._pending.cancel()
            self._pending = None


def start_mesh(case, fractures, sizes=None, timeout: float | None = MESH_TIMEOUT, patch=None) -> MeshRequest:
    """Begin the crack mesh of `fractures` (as discretise would mesh them)
    in the meshing worker and return at once, so that the caller works
    meanwhile (the propagation loop writes the previous step's files);
    discretise(..., mesh=the request) collects it. The time limit runs from
    now. Nothing is raised here: a geometry that cannot be meshed fails
    where the mesh is collected, as the step it belongs to. sizes: the
    error-estimate size field (None: the case's sizes); patch: the run's
    propagation.patch.Patch (None: the whole body meshed freely)."""
    return MeshRequest(case, fractures, sizes, timeout, patch)


def start_meshing(timeout: float | None = MESH_TIMEOUT) -> None:
    """Start the meshing worker (rank 0, when meshing goes to it: a time
    limit), without waiting for it (see wingcrack/startup.py)."""
    if timeout is not None and world_rank() == 0:
        start_worker()
