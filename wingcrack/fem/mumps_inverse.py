"""Entries of the inverse of a matrix MUMPS has factorised: A^-1(i, j) for
given rows i and columns j (MUMPS's ICNTL(30)). MUMPS solves for the unit
right-hand sides e_j as a sparse block and prunes both triangular solves to
the paths of its elimination tree that reach the columns j and the rows i,
so that a few thousand entries of A^-1 cost a fraction of one full solve
each, where a whole column costs a full solve.

petsc4py 3.18 does not wrap PETSc's MatMumpsGetInverseTranspose: it is
called in PETSc's own library, the one petsc4py loaded, through ctypes.
Where that library is not found, available() is False and the callers
solve whole columns instead."""
from __future__ import annotations

import ctypes
import glob
import os

import numpy as np
from mpi4py import MPI
import petsc4py
from petsc4py import PETSc

_LIB = []   # [the CDLL or None], found once


def _library():
    if not _LIB:
        lib = None
        # the library this process has mapped (petsc4py loaded it: F's handle is that library's), and
        # PETSC_DIR's only where none is mapped (another build's symbols would get a handle not theirs)
        with open("/proc/self/maps") as maps:
            found = sorted({line.split()[-1] for line in maps if "/libpetsc" in line and ".so" in line})
        if not found:
            found = sorted(glob.glob(os.path.join(petsc4py.get_config().get("PETSC_DIR", ""), "lib", "libpetsc*.so*")))
        for path in found:
            try:
                candidate = ctypes.CDLL(path)
                fn = candidate.MatMumpsGetInverseTranspose
            except (OSError, AttributeError):
                continue
            fn.argtypes = [ctypes.c_void_p, ctypes.c_void_p]
            fn.restype = ctypes.c_int
            lib = candidate
            break
        _LIB.append(lib)
    return _LIB[0]


def available() -> bool:
    return _library() is not None


def inverse_entries(F: PETSc.Mat, rows, cols, comm) -> np.ndarray | None:
    """(len(rows), len(cols)) A^-1[rows, cols] of the MUMPS factor F of A
    (global indices, each array without repeats), on rank 0 (None on the
    others, and everywhere when MUMPS refused). Collective."""
    N = F.getSize()[0]
    root = comm.rank == 0
    rows = np.asarray(rows, np.int64)
    cols = np.asarray(cols, np.int64)
    r_order, c_order = np.argsort(rows), np.argsort(cols)
    # the pattern as MUMPS takes it: one row of Bt a column j of A^-1, listing the rows i wanted; all of
    # it in rank 0's diagonal block (PETSc hands MUMPS that block of an MPIAIJ)
    n_local = N if root else 0
    it = PETSc.IntType
    if root:
        count = np.zeros(N, np.int64)
        count[cols] = len(rows)
        indptr = np.r_[0, np.cumsum(count)].astype(it)
        indices = np.tile(rows[r_order], len(cols)).astype(it)
    else:
        indptr, indices = np.zeros(1, it), np.zeros(0, it)
    Bt = PETSc.Mat().createAIJ(size=((n_local, N), (n_local, N)), csr=(indptr, indices, np.zeros(len(indices))),
                               comm=comm)
    Bt.assemble()
    # PETSc sets ICNTL(30) (entries of the inverse), 20 (a sparse right-hand side) and 21 (the solution
    # centralised) and leaves them so: the next plain solve would compute entries, or on several
    # processes look for a distributed solution where there is none (MUMPS error -22)
    kept = {i: F.getMumpsIcntl(i) for i in (20, 21, 30)}
    try:
        err = _library().MatMumpsGetInverseTranspose(F.handle, Bt.handle)
    finally:
        for i, value in kept.items():
            F.setMumpsIcntl(i, value)
    out = None
    if root and err == 0:
        values = Bt.getValuesCSR()[2].reshape(len(cols), len(rows))   # (sorted columns, sorted rows)
        out = np.empty((len(rows), len(cols)))
        out[np.ix_(r_order, c_order)] = values.T
    Bt.destroy()
    return out if comm.allreduce(int(err), op=MPI.MAX) == 0 else None
