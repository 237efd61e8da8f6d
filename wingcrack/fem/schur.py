"""The Schur complement of the factorised stiffness on a set of dofs.

MUMPS can eliminate every dof but a chosen few during the factorisation and
hand back the dense Schur complement S_c = K_PP - K_PI K_II^-1 K_IP; then
(K^-1)_PP = S_c^-1, which is all the pair system needs, with no
back-substitution per pair row as Z = K^-1 B takes.
Plain solves with the factor still work:
PETSc condenses and expands through the Schur complement.

petsc4py 3.18 does not wrap MatFactorSetSchurIS and
MatFactorCreateSchurComplement, so they are called through ctypes on the
PETSc library petsc4py itself loaded. PETSc supports MUMPS Schur
complements on one process only; in parallel the caller falls back to
K^-1 B.
"""
from __future__ import annotations

import ctypes

import numpy as np
from petsc4py import PETSc

from ..errors import ComputationError
from .mumps_failure import MEMORY

_LIB = None


def _petsc_library():
    global _LIB
    if _LIB is None:
        path = None
        with open("/proc/self/maps") as fh:
            for line in fh:
                name = line.split()[-1] if line.split() else ""
                if "/libpetsc" in name and ".so" in name:
                    path = name
                    break
        _LIB = ctypes.CDLL(path or "libpetsc_real.so.3.18")
    return _LIB


def available(comm) -> bool:
    return comm.size == 1


def set_schur_dofs(factor: PETSc.Mat, dofs: np.ndarray) -> None:
    """Ask the (not yet set-up) MUMPS factor for the Schur complement on `dofs`."""
    iset = PETSc.IS().createGeneral(np.asarray(dofs, dtype=PETSc.IntType), comm=PETSc.COMM_SELF)
    err = _petsc_library().MatFactorSetSchurIS(ctypes.c_void_p(factor.handle), ctypes.c_void_p(iset.handle))
    iset.destroy()
    if err:
        raise RuntimeError(f"MatFactorSetSchurIS failed (PETSc error {err})")


def schur_complement(factor: PETSc.Mat, k: int) -> np.ndarray:
    """The dense (k, k) Schur complement of the factorised matrix."""
    lib = _petsc_library()
    S = ctypes.c_void_p()
    status = ctypes.c_int()
    err = lib.MatFactorCreateSchurComplement(ctypes.c_void_p(factor.handle), ctypes.byref(S), ctypes.byref(status))
    if err:
        info = factor.getMumpsInfog(1)
        if info in MEMORY:
            raise ComputationError(f"out of memory: the factorisation of the stiffness with the pair dofs' Schur "
                                   f"complement ({k} dofs) needs about {factor.getMumpsInfog(17) / 1024:.1f} GB "
                                   f"(MUMPS error {info}); a coarser mesh (mesh.tip_size, mesh.size) or fewer "
                                   "fractures need less")
        # the factors exist: what failed is the dense (k, k) copy PETSc makes of it; whether that much
        # memory is there, a block of its size says
        size = f"{k} x {k}, {8 * k * k / 2**20:.0f} MB dense"
        try:
            np.ones(k * k)
        except MemoryError:
            raise ComputationError(f"out of memory: the pair dofs' Schur complement ({size}) does not fit; a "
                                   "coarser mesh (mesh.tip_size, mesh.size) or fewer fractures need less") from None
        raise ComputationError(f"the pair dofs' Schur complement ({size}) could not be formed (PETSc error {err})")
    arr = ctypes.POINTER(ctypes.c_double)()
    try:
        if lib.MatDenseGetArrayRead(S, ctypes.byref(arr)):
            raise RuntimeError("MatDenseGetArrayRead failed")
        # column-major storage, leading dimension k
        Sc = np.ctypeslib.as_array(arr, shape=(k, k)).T.copy()
        lib.MatDenseRestoreArrayRead(S, ctypes.byref(arr))
    finally:
        lib.MatDestroy(ctypes.byref(S))
    return 0.5 * (Sc + Sc.T)
