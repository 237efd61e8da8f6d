"""The DOLFINx layer: the only part of wingcrack that imports DOLFINx/PETSc."""
import logging


class _QuietCompiler(logging.Filter):
    """Drop the INFO lines setuptools logs on the root logger while the
    form compiler builds a kernel (it raises the root level to INFO)."""

    def filter(self, record: logging.LogRecord) -> bool:
        return not (record.name == "root" and record.levelno <= logging.INFO)


# On the root logger itself, not on its handlers: its records are dropped whatever handlers ffcx's import
# makes (basicConfig) and whenever, so that importing this package does not import ffcx (0.3 s that a run
# spends in preload, while its first mesh is made)
logging.getLogger().addFilter(_QuietCompiler())


def preload():
    """Import the DOLFINx, ufl and PETSc modules and wingcrack's form modules
    now, so that a caller can freeze their objects for the garbage collector.
    In a function on purpose: the caller chooses when DOLFINx's ~1 s import
    runs (a run: while its first mesh is made)."""
    import dolfinx.fem.petsc  # noqa: F401  (here: the caller picks when DOLFINx loads)
    import ufl  # noqa: F401  (here, as DOLFINx)

    from . import elasticity, interaction_integral  # noqa: F401  (here: they import DOLFINx)
