"""The coordinates gmsh sees: the caller's geometry moved and scaled exactly
(by powers of two) to where gmsh's absolute tolerances hold."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from meshing.domain import Domain
from meshing.plan import Plan


@dataclass(frozen=True)
class Frame:
    """The coordinates gmsh sees, x' = (x - origin) / scale: the domain 2^-10
    to 2^10 units across and its centre within 32 sizes of the origin, where
    gmsh's absolute tolerances hold (it fails to recover edges of a domain
    4e-9 m across, and the divider's periodic nodes stop mirroring at 3e4
    sizes from the origin). scale is a power of two and origin a multiple
    of a power of two above the domain's size, so the map is exact both
    ways for the given geometry and gmsh meshes a moved or scaled geometry
    exactly as the original; for domains of 1e-3 to 1e3 m near the origin
    (every case in cases/) it is the identity."""

    origin: np.ndarray
    scale: float

    @classmethod
    def of(cls, domain: Domain) -> Frame:
        size = float(domain.length_scale())
        scale = 2.0 ** (20 * round(math.log2(size) / 20))
        if domain.shape == "disc":
            centre = np.asarray(domain.center, dtype=np.float64)
        else:
            v = domain.vertices()
            centre = 0.5 * (v.min(axis=0) + v.max(axis=0))
        grid = 2.0 ** (math.floor(math.log2(size)) + 6)
        return cls(np.round(centre / grid) * grid, scale)

    def to(self, x) -> np.ndarray:
        return (np.asarray(x, dtype=np.float64) - self.origin) / self.scale

    def back(self, x) -> np.ndarray:
        return np.asarray(x, dtype=np.float64) * self.scale + self.origin

    def domain(self, domain: Domain) -> Domain:
        if self.scale == 1.0 and not self.origin.any():
            return domain
        if domain.shape == "disc":
            return Domain("disc", center=self.to(domain.center), radius=domain.radius / self.scale)
        if domain.shape == "rectangle":
            return Domain("rectangle", corner=self.to(domain.corner), size=domain.size / self.scale)
        return Domain("polygon", points=self.to(domain.points))

    def plan(self, plan: Plan) -> Plan:
        if self.scale == 1.0 and not self.origin.any():
            return plan
        return dataclasses.replace(
            plan,
            fractures=[self.to(p) for p in plan.fractures],
            tips=[dataclasses.replace(t, x=self.to(t.x), h=t.h / self.scale) for t in plan.tips],
            anchors=[(edge, param, self.to(p)) for edge, param, p in plan.anchors],
        )
