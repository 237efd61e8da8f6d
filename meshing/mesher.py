"""Conforming P2 crack meshes: gmsh geometry, tip rosettes, split faces, quarter points.

One call builds the whole mesh of one step (paper sections 3.1-3.3):

1. the outer boundary, split at every bc point and every edge-crack mouth, so
   that each becomes a mesh node;
2. around every crack tip a structured rosette of `sectors` straight triangles
   of radius `tip_size` (one spoke along the crack), the rest unstructured,
   graded from ~`tip_size` at the tips to `size` away from the fractures;
3. second order: gmsh meshes first order, the mid nodes are added here
   (p2_readback; on the disc rim and the patch circle on the circle);
4. the crack faces split apart (`wingcrack_kernels.split_faces`): each node on
   a crack face gets one copy per side, and the copies are paired for contact;
5. the mid nodes of the edges at each tip moved to the quarter points.

A geometry that the half turn about the domain's centre maps onto itself is
meshed point-symmetrically (meshing/point_symmetry.py): gmsh meshes the half
on one side of a straight divider through the centre, the other half is its
image, so symmetric problems give symmetric answers to round-off
(stats["symmetric"]).

With a `patch` circle the mesh inside it and outside it are separate gmsh
surfaces, the outside (the far field) built and meshed first, so that the
far field comes out bitwise the same whatever the fractures inside: its
factorisation can be kept from one propagation step to the next. A far
field that is the same as the last call's is not meshed again (far_cache).

Lengths in metres. Node order in cells is gmsh's [v0, v1, v2, m01, m12, m20],
counter-clockwise. Fracture direction d runs from a polyline's first point to
its last; the + face is on the left of d.

This module is the mesher's public face; the stages live in modules of
their own, none of which imports this one:

    plan.py           the plan: pure geometry, checked, before gmsh
    frame.py          the exact coordinate frame gmsh sees
    gmsh_session.py   one gmsh session (options, scratch folder, the retry of a far-field miss)
    gmsh_geometry.py  the gmsh geometry of the whole domain (or its half) and its helpers
    patch.py          the patch circle, meshed with its outside first
    far_cache.py      the far field kept from the last call
    size_field.py     the size field gmsh meshes to
    p2_readback.py    the mesh read back from gmsh, made second order
    tip_nodes.py      the tips' nodes after the faces are split
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import wingcrack_kernels as _kernels

from meshing import point_symmetry
from meshing.domain import Domain
from meshing.frame import Frame
from meshing.gmsh_session import gmsh_session
from meshing.patch import Circle, patch_circle
from meshing.plan import ON_BOUNDARY, Plan, make_plan, with_divider
from meshing.records import RawMesh, SplitMesh
from meshing.timeout import MeshTimeout, start_with_timeout
from meshing.tip_nodes import TipNodes, tip_nodes

# gmsh and wingcrack_kernels are imported inside the functions that use them:
# `import meshing` (for Domain, in the case checker) must stay light.


@dataclass
class CrackMesh:
    x: np.ndarray  # (n, 2) nodes, quarter points already moved
    cells: np.ndarray  # (m, 6) P2 triangles, gmsh order, counter-clockwise
    boundary_edges: np.ndarray  # (b, 3) [a, b, mid], outer boundary only
    boundary_tags: np.ndarray  # (b,) tag of each boundary edge
    boundary_names: dict[str, int]  # name -> tag (tags from 1)
    pairs: np.ndarray  # (p, 2) [plus, minus] copies facing each other
    pair_normal: np.ndarray  # (p, 2) unit left normal of d (points into the + side)
    pair_fracture: np.ndarray  # (p,)
    crack_edges: np.ndarray  # (k, 3) + face copy, oriented along d, ordered along each fracture
    crack_fracture: np.ndarray  # (k,)
    tips: list[TipNodes]
    point_nodes: np.ndarray  # (q,) node of each bc point (at a crack mouth: one of its 2 copies)
    crack_edges_minus: np.ndarray | None = None  # (k, 3) - face copy of crack_edges
    stats: dict = field(default_factory=dict)
    # (m,) True for the cells outside the patch circle (the far field); None without a patch
    far: np.ndarray | None = None


def crack_mesh(
    domain: Domain,
    fractures: Sequence[np.ndarray],
    points: Sequence[np.ndarray],
    size: float,
    tip_size: float,
    sectors: int = 16,
    sizes: tuple[np.ndarray, np.ndarray] | None = None,
    timeout: float | None = None,
    patch: tuple[np.ndarray, float] | None = None,
) -> CrackMesh:
    """Mesh `domain` with the `fractures` (polylines (n, 2)) as double-noded
    cracks and the bc `points` (on the boundary) as nodes.

    size: element size away from fractures; tip_size: rosette radius h (and
    the distance tip - corner node; a tip whose last segment is shorter gets a
    rosette of 0.75 times that length);
    sizes = (triangles (m, 3, 2), values (m, 3)): an extra upper bound of the
    element size, linear on the given triangles (the error-estimate field of
    the previous step); timeout: seconds gmsh may take (None: no limit); on
    timeout it is retried once with 1.5 times coarser `sizes` and another
    meshing algorithm, then MeshTimeout (a RuntimeError) is raised.
    patch = (center (2,), radius): a circle (metres, the caller's frame) meshed
    as a curve of its own, with the cells inside and outside it meshed as
    separate gmsh surfaces, the outside first: then the cells outside (the
    far field, CrackMesh.far) come out bitwise the same in every call with
    the same domain, bc points, size, tip_size, sectors, sizes and patch and
    the same fractures outside, whatever the fractures inside, and the
    circle's nodes with them (node numbering may differ). A patch that does
    not fit (patch_circle: off the boundary and the bc points by 2 size,
    every fracture wholly inside or outside and clear of it by
    clearance.clearance_of) is ignored (stats["patch"] False, far None), as is one
    not centred on the centre of a point-symmetric geometry (the symmetry is
    kept instead; a centred one is used with it).
    A fracture end that lies on another fracture (or on a non-adjacent part of
    its own) is a T-junction: no rosette there, the other fracture is split at
    the point, and the junction node gets three copies; two ends at one point
    meet end to end (two copies); fractures that cross get the crossing as a
    vertex of both (an X: four copies), and so on for any number of fractures
    through one point (meshing/network.py; the same coordinates in each). A
    fracture may run from boundary to boundary (both mouths split).
    crack_mesh(...) is start_crack_mesh(...).result(): the same mesh.
    Each call opens and closes its own gmsh session (gmsh.initialize /
    finalize), so do not call it while holding a gmsh session of your own.
    Raises ValueError for geometry that cannot be meshed as asked (a rule of
    meshing/admissibility.py, the one `wingcrack check` applies: Inadmissible,
    its text naming the case key), RuntimeError when gmsh fails or a cell
    comes out inverted. gmsh sees the geometry in an exact frame of its own
    (Frame): any domain size and offset the rules allow mesh alike.
    """
    return start_crack_mesh(domain, fractures, points, size, tip_size, sectors, sizes, timeout, patch).result()


def start_crack_mesh(
    domain: Domain,
    fractures: Sequence[np.ndarray],
    points: Sequence[np.ndarray],
    size: float,
    tip_size: float,
    sectors: int = 16,
    sizes: tuple[np.ndarray, np.ndarray] | None = None,
    timeout: float | None = None,
    patch: tuple[np.ndarray, float] | None = None,
) -> PendingMesh:
    """crack_mesh begun: the arguments are checked and the geometry planned
    here (ValueError at once, as crack_mesh raises it), gmsh's work is sent
    to the meshing worker (the time limit runs from now), and the caller may
    go on; PendingMesh.result() waits for it and returns the CrackMesh (and
    raises what crack_mesh raises after planning). With timeout None gmsh
    runs in-process, at result()."""
    t_start = time.perf_counter()
    # 16 or more is what displacement correlation needs; fewer (down to 8)
    # are allowed for convergence studies of the rosette itself.
    if sectors < 8:
        raise ValueError(f"sectors must be >= 8, not {sectors}")
    if not (0.0 < tip_size < size):
        raise ValueError(f"need 0 < tip_size < size, got tip_size={tip_size}, size={size}")
    plan = make_plan(domain, fractures, points, tip_size)
    # from here on in gmsh's frame: the checks above spoke in the caller's
    frame = Frame.of(domain)
    domain, plan = frame.domain(domain), frame.plan(plan)
    size, tip_size = size / frame.scale, tip_size / frame.scale
    if sizes is not None:
        sizes = (frame.to(sizes[0]), np.asarray(sizes[1], dtype=np.float64) / frame.scale)
    circle = None if patch is None else patch_circle(domain, plan, frame, patch, size, tip_size, sectors, sizes)
    tips, anchors = [(t.x, t.h) for t in plan.tips], [p for _, _, p in plan.anchors]
    half, centre = None, point_symmetry.domain_center(domain)
    if circle is not None and centre is not None and \
            np.linalg.norm(circle.center - centre) <= 1e-9 * domain.length_scale():
        circle = Circle.of(centre, circle.radius, circle.spacing)
        half = point_symmetry.find_half_patched(domain, plan.fractures, tips, anchors, tip_size, circle.radius,
                                                circle.points)
        if half is not None:
            circle = Circle.of(centre, circle.radius, circle.spacing, half.k_out)
    if half is None:
        half = point_symmetry.find_half(domain, plan.fractures, tips, anchors, tip_size)
        if half is not None:
            circle = None  # symmetry first: a circle off the centre would break it
    if half is not None:
        plan = with_divider(domain, plan, half)

    mirror_sizes = False
    if half is not None and sizes is not None:
        halved = point_symmetry.sizes_for_half(*sizes, half, ON_BOUNDARY * domain.length_scale())
        mirror_sizes = halved is None  # not symmetric: bound by the field and its image
        sizes = sizes if halved is None else halved
    return PendingMesh(domain, plan, frame, half, (size, tip_size, sectors, sizes, mirror_sizes, circle), timeout,
                       time.perf_counter() - t_start)


class PendingMesh:
    """A crack mesh begun by start_crack_mesh: result() collects it (once),
    cancel() abandons it (the meshing worker is killed if it is still at it).
    The worker makes the whole CrackMesh (_meshed: gmsh, then the split
    faces, quarter points and checks), so that the caller, which works on
    the previous step meanwhile, receives it finished."""

    def __init__(self, domain, plan, frame, half, job, timeout, seconds_planning):
        self._domain, self._plan, self._frame, self._half, self._job = domain, plan, frame, half, job
        self._timeout, self._seconds = timeout, seconds_planning
        self._first = self.attempt(1.0, 6)

    def attempt(self, coarsen: float, algorithm: int):
        size, tip_size, sectors, sizes, mirror_sizes, circle = self._job
        scaled = None if sizes is None else (sizes[0], coarsen * np.asarray(sizes[1], dtype=np.float64))
        args = (self._domain, self._plan, size, tip_size, sectors, scaled, self._half, mirror_sizes, algorithm)
        if circle is not None:
            args += (circle,)
        # the session by reference from here (the module's at this moment), for the worker to call
        finish = (self._domain, self._plan, self._frame, self._half, circle is not None)
        return start_with_timeout(_meshed, (gmsh_session, args, finish), self._timeout)

    def cancel(self) -> None:
        self._first.cancel()

    def result(self) -> CrackMesh:
        retried = False
        try:
            done = self._first.result()
            t_worker = self._first.seconds
        except MeshTimeout:
            retried = True  # once: coarser sizes, Delaunay instead of Frontal-Delaunay
            second = self.attempt(1.5, 5)
            done = second.result()
            t_worker = self._timeout + second.seconds
        t_after = time.perf_counter()
        if isinstance(done, BaseException):   # raised after gmsh, in the worker: raised here as it was
            raise done
        mesh, t_gmsh = done
        mesh.stats["seconds_gmsh"] = t_gmsh + (self._timeout if retried else 0.0)
        mesh.stats["gmsh_retried"] = retried
        # planning + the worker's gmsh and finishing + the rest here
        mesh.stats["seconds"] = self._seconds + t_worker + (time.perf_counter() - t_after)
        return mesh


def _meshed(session, args: tuple, finish: tuple):
    """(CrackMesh, gmsh's seconds) of session(*args) (gmsh_session),
    finished by _finish(*finish, ...) ((domain, plan, frame, half,
    patched): the same objects as in args, which one pickle carries once),
    in the meshing worker; an error after gmsh is returned, not raised
    (PendingMesh.result raises it in the caller with its own type)."""
    t0 = time.perf_counter()
    raw = session(*args)
    t_gmsh = time.perf_counter() - t0
    domain, plan, frame, half, patched = finish
    try:
        return _finish(domain, plan, frame, half, raw, patched), t_gmsh
    except (RuntimeError, ValueError) as error:
        return error


def _finish(domain, plan, frame, half, raw: RawMesh, patched: bool) -> CrackMesh:
    """The CrackMesh of gmsh's `raw` mesh (in gmsh's frame): the half glued
    to its image, the crack faces split, quarter points at the tips,
    checked, back in the caller's frame."""
    if half is not None:
        raw = _glue(domain, plan, half, raw)
    t0 = time.perf_counter()
    # the binding answers a dict: its one conversion into the record
    split = SplitMesh(**_kernels.split_faces(raw.x, raw.cells, raw.crack_edges, raw.crack_fracture,
                                             raw.boundary_edges))
    tips = tip_nodes(plan, raw, split)
    x = _kernels.quarter_points(split.x, split.cells, np.array([t.node for t in tips], dtype=np.int64))
    jac = _kernels.min_jacobian(x, split.cells)
    if jac.size and jac.min() <= 0.0:
        bad = int(np.argmin(jac))
        raise RuntimeError(f"mesh cell {bad} has min det J = {jac[bad]:.3g} <= 0 after quarter points")
    t_split = time.perf_counter() - t0
    x, jac = frame.back(x), jac * frame.scale**2
    for t in tips:
        t.x, t.h = frame.back(t.x), t.h * frame.scale

    names = {name: i + 1 for i, name in enumerate(domain.boundary_names())}
    mesh = CrackMesh(
        x=x,
        cells=split.cells,
        boundary_edges=split.boundary_edges,
        boundary_tags=np.array([names[n] for n in raw.boundary_name], dtype=np.int64),
        boundary_names=names,
        pairs=split.pairs,
        pair_normal=split.pair_normal,
        pair_fracture=split.pair_fracture,
        crack_edges=split.crack_edges,
        crack_fracture=raw.crack_fracture,
        tips=tips,
        point_nodes=raw.point_nodes,
        crack_edges_minus=split.crack_edges_minus,
        far=raw.far,
    )
    mesh.stats = {
        "nodes": int(len(x)),
        "vertices": int(len(np.unique(mesh.cells[:, :3]))),
        "cells": int(len(mesh.cells)),
        "boundary_edges": int(len(mesh.boundary_edges)),
        "crack_edges": int(len(mesh.crack_edges)),
        "pairs": int(len(mesh.pairs)),
        "tips": len(tips),
        "min_jacobian": float(jac.min()) if jac.size else 0.0,
        "min_quality": float(triangle_quality(x, mesh.cells).min()) if len(mesh.cells) else 0.0,
        # gmsh's own time (in the worker: not the caller's wait, which the pipeline overlaps): PendingMesh.result
        "seconds_gmsh": None,
        "gmsh_retried": False,
        "symmetric": half is not None,
        "divider_angle": None if half is None else math.degrees(half.angle),
        "patch": patched,
        "far_reused": bool(raw.far_reused),  # the far field's cells from the last call's (far_cache.FarCache)
        # the divider inside the patch circle (symmetric meshes with a patch; its own, see point_symmetry.Inner)
        "inner_divider_angle": None if half is None or half.inner is None else math.degrees(half.inner.angle),
        "seconds_split": t_split,
        "seconds": None,
    }
    return mesh


def triangle_quality(x, cells) -> np.ndarray:
    """(m,) shape quality of the straight vertex triangles: 4 sqrt(3) area /
    sum of squared edge lengths, 1 for an equilateral triangle, 0 when
    degenerate (a rosette sector of angle a has ~ sin(a) sqrt(3) / 2 ... 0.33
    at 32 sectors)."""
    v = np.asarray(x)[np.asarray(cells)[:, :3]]
    e = v[:, [1, 2, 0]] - v
    area2 = e[:, 0, 0] * e[:, 2, 1] - e[:, 0, 1] * e[:, 2, 0]
    return 2.0 * math.sqrt(3.0) * np.abs(area2) / np.einsum("mkd,mkd->m", e, e)


def _glue(domain, plan: Plan, half, raw: RawMesh) -> RawMesh:
    """The whole mesh from gmsh's mesh of the left half and its image."""
    tol = 1e-9 * domain.length_scale()
    tip_image = []
    for t in plan.tips:
        if half.left(t.x):
            tip_image.append(-1)
        else:
            image = point_symmetry.rotate(t.x, half.center)
            tip_image.append(int(np.argmin([np.linalg.norm(o.x - image) for o in plan.tips])))
    point_image = [-1 if half.left(plan.anchors[a][2]) else k for k, a in enumerate(plan.point_anchor)]
    return point_symmetry.glue(raw, half, domain, tip_image, point_image, tol)
