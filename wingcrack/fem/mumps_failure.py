"""What stopped a MUMPS factorisation, said for a user: the memory it ran
out of (with the analysis's estimate of what it needs), a singular matrix,
or MUMPS's own codes where neither (INFOG(1), INFOG(2): the MUMPS users'
guide, section "Error diagnostics")."""
from __future__ import annotations

from petsc4py import PETSc

#: INFOG(1) values that mean memory: -8, -9, -11, -14, -15 workspace too small; -13 an allocation
#: failed; -17, -19, -20, -22 buffers and the memory bound ICNTL(23)
MEMORY = frozenset({-8, -9, -11, -13, -14, -15, -17, -19, -20, -22})
#: a singular matrix (numerically)
SINGULAR = -10


def failed(ksp) -> bool:
    """Whether MUMPS's last phase on the KSP's factor failed (INFOG(1) < 0)."""
    try:
        return ksp.getPC().getFactorMatrix().getMumpsInfog(1) < 0
    except (PETSc.Error, AttributeError):
        return False


def describe(ksp, err, what: str, singular: str, prefix: str = "") -> str:
    """The message of a failed factorisation of `what` by the KSP `ksp`
    (its PC's factor matrix holds MUMPS's INFOG); `singular`: the text for
    a singular matrix; err: the PETSc.Error."""
    try:
        F = ksp.getPC().getFactorMatrix()
        info, info2 = F.getMumpsInfog(1), F.getMumpsInfog(2)
        need = F.getMumpsInfog(17)   # MB: the analysis's estimate of the factorisation's memory, all processes
    except (PETSc.Error, AttributeError):
        info, info2, need = 0, 0, 0
    if info in MEMORY:
        amount = f"needs about {need / 1024:.1f} GB for its factors" if need > 0 else "needs more memory"
        return (f"{prefix}out of memory: {what} {amount} (MUMPS error {info}, {info2}); a coarser mesh "
                "(mesh.tip_size, mesh.size) or fewer fractures need less")
    if info == SINGULAR:
        return prefix + singular
    return f"{prefix}{what} could not be factorised (PETSc error {getattr(err, 'ierr', '?')}, MUMPS error {info}, {info2})"
