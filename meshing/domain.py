"""The outer domain of a case: a disc, a rectangle or a polygon, with named boundaries.

Pure numpy; a polygon is checked by the rules of `wingcrack check`
(meshing/admissibility.py). Lengths in metres. A rectangle's boundaries are
"left", "right", "bottom", "top"; a polygon's (points counter-clockwise)
"edge0".."edgeN-1", edge i running from point i to point i+1; a disc's
whole rim is "rim".
Every query takes one point (2,) or many (n, 2) and answers in kind.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from meshing import admissibility

SHAPES = ("disc", "rectangle", "polygon")


@dataclass(frozen=True, eq=False)  # numpy fields: compare explicitly if needed
class Domain:
    shape: str
    center: np.ndarray | None = None
    radius: float | None = None
    corner: np.ndarray | None = None
    size: np.ndarray | None = None
    points: np.ndarray | None = None

    def __post_init__(self):
        if self.shape not in SHAPES:
            raise ValueError(f"domain shape must be one of {SHAPES}, not {self.shape!r}")
        if self.shape == "disc":
            if self.center is None or self.radius is None:
                raise ValueError("a disc needs center and radius")
            object.__setattr__(self, "center", _point(self.center, "center"))
            object.__setattr__(self, "radius", float(self.radius))
            if not self.radius > 0.0:
                raise ValueError("disc radius must be > 0")
        elif self.shape == "rectangle":
            if self.corner is None or self.size is None:
                raise ValueError("a rectangle needs corner and size")
            object.__setattr__(self, "corner", _point(self.corner, "corner"))
            object.__setattr__(self, "size", _point(self.size, "size"))
            if not np.all(self.size > 0.0):
                raise ValueError("rectangle size must be > 0 in x and y")
        else:
            if self.points is None:
                raise ValueError("a polygon needs points")
            pts = np.asarray(self.points, dtype=np.float64)
            if pts.ndim != 2 or pts.shape[1] != 2 or len(pts) < 3 or not np.all(np.isfinite(pts)):
                raise ValueError("polygon points must be at least 3 finite [x, y] pairs")
            object.__setattr__(self, "points", pts)
            admissibility.require(admissibility.polygon(pts, "points"))  # the rules of `wingcrack check`

    # -- the boundary as pieces -------------------------------------------------
    def vertices(self) -> np.ndarray:
        """Corners (k, 2) counter-clockwise of a rectangle or polygon; empty for a disc."""
        if self.shape == "disc":
            return np.zeros((0, 2))
        if self.shape == "rectangle":
            (x0, y0), (w, h) = self.corner, self.size
            return np.array([[x0, y0], [x0 + w, y0], [x0 + w, y0 + h], [x0, y0 + h]])
        return self.points

    def edge_names(self) -> list[str]:
        """Name of each straight edge i (from vertex i to i+1) of vertices()."""
        if self.shape == "rectangle":
            return ["bottom", "right", "top", "left"]
        if self.shape == "polygon":
            return [f"edge{i}" for i in range(len(self.points))]
        return []

    def boundary_names(self) -> list[str]:
        if self.shape == "disc":
            return ["rim"]
        if self.shape == "rectangle":
            return ["left", "right", "bottom", "top"]
        return self.edge_names()

    # -- geometric queries --------------------------------------------------------
    def area(self) -> float:
        if self.shape == "disc":
            return float(np.pi * self.radius**2)
        if self.shape == "rectangle":
            return float(self.size[0] * self.size[1])
        return float(_shoelace(self.points))

    def length_scale(self) -> float:
        """The diameter: the largest distance between two points of the domain."""
        if self.shape == "disc":
            return 2.0 * self.radius
        v = self.vertices()
        return float(np.max(np.linalg.norm(v[:, None, :] - v[None, :, :], axis=-1)))

    def distance_to_boundary(self, p) -> np.ndarray | float:
        """Unsigned distance from p to the boundary curve."""
        q, single = _points(p)
        if self.shape == "disc":
            d = np.abs(np.linalg.norm(q - self.center, axis=1) - self.radius)
        else:
            d = self._edge_distances(q).min(axis=1)
        return float(d[0]) if single else d

    def contains(self, p, tol: float = 0.0) -> np.ndarray | bool:
        """True for points inside the closed domain, grown by tol."""
        q, single = _points(p)
        if self.shape == "disc":
            inside = np.linalg.norm(q - self.center, axis=1) <= self.radius + tol
        else:
            inside = _winding_inside(q, self.vertices()) | (self._edge_distances(q).min(axis=1) <= tol)
        return bool(inside[0]) if single else inside

    def on_boundary(self, p, tol: float) -> np.ndarray | bool:
        d = self.distance_to_boundary(p)
        return bool(d <= tol) if np.isscalar(d) else d <= tol

    def boundary_name_at(self, p, tol: float) -> str | None:
        """Name of the boundary within tol of the single point p, or None.
        Near a corner the nearer edge wins; at the corner itself the edge with
        the lower index in vertices() order ("bottom" < "right" < "top" < "left")."""
        q, _ = _points(p)
        if self.shape == "disc":
            return "rim" if self.distance_to_boundary(q[0]) <= tol else None
        d = self._edge_distances(q)[0]
        i = int(np.argmin(d))
        if d[i] > tol:
            return None
        return self.edge_names()[i]

    def project(self, p) -> tuple[np.ndarray, int, float]:
        """Closest boundary point to the single point p: (point (2,), edge index,
        parameter). For a disc the edge index is 0 and the parameter is the
        polar angle in (-pi, pi]; for a straight edge the parameter is in [0, 1]."""
        q = np.asarray(p, dtype=np.float64).reshape(2)
        if self.shape == "disc":
            r = q - self.center
            angle = float(np.arctan2(r[1], r[0]))
            return self.center + self.radius * np.array([np.cos(angle), np.sin(angle)]), 0, angle
        a, b = self.vertices(), np.roll(self.vertices(), -1, axis=0)
        t = np.clip(np.einsum("ij,ij->i", q - a, b - a) / np.einsum("ij,ij->i", b - a, b - a), 0.0, 1.0)
        foot = a + t[:, None] * (b - a)
        i = int(np.argmin(np.linalg.norm(foot - q, axis=1)))
        return foot[i], i, float(t[i])

    def _edge_distances(self, q: np.ndarray) -> np.ndarray:
        """(n, edges) distance of each point to each straight edge."""
        a, b = self.vertices(), np.roll(self.vertices(), -1, axis=0)
        ab = b - a
        aq = q[:, None, :] - a[None, :, :]
        t = np.clip(np.einsum("nij,ij->ni", aq, ab) / np.einsum("ij,ij->i", ab, ab), 0.0, 1.0)
        return np.linalg.norm(aq - t[..., None] * ab[None], axis=-1)


def _point(v, what: str) -> np.ndarray:
    a = np.asarray(v, dtype=np.float64)
    if a.shape != (2,) or not np.all(np.isfinite(a)):
        raise ValueError(f"{what} must be two finite numbers [x, y]")
    return a


def _points(p) -> tuple[np.ndarray, bool]:
    q = np.asarray(p, dtype=np.float64)
    return q.reshape(-1, 2), q.ndim == 1


def _shoelace(v: np.ndarray) -> float:
    x, y = v[:, 0], v[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def _winding_inside(q: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Even-odd ray casting (strict interior; boundary handled by the caller)."""
    a, b = v, np.roll(v, -1, axis=0)
    x, y = q[:, 0:1], q[:, 1:2]
    crosses = (a[:, 1] > y) != (b[:, 1] > y)
    with np.errstate(divide="ignore", invalid="ignore"):
        xc = a[:, 0] + (y - a[:, 1]) * (b[:, 0] - a[:, 0]) / (b[:, 1] - a[:, 1])
    return (np.sum(crosses & (x < xc), axis=1) % 2) == 1

