"""The patch: a circle whose outside meshes alike whatever lies inside.

The circle (Circle: fixed nodes), the circle of a run where it keeps the
clearances (meshing.clearance) from the fractures, tips, boundary and bc
points (patch_circle), and mesh_patched: the far field
built and meshed first, then the inside (far_cache.FarCache: a far field
the same as the last call's is not meshed again)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from meshing import clearance, point_symmetry
from meshing.far_cache import FarCache
from meshing.gmsh_geometry import (box, fracture_curves, mirror_dividers, outer_curves, point_tags, rosette_curves,
                                   vertex_at)
from meshing.p2_readback import extract, rim
from meshing.plan import Plan
from meshing.records import RawMesh
from meshing.size_field import size_field


@dataclass(frozen=True)
class Circle:
    """The patch circle in gmsh's frame and its fixed 1D mesh: N nodes (N even,
    at most `spacing` apart, counter-clockwise from angle pi/N) joined by N arcs of
    one edge each, mid node k at the middle of the arc from node k to k + 1.
    Fixed nodes, not gmsh's meshing of the circle, because a symmetric
    geometry's dividers end on them: where they end then changes nothing on
    the circle. With `k_out` (the outer divider's node, symmetric meshes)
    the nodes and mid nodes from k_out on for half a turn are placed by
    cos/sin and the others are their images 2c - x, as glue computes the
    image of a node: whichever half of the circle gmsh meshes (that depends
    on the inner divider), the coordinates are the same bits."""

    center: np.ndarray
    radius: float
    spacing: float
    points: np.ndarray  # (N, 2)
    mids: np.ndarray  # (N, 2)

    @classmethod
    def of(cls, center, radius: float, spacing: float, k_out: int | None = None) -> Circle:
        c = np.asarray(center, dtype=np.float64)
        n = max(8, 2 * math.ceil(math.pi * radius / spacing))
        angle = 2.0 * math.pi * (np.arange(n) + 0.5) / n
        pts = c + radius * np.stack([np.cos(angle), np.sin(angle)], axis=1)
        mids = c + radius * np.stack([np.cos(angle + math.pi / n), np.sin(angle + math.pi / n)], axis=1)
        if k_out is not None:
            own = (k_out + np.arange(n // 2)) % n
            pts[(own + n // 2) % n] = point_symmetry.rotate(pts[own], c)
            mids[(own + n // 2) % n] = point_symmetry.rotate(mids[own], c)
        return cls(c, float(radius), float(spacing), pts, mids)


def patch_circle(domain, plan: Plan, frame, patch, size, tip_size, sectors, sizes=None) -> Circle | None:
    """The patch (center, radius; the caller's frame) in gmsh's frame, or None
    when it does not fit: the circle within the domain and 2 size off its
    boundary and off every anchor (bc points, crack mouths), every fracture
    wholly inside or wholly outside it and clearance.clearance_of away from it,
    every tip likewise. Never an error: a patch that does not fit only
    costs the caller the reuse. Its nodes are `size` apart, or as far apart
    as the smallest of the size field `sizes` (gmsh's frame) on the
    triangles that meet the circle asks, and then the size field grades the
    cells from that spacing on the circle (size_field): where the field
    varies along the circle, one spacing fits it nowhere but at its finest
    (cells on the circle came out 0.6-0.7 in shape, against 0.9 in a
    uniform field)."""
    try:
        c = frame.to(np.asarray(patch[0], dtype=np.float64).reshape(2))
        r = float(patch[1]) / frame.scale
    except (TypeError, ValueError, IndexError):
        return None
    if not (np.all(np.isfinite(c)) and math.isfinite(r) and r > 0.0):
        return None
    if not domain.contains(c) or domain.distance_to_boundary(c) < r + clearance.patch_boundary_clearance(size):
        return None
    if any(np.linalg.norm(a - c) < r + clearance.patch_boundary_clearance(size) for _, _, a in plan.anchors):
        return None
    clear = clearance.clearance_of(size, tip_size)
    for pts in plan.fractures:
        if np.linalg.norm(pts - c, axis=1).max() <= r - clear:
            continue  # inside
        a, ab = pts[:-1], np.diff(pts, axis=0)
        t = np.clip(np.einsum("ij,ij->i", c - a, ab) / np.einsum("ij,ij->i", ab, ab), 0.0, 1.0)
        if np.linalg.norm(a + t[:, None] * ab - c, axis=1).min() >= r + clear:
            continue  # outside
        return None
    for t in plan.tips:
        if abs(np.linalg.norm(t.x - c) - r) < clearance.clearance_of(size, tip_size, t.h, sectors):
            return None
    spacing = size
    if sizes is not None and len(sizes[0]):
        tri = np.asarray(sizes[0], dtype=np.float64)
        vals = np.asarray(sizes[1], dtype=np.float64).reshape(len(tri), 3)
        d = np.linalg.norm(tri - c, axis=2)
        edge = np.linalg.norm(tri - np.roll(tri, 1, axis=1), axis=2).max(axis=1)
        meets = (d.min(axis=1) - edge <= r) & (d.max(axis=1) >= r)  # the nearest point is within an edge of a vertex
        if meets.any():
            spacing = min(size, max(tip_size, float(vals[meets].min())))
    return Circle.of(c, r, spacing)


def mesh_patched(domain, plan: Plan, size, tip_size, sectors, sizes, algorithm, half, mirror_sizes, scratch,
                 circle: Circle, reuse: bool = True) -> RawMesh:
    """gmsh_geometry.mesh_with_gmsh with a patch circle: the far field (outside the circle:
    the outer boundary, the fractures and tips there, the divider outside)
    is built first, so that its entities have the lowest tags and its
    surface is meshed first (gmsh meshes surfaces in tag order; meshed
    after the inside, the far surface of one of the identity tests came
    out otherwise, the inside's meshing changing the state gmsh starts
    the next surface from; meshed first, none did); then the inside. With `half`: the far half on the left of the outer divider, the
    patch half on the left of the inner one (point_symmetry.Inner).
    When the far field is the one this process meshed last (FarCache), its
    surfaces are not meshed (reuse False: meshed in any case)."""
    import gmsh  # 0.6 s: loaded by the first mesh (worker.load_gmsh), never by check

    geo = gmsh.model.geo
    gmsh.model.add("wingcrack")
    meshed = (lambda x: True) if half is None else half.left
    c, r, n = circle.center, circle.radius, len(circle.points)
    inside = [bool(np.linalg.norm(p[0] - c) < r) for p in plan.fractures]
    key = FarCache.key(domain, plan, inside, circle, half, size, tip_size, sectors, sizes, mirror_sizes, algorithm)
    cached = FarCache.get(key) if reuse else None

    anchor_tag, boundary_curves = outer_curves(geo, domain, plan, half)
    hub = geo.addPoint(c[0], c[1], 0.0)
    node = [geo.addPoint(p[0], p[1], 0.0) for p in circle.points]
    arcs = [geo.addCircleArc(node[j], hub, node[(j + 1) % n]) for j in range(n)]
    for a in arcs:
        geo.mesh.setTransfiniteCurve(a, 2)

    tip_of = {(t.fracture, t.end): k for k, t in enumerate(plan.tips)}
    tip_point: list = [None] * len(plan.tips)
    spoke: list = [None] * len(plan.tips)
    curves_of: dict[int, list] = {}  # fracture -> its crack curves, in order
    vertex_tags: dict[int, list[int]] = {}
    shared: dict[bytes, int] = {}
    sides = []
    for far_side in (True, False):
        group = [f for f in range(len(plan.fractures)) if inside[f] != far_side]
        tips = [k for k, t in enumerate(plan.tips) if bool(np.linalg.norm(t.x - c) >= r) == far_side]
        sectors_of, holes = [], []
        for k in tips:
            sector_loops, hole = rosette_curves(geo, plan.tips[k], sectors, meshed, tip_point, spoke, k)
            sectors_of += sector_loops
            if hole is not None:
                holes.append(hole)
        embedded, elsewhere = fracture_curves(geo, plan, group, anchor_tag, tip_of, tip_point, spoke, meshed,
                                              vertex_tags, curves_of, shared)
        if far_side:
            divider, loop = [], [cv for cv, _ in boundary_curves]
            if half is not None:  # R(p) .. R(q) | q .. p: the part between R(q) and q is inside
                k_out, m = half.k_out, len(half.points) // 2
                ends = {m - 1: node[(k_out + n // 2) % n], m: node[k_out]}
                tags = [ends.get(i) or vertex_at(plan, anchor_tag, vertex_tags, geo, q)
                        for i, q in enumerate(half.points)]
                divider = [geo.addLine(a, b) for a, b in zip(tags[:m - 1], tags[1:m])]
                divider += [geo.addLine(a, b) for a, b in zip(tags[m:-1], tags[m + 1:])]
                around = [-arcs[(k_out + n // 2 - 1 - j) % n] for j in range(n // 2)]
                loop = loop + divider[: m - 1] + around + divider[m - 1:]
                bounds = [geo.addCurveLoop(loop)] + holes
            else:
                bounds = [geo.addCurveLoop(loop), geo.addCurveLoop(arcs)] + holes
        else:
            if half is not None:
                k_in = half.inner.k
                pts = half.inner.points
                ends = {0: node[(k_in + n // 2) % n], len(pts) - 1: node[k_in]}
                tags = [ends.get(i) or vertex_at(plan, anchor_tag, vertex_tags, geo, q) for i, q in enumerate(pts)]
                divider = [geo.addLine(a, b) for a, b in zip(tags[:-1], tags[1:])]
                loop = [arcs[(k_in + j) % n] for j in range(n // 2)] + divider
            else:
                divider, loop = [], list(arcs)
            bounds = [geo.addCurveLoop(loop)] + holes
        surface = geo.addPlaneSurface(bounds)
        rosettes = [(geo.addPlaneSurface([lp]), corners) for lp, corners in sectors_of]
        sides.append((surface, rosettes, divider, embedded, elsewhere, group))
    for _, rosettes, _, _, _, _ in sides:
        for s, corners in rosettes:
            geo.mesh.setTransfiniteSurface(s, "Left", list(corners))
    geo.synchronize()
    if half is not None:
        mirror_dividers(half, [divider for _, _, divider, _, _, _ in sides])
    for surface, _, _, embedded, _, _ in sides:
        if embedded:
            gmsh.model.mesh.embed(1, embedded, 2, surface)

    groups = [(embedded + elsewhere, [plan.fractures[f] for f in group])
              for _, _, _, embedded, elsewhere, group in sides]
    size_field(plan, [centre for centre, _ in tip_point], [], size, tip_size, sectors,
               sizes, half.center if mirror_sizes else None, box(domain), scratch, crack_groups=groups,
               circle=(arcs, circle.spacing))
    gmsh.option.setNumber("Mesh.Algorithm", algorithm)
    far_surfaces = [sides[0][0]] + [s for s, _ in sides[0][1]]
    if cached is not None:  # the far surfaces' boundaries are meshed (visible), the surfaces not
        gmsh.model.setVisibility([(2, s) for s in far_surfaces], 0, recursive=False)
        gmsh.option.setNumber("Mesh.MeshOnlyVisible", 1)
    gmsh.model.mesh.generate(2)

    points = point_tags(plan, anchor_tag, half)
    used_arcs = list(range(n))
    mirrored_arcs: list[int] = []
    if half is not None:
        far_arcs = {(half.k_out + j) % n for j in range(n // 2)}
        patch_arcs = {(half.inner.k + j) % n for j in range(n // 2)}
        used_arcs = sorted(far_arcs | patch_arcs)
        # an arc in one half's boundary only: its image is the other's (glue mirrors their nodes)
        mirrored_arcs = [arcs[j] for j in sorted(far_arcs ^ patch_arcs)]
    crack_curves = [cv for f in range(len(plan.fractures)) for cv in curves_of[f]]
    (_, _, far_divider, _, _, _), (_, _, inner_divider, _, _, _) = sides
    info: dict = {}
    raw = extract(boundary_curves, crack_curves, tip_point, points, far_divider + inner_divider + mirrored_arcs,
                  far_surfaces=far_surfaces, mids={arcs[j]: circle.mids[j] for j in used_arcs},
                  far_cells=cached, info=None if cached is not None else info, rim=rim(domain, boundary_curves))
    if cached is None:
        FarCache.put(key, raw.x[raw.cells[raw.far]], info["far_interior"])
    return raw
