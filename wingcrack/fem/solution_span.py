"""Solutions kept for their right-hand sides: a linear solve whose
right-hand side is a combination of earlier ones is that combination of
their solutions, with no solve. The loads of a step are affine in the load
factor (b0 + lambda b1), so a few kept pairs span every later one.

The combination is found by least squares on the kept right-hand sides,
through an orthonormal basis of them (classical Gram-Schmidt, twice, with
the dot products summed over the processes that hold parts of them): the
normal equations of their Gram matrix square its conditioning, and two
loads that press a crack the same way (an in-situ stress and the applied
load) make it 1e10, leaving residuals of 1e-12 where the combination is
exact to 1e-14. It is taken only where it reproduces b to `tolerance` |b|:
the assembly of b0 + lambda b1 rounds each entry to about eps, and a
direct solve's own backward error is no smaller, so 1e-14 admits the
combinations the loads make and nothing a solve would answer differently.
"""
from __future__ import annotations

import numpy as np

#: b lies in the kept span when the least-squares residual is below this times |b|
TOLERANCE = 1e-14


class SolutionSpan:
    """The last `keep` (right-hand side, solution) pairs, as columns of
    local arrays of n rows; `comm` sums the small products over processes
    (None: one process)."""

    def __init__(self, n: int, m: int, keep: int, comm=None, tolerance: float = TOLERANCE):
        self.keep, self.comm, self.tolerance = keep, comm, tolerance
        self.rhs = np.zeros((n, 0))
        self.solutions = np.zeros((m, 0))
        self._Q = np.zeros((n, 0))    # orthonormal basis of the kept right-hand sides: rhs = Q R
        self._R = np.zeros((0, 0))
        self.hits = 0   # solves it answered

    def _sum(self, x):
        return x if self.comm is None else self.comm.allreduce(x)

    def _project(self, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(c, r): b = Q c + r with r orthogonal to Q (two Gram-Schmidt passes)."""
        c = np.zeros(self._Q.shape[1])
        r = b
        for _ in range(2):
            d = self._sum(self._Q.T @ r)
            r = r - self._Q @ d
            c = c + d
        return c, r

    def find(self, b: np.ndarray) -> np.ndarray | None:
        """The kept solutions' combination for right-hand side `b`, or None
        when b is not in their span (collective with a comm)."""
        if not self._Q.shape[1]:
            return None
        c, r = self._project(np.asarray(b, dtype=np.float64))
        if self._sum(float(r @ r)) > self.tolerance**2 * self._sum(float(b @ b)):
            return None
        self.hits += 1
        return self.solutions @ np.linalg.solve(self._R, c)

    def add(self, b: np.ndarray, x: np.ndarray) -> None:
        """Keep (b, x), dropping the oldest pair beyond `keep`."""
        rhs = np.column_stack([self.rhs[:, -(self.keep - 1):], b])
        sol = np.column_stack([self.solutions[:, -(self.keep - 1):], x])
        self._Q, self._R = np.zeros((len(rhs), 0)), np.zeros((0, 0))
        kept = []
        for j in range(rhs.shape[1]):   # the basis of the kept columns, in order
            c, r = self._project(rhs[:, j])
            norm = float(np.sqrt(self._sum(float(r @ r))))
            if norm <= self.tolerance * float(np.sqrt(self._sum(float(rhs[:, j] @ rhs[:, j])))):
                continue   # in the span of the earlier ones (a zero load): adds nothing, and R stays invertible
            R = np.zeros((len(c) + 1, len(c) + 1))
            R[:-1, :-1], R[:-1, -1], R[-1, -1] = self._R, c, norm
            self._Q, self._R = np.column_stack([self._Q, r / norm]), R
            kept.append(j)
        self.rhs, self.solutions = rhs[:, kept], sol[:, kept]
