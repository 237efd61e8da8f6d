"""Running under mpirun/srun: which rank this process is and whether a
launcher started it, doing a piece of work on rank 0 only with every rank
getting its result (or its error), now (on_root) or begun now and collected
later (RootPending), and rounding what gmsh is given so that any number of
ranks meshes alike."""
from __future__ import annotations

import os
import sys

_RANK_VARIABLES = ("OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK", "SLURM_PROCID")


def world_rank() -> int:
    """This process's rank in MPI_COMM_WORLD, without starting MPI when it
    is not started yet (the launcher's environment says it); 0 when serial."""
    mpi = sys.modules.get("mpi4py.MPI")
    if mpi is not None and mpi.Is_initialized():
        return mpi.COMM_WORLD.rank
    for name in _RANK_VARIABLES:
        value = os.environ.get(name, "")
        if value.isdigit():
            return int(value)
    return 0


def launched() -> bool:
    """Whether this process is one rank of a launcher's (mpirun, srun: its
    environment names its rank, as world_rank reads it) or has started MPI
    already: then work on a shared folder is collective (rank 0 does it,
    every rank hears the outcome); a serial command never starts MPI for it."""
    return "mpi4py.MPI" in sys.modules or any(os.environ.get(name, "").isdigit() for name in _RANK_VARIABLES)


def on_root(make):
    """make() on rank 0 (gmsh meshes there only), its result, or the error it
    raised, broadcast to every rank: all ranks go on, or all raise."""
    from mpi4py import MPI  # here: its import starts MPI, which `check` and world_rank never do

    comm = MPI.COMM_WORLD
    if comm.size == 1:
        return make()
    value, error = None, None
    if comm.rank == 0:
        try:
            value = make()
        except (RuntimeError, ValueError) as err:
            error = err
        except Exception as err:  # noqa: BLE001 - the other ranks must hear of it too
            error = RuntimeError(f"{type(err).__name__}: {err}")
    value, error = comm.bcast((value, error), root=0)
    if error is not None:
        raise error
    return value


class RootPending:
    """start() begun on rank 0 only, returning something with .result() and
    .cancel() (a meshing.PendingMesh); result() is collective, as on_root:
    rank 0 collects it and every rank gets its value or its error. An error
    of start() itself is kept and raised by result() on every rank, so that
    rank 0 alone never raises where the others go on (they would wait for it
    in the next collective call forever)."""

    def __init__(self, start):
        from mpi4py import MPI  # here: its import starts MPI (see on_root)

        self._pending, self._error = None, None
        if MPI.COMM_WORLD.rank == 0:
            try:
                self._pending = start()
            except Exception as err:  # noqa: BLE001 - raised again by result(), on every rank
                self._error = err

    def result(self):
        def collect():
            if self._error is not None:
                raise self._error
            pending, self._pending = self._pending, None
            return pending.result()
        return on_root(collect)

    def cancel(self) -> None:
        """Abandon it (rank 0's work is stopped); local, no communication."""
        if self._pending is not None:
            self._pending.cancel()
            self._pending = None


def snap(value, grid: float):
    """value rounded to a multiple of grid. The numbers of one run on 1 and on
    N processes differ by round-off (~1e-13: parallel sums go in another
    order), and gmsh turns any difference in its input into another mesh;
    rounded to a grid far above round-off, both hand gmsh the same input bit
    for bit (a rounding boundary falls between them with probability about
    round-off / grid)."""
    import numpy as np   # here: a stop during numpy's import is told (world_rank) without importing it again

    return np.round(np.asarray(value, float) / grid) * grid
