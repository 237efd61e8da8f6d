"""wingcrack: wing-crack initiation and growth from pre-existing fractures,
with the fracture faces in contact or open (Dang-Trung, Keilegavlen & Berre,
IJSS 2020).

    import wingcrack
    case = wingcrack.Case.from_toml("cases/brazilian_disc_45.toml")
    result = wingcrack.sif(case, out="results/disc45")   # or run(case, out=...)
    wingcrack.plot("results/disc45")                       # the pictures again

DOLFINx is imported only when a computation starts, so reading and checking
cases stays fast.
"""
import os as _os

from .errors import CaseError, ComputationError, FolderError
from .version import __version__

# A process no launcher started is an MPI singleton, for which Open MPI's
# MPI_Init starts a helper daemon unless the singleton is declared isolated:
# wingcrack never spawns processes through MPI, so it need not be. Set
# before anything imports mpi4py; a launcher's jobs (mpirun, srun) are not
# singletons and never read it, and a user's own setting wins.
_os.environ.setdefault("OMPI_MCA_ess_singleton_isolated", "1")

__all__ = ["Case", "CaseError", "ComputationError", "FolderError", "sif", "run", "plot", "__version__"]


def __getattr__(name):
    """Case, sif, run and plot load on first use: `import wingcrack.cli` (every
    command, `--version` too) must not pay for numpy, the mesher and the API."""
    if name == "Case":
        from .case import Case  # numpy, scipy, meshing: on first use
        return Case
    if name in ("sif", "run", "plot"):
        from . import api  # the whole pipeline: on first use
        return getattr(api, name)
    raise AttributeError(f"module 'wingcrack' has no attribute {name!r}")
