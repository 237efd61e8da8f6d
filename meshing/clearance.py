"""How far the patch circle of a fixed-mesh run keeps from fractures, tips
and the boundary (pure arithmetic on the sizes, no gmsh): the mesher asks
it of a circle, and the propagation loop of the patch it chooses. The size
field's grading is defined here because the clearance follows from it."""
from __future__ import annotations

import math

# Size growth per element layer away from tips and fractures: h(d) = h0 + GRADING * d
# makes neighbouring layers differ by a factor 1 + GRADING.
GRADING = 0.3
#: the same around the tips (the rosette's surroundings set the SIF accuracy)
TIP_GRADING = 0.3


def clearance_of(size: float, tip_size: float, tip_h: float | None = None, sectors: int = 16) -> float:
    """The least distance between the patch circle and a fracture (tip_h None)
    or a tip with rosette radius tip_h. The size field (size_field) is a min
    of thresholds that reach `size` at DistMax from their fracture or tip:
    (size - h_crack) / GRADING from a fracture (h_crack >= tip_size, so
    (size - tip_size) / GRADING bounds it), h + (size - h_ring) / TIP_GRADING
    from a tip (h_ring the rosette's chord, below tip_size: a tip reaches
    farther than its fracture). Beyond it every threshold is `size` exactly
    (gmsh's Threshold returns SizeMax there, and its sampled distance never
    undercuts the true one), so on the circle and outside it the field does
    not depend on what is inside. The 2 size more keep the graded cells
    inside off the circle: the cells that touch it inside are of its own
    spacing, and the inside's meshing starts from a boundary that is not
    crowded by the refinement (tests/unit/test_meshing_patch.py measures the far
    field's identity with it)."""
    if tip_h is None:
        return 2.0 * size + (size - tip_size) / GRADING
    return 2.0 * size + tip_h + (size - 2.0 * tip_h * math.sin(math.pi / sectors)) / TIP_GRADING


#: the smallest rosette radius of a tip, in tip sizes (a wing's: min(tip_size,
#: 0.75 L) with L >= 0.4 tip_size, wingcrack.case's Propagation.length)
SMALLEST_ROSETTE = 0.3


def patch_clearance(size: float, tip_size: float, sectors: int) -> float:
    """The room a caller leaves between a patch circle and any fracture or
    tip for the mesher to use the patch: clearance_of's largest over
    fractures and over tips of any rosette radius from SMALLEST_ROSETTE
    tip sizes to tip_size (the tip's bound is linear in the radius, so the
    ends bound it)."""
    return max(clearance_of(size, tip_size),
               *(clearance_of(size, tip_size, h, sectors) for h in (SMALLEST_ROSETTE * tip_size, tip_size)))


def patch_boundary_clearance(size: float) -> float:
    """The room between a patch circle and the outer boundary (and every bc
    point) that the mesher asks."""
    return 2.0 * size
