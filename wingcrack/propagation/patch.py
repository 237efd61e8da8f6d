"""The patch of a propagation run: a circle around the growing fractures.

Inside it every step remeshes; outside it the mesher makes the same cells
step after step (meshing.crack_mesh, `patch`), so that the far field's
stiffness is factorised once and condensed onto the circle
(fem.far_field), and a step factorises the patch only. The loop keeps one
patch while every growing fracture stays clear inside it and every other
one clear outside (an epoch); then it draws a new one around the grown
fractures, `STEPS_AHEAD` steps of Lmax wider than they are.

Only on fixed meshes (mesh.adaptive = false): an adaptive mesh takes new
element sizes everywhere every step, so nothing outside would stay the
same. A circle that does not fit in the domain (the mesher's clearance
from the boundary) means no patch: every step remeshes the whole body, as
without one.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from meshing.clearance import patch_boundary_clearance, patch_clearance

#: the growth steps (of Lmax at every tip) an epoch leaves room for: a
#: wider patch makes each step's factorisation of the patch dearer, a
#: narrower one starts epochs (each a whole factorisation) more often
STEPS_AHEAD = 8


@dataclass(frozen=True, eq=False)
class Patch:
    center: np.ndarray   # (2,) m
    radius: float        # m

    def for_mesher(self) -> tuple:
        return (np.asarray(self.center, float), float(self.radius))

    def to_list(self) -> list:
        return [float(self.center[0]), float(self.center[1]), float(self.radius)]

    @classmethod
    def from_list(cls, values) -> "Patch":
        return cls(np.array(values[:2], dtype=np.float64), float(values[2]))

    def __eq__(self, other) -> bool:
        return isinstance(other, Patch) and self.radius == other.radius and \
            bool(np.array_equal(self.center, other.center))


def clearance(case) -> float:
    """The room the mesher asks between the circle and any fracture (and,
    with `boundary_clearance`, the outer boundary): meshing's own rule."""
    return patch_clearance(case.mesh.size, case.mesh.tip_size, case.mesh.sectors)


def boundary_clearance(case) -> float:
    return patch_boundary_clearance(case.mesh.size)


def wanted(case) -> bool:
    """Whether a run of this case meshes with a patch at all."""
    return not case.mesh.adaptive and case.propagation.steps >= 2


def _distance_to_polyline(c: np.ndarray, pts: np.ndarray) -> float:
    """The shortest distance from point c to the polyline through pts."""
    if len(pts) == 1:
        return float(np.linalg.norm(pts[0] - c))
    a, b = pts[:-1], pts[1:]
    ab = b - a
    t = np.clip(np.einsum("ij,ij->i", c - a, ab) / np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-300), 0.0, 1.0)
    return float(np.min(np.linalg.norm(a + t[:, None] * ab - c, axis=1)))


def _growing(fset) -> set:
    return {i for i, _ in fset.active_tips()}


def holds(patch: Patch | None, case, fset) -> bool:
    """Whether `patch` still serves these fractures: every growing one (an
    end that may still grow) clear inside it, every other one clear inside
    or clear outside."""
    if patch is None:
        return False
    c, r, clear = patch.center, patch.radius, clearance(case)
    growing = _growing(fset)
    if not growing:
        return False
    for i, f in enumerate(fset.fractures):
        inside = np.max(np.linalg.norm(f.points - c, axis=1)) <= r - clear
        if i in growing and not inside:
            return False
        if not inside and _distance_to_polyline(c, f.points) < r + clear:
            return False
    return True


def choose(case, fset) -> Patch | None:
    """A patch for the fractures as they are: centred on the bounding box of
    the growing ones (on the centre of a point-symmetric geometry, where
    the mesher keeps its symmetry), wide enough for STEPS_AHEAD steps, and
    taking in whole every other fracture it would come near. None when
    nothing grows or the circle does not fit in the domain."""
    growing = _growing(fset)
    if not growing:
        return None
    pts = np.vstack([fset.fractures[i].points for i in sorted(growing)])
    c = 0.5 * (pts.min(axis=0) + pts.max(axis=0))
    clear = clearance(case)
    r = float(np.max(np.linalg.norm(pts - c, axis=1))) + clear + STEPS_AHEAD * case.propagation.length
    taken = set(growing)
    changed = True
    while changed:
        changed = False
        for i, f in enumerate(fset.fractures):
            if i in taken or _distance_to_polyline(c, f.points) >= r + clear:
                continue
            taken.add(i)
            r = max(r, float(np.max(np.linalg.norm(f.points - c, axis=1))) + clear)
            changed = True
    domain = case.domain
    if not bool(domain.contains(c)) or float(domain.distance_to_boundary(c)) < r + boundary_clearance(case):
        return None
    return Patch(c, r)


def next_patch(patch: Patch | None, case, fset) -> Patch | None:
    """The patch of the next mesh: this one while it holds, else a new one
    (None: no patch)."""
    if not wanted(case):
        return None
    return patch if holds(patch, case, fset) else choose(case, fset)
