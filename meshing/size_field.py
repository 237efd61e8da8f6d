"""The size field gmsh meshes to: graded from the tips' rosettes and the
fractures to `size`, bounded by a given field (sampled on a grid written
for gmsh) and by the patch circle's spacing."""

from __future__ import annotations

import math
import os

import numpy as np
import wingcrack_kernels as _kernels

from meshing.clearance import GRADING, TIP_GRADING
from meshing.plan import Plan


# Element size along a fracture, in tip sizes (capped by `size`).
CRACK_SIZE_IN_TIPS = 2.0


def size_field(plan: Plan, tip_points, crack_curves, size, tip_size, sectors, sizes=None, center=None,
               box=None, scratch=None, crack_groups=None, circle=None):
    """h = min(size, h_ring + GRADING (r - h_tip), h_crack + GRADING dist, sizes): the rosette
    chord length at each ring, the crack size on the fracture, growing linearly; and the
    given size field (linear on its triangles), never below tip_size, sampled on a grid
    over `box` (lo (2,), hi (2,)) written into the directory `scratch`. With a `center`
    the size field is made point-symmetric: sizes also bounds at the images 2 center - x.
    crack_groups: [(curves, their polylines)] each measured by a distance field of its
    own (crack_curves then unused), so that one group's sampling does not depend on the
    others' (the patch's far field and its inside); circle: (curves, spacing) the patch
    circle, h <= spacing + GRADING dist: cells graded from its fixed nodes."""
    import gmsh  # 0.6 s: loaded by the first mesh (worker.load_gmsh), never by check

    field = gmsh.model.mesh.field
    gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
    gmsh.option.setNumber("Mesh.MeshSizeMax", size)
    parts = []
    # tips of one rosette radius share one distance field: the threshold grows
    # with the distance, so the least of their thresholds is the threshold of
    # the nearest tip, and one field evaluates it once instead of once a tip
    by_radius: dict[float, list[int]] = {}
    for t, centre in zip(plan.tips, tip_points):
        by_radius.setdefault(t.h, []).append(centre)
    for h, centres in by_radius.items():
        h_ring = 2.0 * h * math.sin(math.pi / sectors)
        d = field.add("Distance")
        field.setNumbers(d, "PointsList", centres)
        parts.append(_threshold(d, h_ring, size, h, TIP_GRADING))
    if crack_groups is None:
        crack_groups = [(crack_curves, plan.fractures)]
    for curves, polylines in crack_groups:
        if not curves:
            continue
        h_crack = min(size, CRACK_SIZE_IN_TIPS * tip_size)
        longest = max(np.max(np.linalg.norm(np.diff(p, axis=0), axis=1)) for p in polylines)
        d = field.add("Distance")
        field.setNumbers(d, "CurvesList", curves)
        field.setNumber(d, "NumPointsPerCurve", int(min(20000, math.ceil(4.0 * longest / h_crack) + 2)))
        parts.append(_threshold(d, h_crack, size, 0.0))
    if circle is not None and circle[1] < size:
        d = field.add("Distance")
        field.setNumbers(d, "CurvesList", circle[0])
        field.setNumber(d, "NumPointsPerCurve", 4)  # the arcs are one spacing long
        parts.append(_threshold(d, circle[1], size, 0.0))
    if sizes is not None:
        tri, vals = (np.asarray(a, dtype=np.float64) for a in sizes)
        vals = np.maximum(vals.reshape(len(tri), 3), tip_size)
        # a field that asks nowhere for less than `size` changes nothing (MeshSizeMax)
        if len(tri) and vals.min() < size:
            if center is not None:
                tri = np.concatenate([tri, 2.0 * np.asarray(center) - tri])
                vals = np.concatenate([vals, vals])
            parts.append(_grid_field(tri, vals, box, size, os.path.join(scratch, "sizes.bin")))
    if not parts:
        gmsh.option.setNumber("Mesh.MeshSizeMin", size)
        return
    m = field.add("Min")
    field.setNumbers(m, "FieldsList", parts)
    field.setAsBackgroundMesh(m)


# The size grid's spacing in units of the smallest size in the field: a mesh of
# that size cannot represent variations finer than itself, and half of it puts
# two grid steps in every such element. Finer grids cost more to write and to
# read without changing the meshes (a cracked disc's: the same cell counts to
# 1.5 % from 1 to 1/4 of the smallest size).
GRID_SPACING = 0.5
# At most this many grid nodes (8 bytes each in the file gmsh reads back):
# the grid grows like (domain / tip_size)^2 while the adaptive mesh grows far
# more slowly, so a huge domain or a tiny tip would spend more on the grid than
# on the mesh. Above it the spacing grows; the tip and crack fields, not the
# grid, set the sizes near tips and fractures, where the field is smallest.
GRID_MAX_NODES = 1 << 21


