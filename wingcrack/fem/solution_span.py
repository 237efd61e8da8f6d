"""Solutions kept for their right-hand sides: a linear solve whose
right-hand side is a combination of earlier ones is that combination of
their solutions, with no solve. The loads of a step are affine in the load
factor (b0 + lambda b1), so a few kept pairs span every later one.

The combination is found by least squares on the kept right-hand sides
(their Gram matrix, summed over the processes that hold parts of them) and
taken only where it reproduces b to `tolerance` |b|: the assembly of
b0 + lambda b1 rounds each entry to about eps, and a direct solve's own
backward error is no smaller, so 1e-14 admits the combinations the loads
make and nothing a solve would answer differently.
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
        self.hits = 0   # solves it answered

    def _sum(self, x):
        return x if self.comm is None else self.comm.allreduce(x)

    def find(self, b: np.ndarray) -> np.ndarray | None:
        """The kept solutions' combination for right-hand side `b`, or None
        when b is not in their span (collective with a comm)."""
        B = self.rhs
        if not B.shape[1]:
            return None
        alpha = np.linalg.lstsq(self._sum(B.T @ B), self._sum(B.T @ b), rcond=None)[0]
        r = b - B @ alpha
        if self._sum(float(r @ r)) > self.tolerance**2 * self._sum(float(b @ b)):
            return None
        self.hits += 1
        return self.solutions @ alpha

    def add(self, b: np.ndarray, x: np.ndarray) -> None:
        """Keep (b, x), dropping the oldest pair beyond `keep`."""
        self.rhs = np.column_stack([self.rhs[:, -(self.keep - 1):], b])
        self.solutions = np.column_stack([self.solutions[:, -(self.keep - 1):], x])