def _grid_field(tri, vals, box, size, path) -> int:
    """A gmsh Structured field (bilinear on a regular grid over `box`) of the
    P1 field (tri (m, 3, 2), vals (m, 3)); where several triangles overlap (a
    field and its image) the smallest value. gmsh reads `path` lazily, while
    meshing: it must stay until the mesh is generated."""
    import gmsh  # 0.6 s: loaded by the first mesh (worker.load_gmsh), never by check

    lo, step, counts = _grid(_binding_box(tri, vals, box, size), float(vals.min()))
    grid = _kernels.rasterise_p1(tri, vals, lo, [step, step], counts, size)
    with open(path, "wb") as out:  # gmsh's binary Structured format, one z layer
        out.write(np.array([lo[0], lo[1], 0.0, step, step, 1.0]).tobytes())
        out.write(np.array([counts[0], counts[1], 1], dtype=np.int32).tobytes())
        out.write(np.ascontiguousarray(grid, dtype=np.float64).tobytes())
    field = gmsh.model.mesh.field
    s = field.add("Structured")
    field.setString(s, "FileName", path)
    field.setNumber(s, "TextFormat", 0)
    # gmsh 4.8 leaves these two uninitialised (a point outside the grid then
    # read garbage: meshes came out coarse or endlessly fine at random). The
    # grid covers where the field binds (_binding_box); outside it the field is
    # `size`, which bounds nothing (MeshSizeMax).
    field.setNumber(s, "SetOutsideValue", 1)
    field.setNumber(s, "OutsideValue", size)
    return s


def _binding_box(tri, vals, box, size) -> tuple[np.ndarray, np.ndarray]:
    """The part of `box` where the P1 field (tri, vals) asks for less than
    `size`: the bounding box of the cells with a value below it, widened by
    a tenth of its extent and by the largest of those cells (so that the
    grid's last rows lie where the field is `size` or are sampled from the
    cells themselves), within `box`. Elsewhere the field is at least
    `size` and bounds nothing: on a domain much larger than its cracks
    (a plate 1000 tip sizes across) the grid shrinks to the cracks'
    neighbourhood instead of spanning the domain at the smallest size."""
    lo, hi = (np.asarray(b, dtype=np.float64) for b in box)
    binding = tri[vals.min(axis=1) < size]
    if not len(binding):
        return lo, hi
    pts = binding.reshape(-1, 2)
    b_lo, b_hi = pts.min(axis=0), pts.max(axis=0)
    cell = float(np.max(binding.max(axis=1) - binding.min(axis=1)))
    pad = 0.1 * float(np.max(b_hi - b_lo)) + cell
    return np.maximum(lo, b_lo - pad), np.minimum(hi, b_hi + pad)


def _grid(box, smallest: float) -> tuple[np.ndarray, float, np.ndarray]:
    """(origin, step, counts (2,)) of the size grid over box = (lo, hi), its
    last node beyond hi: step GRID_SPACING * smallest, coarser where that
    would exceed GRID_MAX_NODES."""
    lo, hi = (np.asarray(b, dtype=np.float64) for b in box)
    extent = hi - lo
    step = max(GRID_SPACING * smallest, math.sqrt(float(np.prod(extent)) / GRID_MAX_NODES))
    # the last node strictly beyond hi: gmsh takes a point on the last node
    # (the domain's own boundary) as outside the grid
    counts = np.floor(extent / step).astype(np.int64) + 2
    while counts.prod() > GRID_MAX_NODES:  # the +2 nodes of a thin domain
        step *= 1.05
        counts = np.floor(extent / step).astype(np.int64) + 2
    return lo, step, counts


def _threshold(distance_field, h0, size, d0, grading=GRADING):
    import gmsh  # 0.6 s: loaded by the first mesh (worker.load_gmsh), never by check

    field = gmsh.model.mesh.field
    t = field.add("Threshold")
    field.setNumber(t, "InField", distance_field)
    field.setNumber(t, "SizeMin", h0)
    field.setNumber(t, "SizeMax", size)
    field.setNumber(t, "DistMin", d0)
    field.setNumber(t, "DistMax", d0 + (size - h0) / grading)
    return t
