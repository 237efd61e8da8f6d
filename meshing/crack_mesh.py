"""Conforming P2 crack meshes: gmsh geometry, tip rosettes, split faces, quarter points.

One call builds the whole mesh of one step (paper sections 3.1-3.3):

1. the outer boundary, split at every bc point and every edge-crack mouth, so
   that each becomes a mesh node;
2. around every crack tip a structured rosette of `sectors` straight triangles
   of radius `tip_size` (one spoke along the crack), the rest unstructured,
   graded from ~`tip_size` at the tips to `size` away from the fractures;
3. second order: gmsh meshes first order, the mid nodes are added here
   (_P2; on the disc rim and the patch circle on the circle);
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
field that is the same as the last call's is not meshed again (_FarCache).

Lengths in metres. Node order in cells is gmsh's [v0, v1, v2, m01, m12, m20],
counter-clockwise. Fracture direction d runs from a polyline's first point to
its last; the + face is on the left of d.
"""

from __future__ import annotations

import contextlib
import dataclasses
import math
import os
import shutil
import tempfile
import time
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from meshing import admissibility, network, point_symmetry
from meshing.domain import Domain
from meshing.records import RawMesh, SplitMesh
from meshing.timeout import MeshTimeout, start_with_timeout

# gmsh and wingcrack_kernels are imported inside the functions that use them:
# `import meshing` (for Domain, in the case checker) must stay light.

# Size growth per element layer away from tips and fractures: h(d) = h0 + GRADING * d
# makes neighbouring layers differ by a factor 1 + GRADING.
GRADING = 0.3
#: the same around the tips (the rosette's surroundings set the SIF accuracy)
TIP_GRADING = 0.3
# Element size along a fracture, in tip sizes (capped by `size`).
CRACK_SIZE_IN_TIPS = 2.0
# Ends of fractures and bc points closer than this (times the domain diameter)
# to the boundary are on it.
ON_BOUNDARY = admissibility.REL_TOL


@dataclass
class TipNodes:
    """The nodes of one crack tip. `upper` is the face on the +y' side of the
    tip frame (the + face at end 1, the - face at end 0); each face gives
    (quarter-point node, corner node) along the spoke on the crack, at
    distances h/4 and h from the tip."""

    fracture: int
    end: int
    node: int
    x: np.ndarray
    ex: np.ndarray
    ey: np.ndarray
    h: float
    upper: tuple[int, int]
    lower: tuple[int, int]


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
    not fit (_patch_circle: off the boundary and the bc points by 2 size,
    every fracture wholly inside or outside and clear of it by
    _patch_clearance) is ignored (stats["patch"] False, far None), as is one
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
    (_Frame): any domain size and offset the rules allow mesh alike.
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
    plan = _plan(domain, fractures, points, tip_size)
    # from here on in gmsh's frame: the checks above spoke in the caller's
    frame = _Frame.of(domain)
    domain, plan = frame.domain(domain), frame.plan(plan)
    size, tip_size = size / frame.scale, tip_size / frame.scale
    if sizes is not None:
        sizes = (frame.to(sizes[0]), np.asarray(sizes[1], dtype=np.float64) / frame.scale)
    circle = None if patch is None else _patch_circle(domain, plan, frame, patch, size, tip_size, sectors, sizes)
    tips, anchors = [(t.x, t.h) for t in plan.tips], [p for _, _, p in plan.anchors]
    half, centre = None, point_symmetry.domain_center(domain)
    if circle is not None and centre is not None and \
            np.linalg.norm(circle.center - centre) <= 1e-9 * domain.length_scale():
        circle = _Circle.of(centre, circle.radius, circle.spacing)
        half = point_symmetry.find_half_patched(domain, plan.fractures, tips, anchors, tip_size, circle.radius,
                                                circle.points)
        if half is not None:
            circle = _Circle.of(centre, circle.radius, circle.spacing, half.k_out)
    if half is None:
        half = point_symmetry.find_half(domain, plan.fractures, tips, anchors, tip_size)
        if half is not None:
            circle = None  # symmetry first: a circle off the centre would break it
    if half is not None:
        plan = _with_divider(domain, plan, half)

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
        return start_with_timeout(_meshed, (_gmsh_session, args, finish), self._timeout)

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
    """(CrackMesh, gmsh's seconds) of session(*args) (_gmsh_session),
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
    import wingcrack_kernels as _kernels

    if half is not None:
        raw = _glue(domain, plan, half, raw)
    t0 = time.perf_counter()
    # the binding answers a dict: its one conversion into the record
    split = SplitMesh(**_kernels.split_faces(raw.x, raw.cells, raw.crack_edges, raw.crack_fracture,
                                             raw.boundary_edges))
    tips = _tip_nodes(plan, raw, split)
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
        "far_reused": bool(raw.far_reused),  # the far field's cells from the last call's (_FarCache)
        # the divider inside the patch circle (symmetric meshes with a patch; its own, see point_symmetry.Inner)
        "inner_divider_angle": None if half is None or half.inner is None else math.degrees(half.inner.angle),
        "seconds_split": t_split,
        "seconds": None,
    }
    return mesh


@dataclass(frozen=True)
class _Frame:
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
    def of(cls, domain: Domain) -> _Frame:
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

    def plan(self, plan: _Plan) -> _Plan:
        if self.scale == 1.0 and not self.origin.any():
            return plan
        return dataclasses.replace(
            plan,
            fractures=[self.to(p) for p in plan.fractures],
            tips=[dataclasses.replace(t, x=self.to(t.x), h=t.h / self.scale) for t in plan.tips],
            anchors=[(edge, param, self.to(p)) for edge, param, p in plan.anchors],
        )


def triangle_quality(x, cells) -> np.ndarray:
    """(m,) shape quality of the straight vertex triangles: 4 sqrt(3) area /
    sum of squared edge lengths, 1 for an equilateral triangle, 0 when
    degenerate (a rosette sector of angle a has ~ sin(a) sqrt(3) / 2 ... 0.33
    at 32 sectors)."""
    v = np.asarray(x)[np.asarray(cells)[:, :3]]
    e = v[:, [1, 2, 0]] - v
    area2 = e[:, 0, 0] * e[:, 2, 1] - e[:, 0, 1] * e[:, 2, 0]
    return 2.0 * math.sqrt(3.0) * np.abs(area2) / np.einsum("mkd,mkd->m", e, e)


# -- 1. the plan: pure geometry, before gmsh -------------------------------------


@dataclass
class _Tip:
    fracture: int
    end: int
    x: np.ndarray  # tip point
    back: np.ndarray  # unit vector from the tip back along the crack
    h: float  # rosette radius


@dataclass
class _Plan:
    fractures: list[np.ndarray]  # mouths projected onto the boundary, junction points inserted
    tips: list[_Tip]
    anchors: list[tuple[int, float, np.ndarray]]  # boundary split points (edge, param, point)
    point_anchor: list[int]  # anchor of each bc point
    mouth_anchor: dict[tuple[int, int], int]  # (fracture, end) -> anchor
    junction: dict[tuple[int, int], tuple[int, int]] = field(default_factory=dict)
    # (fracture, end) -> (host fracture, vertex of the host's polyline) at a T


ROSETTE_IN_SEGMENT = admissibility.ROSETTE_IN_SEGMENT


def _plan(domain: Domain, fractures, points, tip_size: float) -> _Plan:
    tol = ON_BOUNDARY * domain.length_scale()
    anchors: list[tuple[int, float, np.ndarray]] = []

    def anchor(p) -> int:
        q, edge, t = domain.project(p)
        for i, (_, _, a) in enumerate(anchors):
            if np.linalg.norm(a - q) <= tol:
                return i
        anchors.append((edge, t, q))
        return len(anchors) - 1

    polylines, mouth_anchor, free_ends = [], {}, []
    for f, pts in enumerate(fractures):
        pts = np.array(pts, dtype=np.float64)
        if pts.ndim != 2 or pts.shape[1] != 2 or len(pts) < 2 or not np.all(np.isfinite(pts)):
            raise ValueError(f"fracture {f}: points must be finite, (n >= 2, 2)")
        if np.any(np.linalg.norm(np.diff(pts, axis=0), axis=1) <= 1e3 * tol):
            raise ValueError(f"fracture {f}: two consecutive points coincide")
        inner = pts[1:-1]
        if len(inner) and (
            not np.all(domain.contains(inner)) or np.any(domain.distance_to_boundary(inner) <= tol)
        ):
            raise ValueError(f"fracture {f}: inner points must lie inside the domain")
        for end, i in ((0, 0), (1, -1)):
            if domain.distance_to_boundary(pts[i]) <= tol:
                a = anchor(pts[i])
                pts[i] = anchors[a][2]
                mouth_anchor[(f, end)] = a
            elif not domain.contains(pts[i]):
                raise ValueError(f"fracture {f}: end {end} lies outside the domain")
            else:
                free_ends.append((f, end))
        polylines.append(pts)

    joined = network.join(polylines, free_ends, tol, mouths=list(mouth_anchor))
    admissibility.require(admissibility.joins(joined, [len(p) for p in fractures]))
    polylines, junction, met = joined.polylines, joined.junction, joined.met
    tips = []
    for f, end in free_ends:
        if (f, end) in junction or (f, end) in met:
            continue
        pts = polylines[f]
        i, j = (0, 1) if end == 0 else (-1, -2)
        back = pts[j] - pts[i]
        length = float(np.linalg.norm(back))
        tips.append(_Tip(f, end, pts[i].copy(), back / length, admissibility.rosette_radius(tip_size, length)))

    point_anchor = []
    for q, p in enumerate(points):
        p = np.asarray(p, dtype=np.float64).reshape(2)
        if domain.distance_to_boundary(p) > 1e-6 * domain.length_scale():
            raise ValueError(f"bc point {q} at {p.tolist()} is not on the boundary")
        point_anchor.append(anchor(p))

    rosettes = [admissibility.Rosette(t.fracture, t.end, t.x, t.h) for t in tips]
    admissibility.require(admissibility.rosettes(domain, polylines, rosettes, tip_size))
    return _Plan(polylines, tips, anchors, point_anchor, mouth_anchor, junction)


# -- 2. gmsh -----------------------------------------------------------------------


def _gmsh_session(domain, plan, size, tip_size, sectors, sizes, half, mirror_sizes, algorithm,
                  circle=None) -> RawMesh:
    import gmsh

    with _scratch() as scratch:
        gmsh.initialize(readConfigFiles=False)
        try:
            _session_options()
            if circle is not None:
                args = (domain, plan, size, tip_size, sectors, sizes, algorithm, half, mirror_sizes, scratch, circle)
                try:
                    return _mesh_patched(*args)
                except _CacheMiss:  # a fresh session, the far field meshed too
                    gmsh.finalize()
                    gmsh.initialize(readConfigFiles=False)
                    _session_options()
                    return _mesh_patched(*args, reuse=False)
            return _mesh_with_gmsh(domain, plan, size, tip_size, sectors, sizes, algorithm, half, mirror_sizes,
                                   scratch)
        except Exception as error:  # gmsh raises bare Exception
            raise RuntimeError(f"gmsh could not mesh the domain: {error}") from error
        finally:
            gmsh.finalize()


# gmsh's relative precision when it integrates 1 / h along a curve to place the
# curve's nodes. Its default 1e-9 made the 1D pass a third of gmsh's time on the
# paper's 4.4 meshes (the size grid's kinks, every half smallest size, each
# resolved to that precision along every boundary and fracture curve): 2.6 s
# of 7.6 over multi_fractures_shear's 35 meshes; 1e-7: 1.3 s, 1e-6: 0.9 s.
# 1e-7, not 1e-6: at 1e-6 the nodes moved enough that the adaptive open disc
# ended its 34 steps 1.2 % below its DOFs at the default (13,288 against
# 13,448; 1e-7: 13,480) and three_fractures_friction, whose tips stand at
# K_eq = 1.0007 KIc at step 5, took another path; at 1e-7 both as at 1e-9.
LC_INTEGRATION_PRECISION = 1e-7


def _session_options() -> None:
    """The options every session of this module starts with."""
    import gmsh

    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("Mesh.LcIntegrationPrecision", LC_INTEGRATION_PRECISION)


_SCRATCH_PREFIX = "wingcrack-sizes-"
_SCRATCH_STALE = 3600.0


@contextlib.contextmanager
def _scratch():
    """A directory of this session's own for the size grid that gmsh reads
    (every process and session its own, so parallel runs never share one),
    removed when the session ends. A session killed on timeout (the meshing
    worker is SIGKILLed) cannot remove its own: each session first removes
    those of processes that are gone (the pid is in the name) and that are
    older than _SCRATCH_STALE seconds (a process of another pid namespace
    sharing /tmp looks gone; gmsh would silently mesh without the grid if
    its file vanished mid-session)."""
    base = tempfile.gettempdir()
    now = time.time()
    for name in os.listdir(base):
        if not name.startswith(_SCRATCH_PREFIX):
            continue
        pid, path = name[len(_SCRATCH_PREFIX):].split("-", 1)[0], os.path.join(base, name)
        try:
            aged = now - os.stat(path).st_mtime > _SCRATCH_STALE
        except OSError:
            continue
        if aged and pid.isdigit() and not _alive(int(pid)):
            shutil.rmtree(path, ignore_errors=True)
    with tempfile.TemporaryDirectory(prefix=f"{_SCRATCH_PREFIX}{os.getpid()}-") as path:
        yield path


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # another user's process
        return True
    return True


def _mesh_with_gmsh(domain, plan: _Plan, size, tip_size, sectors, sizes, algorithm, half=None,
                    mirror_sizes=False, scratch=None) -> RawMesh:
    """The mesh of the whole domain, or with `half` (a point_symmetry.Half) of
    the half on the left of the divider only; the other half's tips and crack
    curves are then free geometry that only shapes the size field. scratch: a
    directory for the size grid file (needed when `sizes` is given)."""
    import gmsh

    geo = gmsh.model.geo
    gmsh.model.add("wingcrack")
    meshed = (lambda x: True) if half is None else half.left

    anchor_tag, boundary_curves = _outer_curves(geo, domain, plan, half)
    outer = [c for c, _ in boundary_curves]

    # Rosettes: one transfinite triangle per sector, spoke 0 along the crack.
    rosettes, holes = [], []
    tip_point, spoke_on_crack = [None] * len(plan.tips), [None] * len(plan.tips)
    tip_of = {(t.fracture, t.end): k for k, t in enumerate(plan.tips)}
    for k, t in enumerate(plan.tips):   # the other half's tips: a point for the size field only
        loops, hole = _rosette_curves(geo, t, sectors, meshed, tip_point, spoke_on_crack, k)
        rosettes += [(geo.addPlaneSurface([loop]), corners) for loop, corners in loops]
        if hole is not None:
            holes.append(hole)

    # Fracture curves outside the rosettes, in order along each fracture.
    # Vertex tags first (a T-junction end takes its host's vertex), then lines.
    vertex_tags, curves_of = {}, {}
    embedded, elsewhere = _fracture_curves(geo, plan, range(len(plan.fractures)), anchor_tag, tip_of, tip_point,
                                           spoke_on_crack, meshed, vertex_tags, curves_of, {})
    crack_curves = [c for f in range(len(plan.fractures)) for c in curves_of[f]]  # (curve, fracture, d)

    divider: list[int] = []
    if half is not None:  # from R(p) through the crossings and the centre to p
        tags = [_vertex_at(plan, anchor_tag, vertex_tags, geo, q) for q in half.points]
        divider = [geo.addLine(a, b) for a, b in zip(tags[:-1], tags[1:])]
        outer += divider
    surface = geo.addPlaneSurface([geo.addCurveLoop(outer)] + holes)
    for s, corners in rosettes:
        geo.mesh.setTransfiniteSurface(s, "Left", list(corners))
    geo.synchronize()
    if half is not None:
        _mirror_dividers(half, [divider])
    if embedded:
        gmsh.model.mesh.embed(1, embedded, 2, surface)

    _size_field(plan, [centre for centre, _ in tip_point], embedded + elsewhere, size, tip_size, sectors,
                sizes, half.center if mirror_sizes else None, _box(domain), scratch)
    gmsh.option.setNumber("Mesh.Algorithm", algorithm)
    gmsh.model.mesh.generate(2)
    points = [anchor_tag[a] for a in plan.point_anchor]
    if half is not None:  # a bc point of the other half: the node of its image, mapped back by _glue
        points = [tag if half.left(plan.anchors[a][2]) else
                  _anchor_at(plan, anchor_tag, point_symmetry.rotate(plan.anchors[a][2], half.center))
                  for tag, a in zip(points, plan.point_anchor)]
    return _extract(boundary_curves, crack_curves, tip_point, points, divider, rim=_rim(domain, boundary_curves))



# -- the patch: a circle whose outside meshes alike whatever lies inside ----------


@dataclass(frozen=True)
class _Circle:
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
    def of(cls, center, radius: float, spacing: float, k_out: int | None = None) -> _Circle:
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


class _CacheMiss(RuntimeError):
    """A cached far field that does not fit the mesh made around it."""


class _FarCache:
    """The far field this process meshed last (in the meshing worker: across
    calls), so that a call whose far field is the same does not mesh it
    again: its surfaces are hidden from gmsh (Mesh.MeshOnlyVisible; their
    boundary curves are still meshed, alike), and its cells are taken from
    here, glued by their nodes on those curves, which carry the same bits
    (tests/test_meshing_patch.py: the mesh is then bitwise the one that
    meshing it gives). Only the last far field is kept: a propagation
    loop's far field changes seldom and is large."""

    _last: tuple | None = None

    @staticmethod
    def key(domain, plan, inside, circle, half, size, tip_size, sectors, sizes, mirror_sizes, algorithm) -> bytes:
        """A digest of everything the far field's mesh depends on: the domain,
        the anchors, the fractures and tips outside the circle (by their
        place among those outside), the circle, the outer divider, the
        sizes and the size field, the algorithm."""
        import hashlib
        import pickle

        group = [f for f, i in enumerate(inside) if not i]
        where = {f: k for k, f in enumerate(group)}

        def b(a) -> bytes:
            return np.ascontiguousarray(a, dtype=np.float64).tobytes()

        parts = (
            domain.shape, b(domain.center) if domain.shape == "disc" else b(domain.vertices()),
            float(domain.radius) if domain.shape == "disc" else 0.0,
            [(e, float(t), b(p)) for e, t, p in plan.anchors],
            [b(plan.fractures[f]) for f in group],
            sorted((where[f], end, a) for (f, end), a in plan.mouth_anchor.items() if f in where),
            sorted((where[f], end, where.get(g, -1), v) for (f, end), (g, v) in plan.junction.items() if f in where),
            [(where[t.fracture], t.end, b(t.x), b(t.back), float(t.h)) for t in plan.tips if t.fracture in where],
            b(circle.center), float(circle.radius), b(circle.points), b(circle.mids),
            None if half is None else (b(half.center), b(half.u), b(half.points), half.k_out),
            float(size), float(tip_size), int(sectors), bool(mirror_sizes), int(algorithm),
            None if sizes is None else (b(sizes[0]), b(sizes[1])),
        )
        return hashlib.sha256(pickle.dumps(parts)).digest()

    @classmethod
    def get(cls, key):
        return cls._last[1] if cls._last is not None and cls._last[0] == key else None

    @classmethod
    def put(cls, key, cells, interior) -> None:
        cls._last = (key, (np.array(cells, dtype=np.float64), np.array(interior, dtype=bool)))
        cls._nodes = None

    @classmethod
    def clear(cls) -> None:
        cls._last = cls._nodes = None

    @staticmethod
    def merge(cached, far_surfaces, tri, far, tags, xyz, p2):
        """gmsh's cells (tri (m, 6) node tags; none of them far; p2 the _P2
        that numbered their mid nodes) with the cached
        far cells in front: a cached node on the far field's boundary is
        gmsh's node of the same coordinates (same bits), a cached interior
        node a new tag. Raises _CacheMiss when a boundary node has no match."""
        import gmsh

        cells, interior = cached
        if far.any():
            raise _CacheMiss("the far surfaces were meshed")
        inner_first, inner_fresh, boundary, boundary_of = _FarCache._nodes_of(cells, interior)
        on = set()
        for _, tag in gmsh.model.getBoundary([(2, s) for s in far_surfaces], combined=False, oriented=False):
            on.add(abs(tag))
        for s in far_surfaces:  # the fractures outside, embedded in the far surface
            on.update(abs(t) for dim, t in gmsh.model.mesh.getEmbedded(2, s) if dim == 1)
        on_tags = np.unique(np.concatenate([np.zeros(0, np.int64)] + [p2.curve(curve).ravel()
                                                                      for curve in sorted(on)]))
        by_tag = np.argsort(tags)
        known, first = np.unique(_bits(xyz[by_tag[np.searchsorted(tags[by_tag], on_tags)]]), return_index=True)
        known_tag = on_tags[first]
        flat, inner = cells.reshape(-1, 2), interior.ravel()
        out = np.empty(len(flat), dtype=np.int64)
        j = np.minimum(np.searchsorted(known, boundary), max(len(known) - 1, 0))
        if len(boundary) and (not len(known) or np.any(known[j] != boundary)):
            raise _CacheMiss("a node of the far field's boundary is not in the mesh")
        out[~inner] = known_tag[j][boundary_of]
        top = int(tags.max()) + 1 if len(tags) else 1
        out[inner] = top + inner_fresh
        tri = np.concatenate([out.reshape(-1, 6), tri])
        far = np.concatenate([np.ones(len(cells), dtype=bool), far])
        tags = np.concatenate([tags, np.arange(top, top + len(inner_first), dtype=np.int64)])
        xyz = np.concatenate([xyz, flat[inner][inner_first]])
        return tri, far, tags, xyz

    _nodes = None   # (cells, interior, their _nodes_of): the last cached far field's

    @classmethod
    def _nodes_of(cls, cells, interior):
        """The node structure of a cached far field (cells (m, 6, 2) places,
        interior (m, 6) its nodes off the boundary), the same in every call
        it is glued in, so worked out once: (first, fresh) of its interior
        nodes (np.unique of their places' bits: the first occurrence of each,
        the index of each occurrence's node), (boundary, of) of its boundary
        nodes (their places' bits sorted unique, and the index in those of
        each occurrence)."""
        last = cls._nodes
        if last is not None and last[0] is cells and last[1] is interior:
            return last[2]
        flat, inner = cells.reshape(-1, 2), interior.ravel()
        _, first, fresh = np.unique(_bits(flat[inner]), return_index=True, return_inverse=True)
        boundary, of = np.unique(_bits(flat[~inner]), return_inverse=True)
        out = (first, fresh.ravel(), boundary, of.ravel())
        cls._nodes = (cells, interior, out)
        return out


def _table(keys: np.ndarray, values: np.ndarray) -> np.ndarray:
    """A dense lookup table of distinct non-negative int keys: table[k] is
    the value of key k, -1 where k is no key."""
    keys = np.asarray(keys, dtype=np.int64)
    table = np.full(int(keys.max()) + 1 if len(keys) else 0, -1, dtype=np.int64)
    table[keys] = values
    return table


def _bits(a) -> np.ndarray:
    """(n, 2) float64 rows as (n,) keys that compare and sort by their bits."""
    return np.ascontiguousarray(a, dtype=np.float64).view(np.dtype((np.void, 16))).ravel()


def _patch_clearance(size: float, tip_size: float, tip_h: float | None = None, sectors: int = 16) -> float:
    """The least distance between the patch circle and a fracture (tip_h None)
    or a tip with rosette radius tip_h. The size field (_size_field) is a min
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
    crowded by the refinement (tests/test_meshing_patch.py measures the far
    field's identity with it)."""
    if tip_h is None:
        return 2.0 * size + (size - tip_size) / GRADING
    return 2.0 * size + tip_h + (size - 2.0 * tip_h * math.sin(math.pi / sectors)) / TIP_GRADING


#: the smallest rosette radius of a tip, in tip sizes (a wing's: min(tip_size,
#: 0.75 L) with L >= 0.4 tip_size, wingcrack.case's Propagation.length)
SMALLEST_ROSETTE = 0.3


def patch_clearance(size: float, tip_size: float, sectors: int) -> float:
    """The room a caller leaves between a patch circle and any fracture or
    tip for the mesher to use the patch: _patch_clearance's largest over
    fractures and over tips of any rosette radius from SMALLEST_ROSETTE
    tip sizes to tip_size (the tip's bound is linear in the radius, so the
    ends bound it)."""
    return max(_patch_clearance(size, tip_size),
               *(_patch_clearance(size, tip_size, h, sectors) for h in (SMALLEST_ROSETTE * tip_size, tip_size)))


def patch_boundary_clearance(size: float) -> float:
    """The room between a patch circle and the outer boundary (and every bc
    point) that the mesher asks."""
    return 2.0 * size


def _patch_circle(domain, plan: _Plan, frame, patch, size, tip_size, sectors, sizes=None) -> _Circle | None:
    """The patch (center, radius; the caller's frame) in gmsh's frame, or None
    when it does not fit: the circle within the domain and 2 size off its
    boundary and off every anchor (bc points, crack mouths), every fracture
    wholly inside or wholly outside it and _patch_clearance away from it,
    every tip likewise. Never an error: a patch that does not fit only
    costs the caller the reuse. Its nodes are `size` apart, or as far apart
    as the smallest of the size field `sizes` (gmsh's frame) on the
    triangles that meet the circle asks, and then the size field grades the
    cells from that spacing on the circle (_size_field): where the field
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
    if not domain.contains(c) or domain.distance_to_boundary(c) < r + patch_boundary_clearance(size):
        return None
    if any(np.linalg.norm(a - c) < r + patch_boundary_clearance(size) for _, _, a in plan.anchors):
        return None
    clear = _patch_clearance(size, tip_size)
    for pts in plan.fractures:
        if np.linalg.norm(pts - c, axis=1).max() <= r - clear:
            continue  # inside
        a, ab = pts[:-1], np.diff(pts, axis=0)
        t = np.clip(np.einsum("ij,ij->i", c - a, ab) / np.einsum("ij,ij->i", ab, ab), 0.0, 1.0)
        if np.linalg.norm(a + t[:, None] * ab - c, axis=1).min() >= r + clear:
            continue  # outside
        return None
    for t in plan.tips:
        if abs(np.linalg.norm(t.x - c) - r) < _patch_clearance(size, tip_size, t.h, sectors):
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
    return _Circle.of(c, r, spacing)


def _mesh_patched(domain, plan: _Plan, size, tip_size, sectors, sizes, algorithm, half, mirror_sizes, scratch,
                  circle: _Circle, reuse: bool = True) -> RawMesh:
    """_mesh_with_gmsh with a patch circle: the far field (outside the circle:
    the outer boundary, the fractures and tips there, the divider outside)
    is built first, so that its entities have the lowest tags and its
    surface is meshed first (gmsh meshes surfaces in tag order; meshed
    after the inside, the far surface of one of the identity tests came
    out otherwise, the inside's meshing changing the state gmsh starts
    the next surface from; meshed first, none did); then the inside. With `half`: the far half on the left of the outer divider, the
    patch half on the left of the inner one (point_symmetry.Inner).
    When the far field is the one this process meshed last (_FarCache), its
    surfaces are not meshed (reuse False: meshed in any case)."""
    import gmsh

    geo = gmsh.model.geo
    gmsh.model.add("wingcrack")
    meshed = (lambda x: True) if half is None else half.left
    c, r, n = circle.center, circle.radius, len(circle.points)
    inside = [bool(np.linalg.norm(p[0] - c) < r) for p in plan.fractures]
    key = _FarCache.key(domain, plan, inside, circle, half, size, tip_size, sectors, sizes, mirror_sizes, algorithm)
    cached = _FarCache.get(key) if reuse else None

    anchor_tag, boundary_curves = _outer_curves(geo, domain, plan, half)
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
            sector_loops, hole = _rosette_curves(geo, plan.tips[k], sectors, meshed, tip_point, spoke, k)
            sectors_of += sector_loops
            if hole is not None:
                holes.append(hole)
        embedded, elsewhere = _fracture_curves(geo, plan, group, anchor_tag, tip_of, tip_point, spoke, meshed,
                                               vertex_tags, curves_of, shared)
        if far_side:
            divider, loop = [], [cv for cv, _ in boundary_curves]
            if half is not None:  # R(p) .. R(q) | q .. p: the part between R(q) and q is inside
                k_out, m = half.k_out, len(half.points) // 2
                ends = {m - 1: node[(k_out + n // 2) % n], m: node[k_out]}
                tags = [ends.get(i) or _vertex_at(plan, anchor_tag, vertex_tags, geo, q)
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
                tags = [ends.get(i) or _vertex_at(plan, anchor_tag, vertex_tags, geo, q) for i, q in enumerate(pts)]
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
        _mirror_dividers(half, [divider for _, _, divider, _, _, _ in sides])
    for surface, _, _, embedded, _, _ in sides:
        if embedded:
            gmsh.model.mesh.embed(1, embedded, 2, surface)

    groups = [(embedded + elsewhere, [plan.fractures[f] for f in group])
              for _, _, _, embedded, elsewhere, group in sides]
    _size_field(plan, [centre for centre, _ in tip_point], [], size, tip_size, sectors,
                sizes, half.center if mirror_sizes else None, _box(domain), scratch, crack_groups=groups,
                circle=(arcs, circle.spacing))
    gmsh.option.setNumber("Mesh.Algorithm", algorithm)
    far_surfaces = [sides[0][0]] + [s for s, _ in sides[0][1]]
    if cached is not None:  # the far surfaces' boundaries are meshed (visible), the surfaces not
        gmsh.model.setVisibility([(2, s) for s in far_surfaces], 0, recursive=False)
        gmsh.option.setNumber("Mesh.MeshOnlyVisible", 1)
    gmsh.model.mesh.generate(2)

    points = [anchor_tag[a] for a in plan.point_anchor]
    used_arcs = list(range(n))
    mirrored_arcs: list[int] = []
    if half is not None:
        points = [tag if half.left(plan.anchors[a][2]) else
                  _anchor_at(plan, anchor_tag, point_symmetry.rotate(plan.anchors[a][2], half.center))
                  for tag, a in zip(points, plan.point_anchor)]
        far_arcs = {(half.k_out + j) % n for j in range(n // 2)}
        patch_arcs = {(half.inner.k + j) % n for j in range(n // 2)}
        used_arcs = sorted(far_arcs | patch_arcs)
        # an arc in one half's boundary only: its image is the other's (glue mirrors their nodes)
        mirrored_arcs = [arcs[j] for j in sorted(far_arcs ^ patch_arcs)]
    crack_curves = [cv for f in range(len(plan.fractures)) for cv in curves_of[f]]
    (_, _, far_divider, _, _, _), (_, _, inner_divider, _, _, _) = sides
    info: dict = {}
    raw = _extract(boundary_curves, crack_curves, tip_point, points, far_divider + inner_divider + mirrored_arcs,
                   far_surfaces=far_surfaces, mids={arcs[j]: circle.mids[j] for j in used_arcs},
                   far_cells=cached, info=None if cached is not None else info, rim=_rim(domain, boundary_curves))
    if cached is None:
        _FarCache.put(key, raw.x[raw.cells[raw.far]], info["far_interior"])
    return raw


def _rosette_curves(geo, t, sectors, meshed, tip_point, spoke, k):
    """The points and curves of tip t's rosette (as _mesh_with_gmsh builds
    them) and its sectors' loops [(loop, corners)], the surfaces left to the
    caller; fills tip_point[k], spoke[k]. Returns (loops, hole loop), the
    hole None (and no loops) for a tip not meshed here."""
    centre = geo.addPoint(t.x[0], t.x[1], 0.0)
    if not meshed(t.x):
        tip_point[k] = (centre, None)
        return [], None
    phi0 = math.atan2(t.back[1], t.back[0])
    ring_pts = []
    for j in range(sectors):
        phi = phi0 + 2.0 * math.pi * j / sectors
        p = t.x + t.h * (t.back if j == 0 else np.array([math.cos(phi), math.sin(phi)]))
        ring_pts.append(geo.addPoint(p[0], p[1], 0.0))
    spokes = [geo.addLine(centre, q) for q in ring_pts]
    chords = [geo.addLine(ring_pts[j], ring_pts[(j + 1) % sectors]) for j in range(sectors)]
    loops = [(geo.addCurveLoop([spokes[j], chords[j], -spokes[(j + 1) % sectors]]),
              (centre, ring_pts[j], ring_pts[(j + 1) % sectors])) for j in range(sectors)]
    for cv in spokes + chords:
        geo.mesh.setTransfiniteCurve(cv, 2)
    tip_point[k] = (centre, ring_pts[0])
    spoke[k] = spokes[0]
    return loops, geo.addCurveLoop(chords)


def _fracture_curves(geo, plan, group, anchor_tag, tip_of, tip_point, spoke, meshed, vertex_tags, curves_of,
                     shared):
    """The crack curves of the fractures in `group` (as _mesh_with_gmsh builds
    them): fills vertex_tags[f] and curves_of[f] ([(curve, f, d)] in order
    along f, the rosettes' spokes on the crack included), and shared (the
    bits of a vertex's coordinates -> its point tag: vertices of several
    fractures at one place are one point); returns (curves to embed, the
    other half's curves)."""
    for f in group:
        pts = plan.fractures[f]
        tags = [0] * len(pts)
        for end, i in ((0, 0), (1, len(pts) - 1)):
            if (f, end) in plan.mouth_anchor:
                tags[i] = anchor_tag[plan.mouth_anchor[(f, end)]]
            elif (f, end) in tip_of and spoke[tip_of[(f, end)]] is not None:
                tags[i] = tip_point[tip_of[(f, end)]][1]
        joined = {0 if end == 0 else len(pts) - 1 for (g, end) in plan.junction if g == f}
        for i in range(len(pts)):
            if not tags[i] and i not in joined:
                # one point where vertices of several fractures coincide (an X: network.join
                # gave them the same bits)
                key = pts[i].tobytes()
                if key not in shared:
                    shared[key] = geo.addPoint(pts[i][0], pts[i][1], 0.0)
                tags[i] = shared[key]
        vertex_tags[f] = tags
    for (f, end), (g, vertex) in plan.junction.items():
        if f in group:  # a junction joins fractures of one side (they touch)
            vertex_tags[f][0 if end == 0 else -1] = vertex_tags[g][vertex]
    embedded, elsewhere = [], []
    for f in group:
        pts, tags, own = plan.fractures[f], vertex_tags[f], []
        if (f, 0) in tip_of and spoke[tip_of[(f, 0)]] is not None:
            own.append((spoke[tip_of[(f, 0)]], f, pts[1] - pts[0]))
        for s in range(len(pts) - 1):
            line = geo.addLine(tags[s], tags[s + 1])
            if meshed(0.5 * (pts[s] + pts[s + 1])):
                own.append((line, f, pts[s + 1] - pts[s]))
                embedded.append(line)
            else:
                elsewhere.append(line)
        if (f, 1) in tip_of and spoke[tip_of[(f, 1)]] is not None:
            own.append((spoke[tip_of[(f, 1)]], f, pts[-1] - pts[-2]))
        curves_of[f] = own
    return embedded, elsewhere


def _vertex_at(plan, anchor_tag, vertex_tags, geo, q) -> int:
    """The point tag at divider vertex q: an anchor (its ends), a fracture
    vertex built so far (vertex_tags: f -> tags; a crossing, inserted with
    q's coordinates), or a new point (the centre off every fracture)."""
    for k, (_, _, a) in enumerate(plan.anchors):
        if np.array_equal(a, q):
            return anchor_tag[k]
    for f, tags in vertex_tags.items():
        hit = np.flatnonzero(np.all(plan.fractures[f] == q, axis=1))
        if len(hit):
            return tags[int(hit[0])]
    return geo.addPoint(q[0], q[1], 0.0)


def _mirror_dividers(half, dividers) -> None:
    """Each divider's second half mirrors its first, node for node (gmsh
    periodic curves under the half turn about the centre)."""
    import gmsh

    cx, cy = half.center
    turn = [-1.0, 0.0, 0.0, 2.0 * cx, 0.0, -1.0, 0.0, 2.0 * cy, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0]
    for divider in dividers:
        for k in range(len(divider) // 2):
            gmsh.model.mesh.setPeriodic(1, [divider[len(divider) - 1 - k]], [divider[k]], turn)


def _outer_curves(geo, domain, plan: _Plan, half) -> tuple[list[int], list[tuple[int, str]]]:
    """The outer boundary in gmsh: the anchors' point tags and the boundary
    curves [(curve, name)] counter-clockwise, all of them, or with `half`
    those from the divider's end p to its other end R(p)."""
    anchor_tag = [geo.addPoint(p[0], p[1], 0.0) for _, _, p in plan.anchors]
    ring = _boundary_ring(domain, plan, geo, anchor_tag)  # [(point tag, name of the curve after it)]
    center = geo.addPoint(*domain.center, 0.0) if domain.shape == "disc" else None
    if half is None:
        pieces = list(zip(ring, ring[1:] + ring[:1]))
    else:
        tags = [tag for tag, _ in ring]
        start = tags.index(_anchor_at(plan, anchor_tag, half.points[-1]))
        stop = tags.index(_anchor_at(plan, anchor_tag, half.points[0]))
        arc = ring[start:] + ring[:start]
        arc = arc[: (stop - start) % len(ring) + 1]
        pieces = list(zip(arc[:-1], arc[1:]))
    boundary_curves = []
    for (a, name), (b, _) in pieces:
        curve = geo.addCircleArc(a, center, b) if center is not None else geo.addLine(a, b)
        boundary_curves.append((curve, name))
    return anchor_tag, boundary_curves


def _boundary_ring(domain, plan, geo, anchor_tag) -> list[tuple[int, str]]:
    """The outer boundary's points counter-clockwise, each with the name of the
    boundary curve that starts at it (a disc's arcs are filled to <= pi/2)."""
    if domain.shape == "disc":
        angles = [(t, tag) for (_, t, _), tag in zip(plan.anchors, anchor_tag)]
        return [(tag, "rim") for _, tag in _fill_arc_gaps(sorted(angles), domain, geo)]
    corners, names = domain.vertices(), domain.edge_names()
    tol = ON_BOUNDARY * domain.length_scale()
    ring = []
    for i, corner in enumerate(corners):
        on_corner = [k for k, (_, _, p) in enumerate(plan.anchors) if np.linalg.norm(p - corner) <= tol]
        ring.append((anchor_tag[on_corner[0]] if on_corner else geo.addPoint(*corner, 0.0), names[i]))
        inner = sorted(
            (t, anchor_tag[k])
            for k, (e, t, p) in enumerate(plan.anchors)
            if e == i and k not in on_corner and np.linalg.norm(p - corners[(i + 1) % len(corners)]) > tol
        )
        ring.extend((tag, names[i]) for _, tag in inner)
    return ring


def _anchor_at(plan, anchor_tag, p) -> int:
    k = int(np.argmin([np.linalg.norm(a - p) for _, _, a in plan.anchors]))
    return anchor_tag[k]


def _with_divider(domain, plan: _Plan, half) -> _Plan:
    """The plan of a point-symmetric geometry: the divider's crossings become
    fracture vertices, its ends and every anchor's image become anchors."""
    tol = ON_BOUNDARY * domain.length_scale()
    fractures, junction = point_symmetry.insert_divider(plan.fractures, plan.junction, half, tol)
    anchors = list(plan.anchors)

    def add(p) -> np.ndarray:
        for _, _, a in anchors:
            if np.linalg.norm(a - p) <= tol:
                return a
        q, edge, t = domain.project(p)
        anchors.append((edge, t, q))
        return q

    for _, _, a in plan.anchors:
        add(point_symmetry.rotate(a, half.center))
    half.points[0], half.points[-1] = add(half.points[0]), add(half.points[-1])
    return dataclasses.replace(plan, fractures=fractures, junction=junction, anchors=anchors)


def _glue(domain, plan: _Plan, half, raw: RawMesh) -> RawMesh:
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


def _fill_arc_gaps(angles, domain, geo):
    """Circle arcs must be shorter than pi: add rim points so that no arc spans
    more than pi/2. angles: sorted [(angle, point tag)]; returns the same, filled."""
    if not angles:
        angles = [(-math.pi, _rim_point(-math.pi, domain, geo))]
    out = []
    for i, (t, tag) in enumerate(angles):
        out.append((t, tag))
        t_next = angles[(i + 1) % len(angles)][0] + (2.0 * math.pi if i == len(angles) - 1 else 0.0)
        n = max(1, math.ceil((t_next - t) / (0.5 * math.pi) - 1e-9))
        out.extend((s, _rim_point(s, domain, geo)) for s in (t + (t_next - t) * j / n for j in range(1, n)))
    return out


def _rim_point(angle, domain, geo) -> int:
    p = domain.center + domain.radius * np.array([math.cos(angle), math.sin(angle)])
    return geo.addPoint(p[0], p[1], 0.0)


def _size_field(plan: _Plan, tip_points, crack_curves, size, tip_size, sectors, sizes=None, center=None,
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
    import gmsh

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
# read without changing the meshes (the open disc's: the same cell counts to
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
    import gmsh
    import wingcrack_kernels as _kernels

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


def _box(domain: Domain) -> tuple[np.ndarray, np.ndarray]:
    """The domain's bounding box (lo, hi)."""
    if domain.shape == "disc":
        return domain.center - domain.radius, domain.center + domain.radius
    v = domain.vertices()
    return v.min(axis=0), v.max(axis=0)


def _threshold(distance_field, h0, size, d0, grading=GRADING):
    import gmsh

    field = gmsh.model.mesh.field
    t = field.add("Threshold")
    field.setNumber(t, "InField", distance_field)
    field.setNumber(t, "SizeMin", h0)
    field.setNumber(t, "SizeMax", size)
    field.setNumber(t, "DistMin", d0)
    field.setNumber(t, "DistMax", d0 + (size - h0) / grading)
    return t


# -- 3. read the mesh back ---------------------------------------------------------


def _rim(domain, boundary_curves):
    """(center, radius, curves): the outer boundary's circle arcs (a disc's
    rim), whose mid nodes lie on the circle; None for straight boundaries."""
    if domain.shape != "disc":
        return None
    return np.asarray(domain.center, dtype=np.float64), float(domain.radius), [c for c, _ in boundary_curves]


class _P2:
    """gmsh's first-order mesh made second order: a mid node on every edge
    of a triangle or of a curve's line element, at 0.5 (a + b), on a circle
    arc (rim) at the circle's point on the edge's bisector (the arc's
    middle, which gmsh's setOrder(2) finds by a Newton solve to a relative
    1e-6 only: tests/test_mid_nodes.py), on a one-edge curve of `mids` at
    the given point. Built here, not by setOrder(2), for its cost: a
    sizeable part of gmsh's time on meshes of many fractures. A mid node
    is a function of its edge's vertex coordinates only (0.5 (a + b) is the
    same bits either way round), so that a far field meshed alike gets the
    same bits in every call (_FarCache) and a divider's mids mirror as its
    vertices do (glue). Mid tags follow gmsh's largest tag, in the order
    the line elements, then the triangles' edges 01, 12, 20 meet them.

    tags (n,), xyz (n, 2): the vertices then the mids; tri (m, 6): the cells."""

    def __init__(self, tri3, lines, tags, xyz, rim=None, mids=None):
        mesh = _gmsh_mesh()
        top = int(tags.max()) + 1 if len(tags) else 1
        pos = np.zeros(top, dtype=np.int64)
        pos[tags] = np.arange(len(tags))
        pairs = np.concatenate([lines, tri3[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)])
        lo, hi = pairs.min(axis=1), pairs.max(axis=1)
        key = lo * top + hi
        uniq, first, inverse = np.unique(key, return_index=True, return_inverse=True)
        seen = np.argsort(first, kind="stable")
        rank = np.empty(len(uniq), dtype=np.int64)
        rank[seen] = np.arange(len(uniq))
        a, b = xyz[pos[lo[first]]], xyz[pos[hi[first]]]
        mid = 0.5 * (a + b)
        self._top, self._key, self._mid_tag = top, uniq, top + rank
        if rim is not None:
            center, radius, curves = rim
            e = self._edge(np.concatenate([np.zeros((0, 2), np.int64)] + [self._lines(mesh, c) for c in curves]))
            d = mid[e] - center
            mid[e] = center + radius * d / np.linalg.norm(d, axis=1)[:, None]
        for curve, at in (mids or {}).items():
            mid[self._edge(self._lines(mesh, curve))] = at
        self.on_line = np.zeros(len(uniq), dtype=bool)
        self.on_line[inverse[: len(lines)]] = True
        self.tags = np.concatenate([tags, top + np.arange(len(uniq), dtype=np.int64)])
        self.xyz = np.concatenate([xyz, mid[seen]])
        m = len(tri3)
        self.tri = np.concatenate([tri3, self._mid_tag[inverse[len(lines):]].reshape(m, 3)], axis=1)

    @staticmethod
    def _lines(mesh, curve) -> np.ndarray:
        return np.asarray(mesh.getElementsByType(1, abs(curve))[1], dtype=np.int64).reshape(-1, 2)

    def _edge(self, pairs) -> np.ndarray:
        return np.searchsorted(self._key, pairs.min(axis=1) * self._top + pairs.max(axis=1))

    def curve(self, curve) -> np.ndarray:
        """(k, 3) [a, b, mid] tags of the curve's line elements, in gmsh's order."""
        pairs = self._lines(_gmsh_mesh(), curve)
        return np.concatenate([pairs, self._mid_tag[self._edge(pairs)][:, None]], axis=1)

    def interior_mids(self) -> np.ndarray:
        """The mid tags of the edges on no curve (inside a surface)."""
        return self._mid_tag[~self.on_line]


def _gmsh_mesh():
    import gmsh

    return gmsh.model.mesh


def _extract(boundary_curves, crack_curves, tip_point, point_tags, divider=(), far_surfaces=None,
             mids=None, far_cells=None, info=None, rim=None) -> RawMesh:
    """The mesh gmsh made (first order; _P2 adds the mid nodes). tip_point:
    (centre, corner) point tags of each tip,
    corner None for a tip not meshed here (its nodes are -1); point_tags: of
    each bc point, None likewise; divider: curves whose nodes are returned as
    divider_nodes; far_surfaces: the surfaces whose cells are RawMesh.far
    (None: far None; else the far cells come first and the nodes are
    numbered in the order the cells meet them, not in gmsh's tag order);
    mids: {curve: (2,)} the mid node of one-edge curves placed there;
    far_cells: a far field meshed before (_FarCache), its surfaces not
    meshed now; info: a dict, given "far_interior" (as _FarCache keeps it);
    rim: (center, radius, curves) curves on that circle (_rim)."""
    mesh = _gmsh_mesh()
    element_tags, tri = mesh.getElementsByType(2)  # 3-node triangles
    tri = np.asarray(tri, dtype=np.int64).reshape(-1, 3)
    tags, coords, _ = mesh.getNodes(returnParametricCoord=False)
    tags = np.asarray(tags, dtype=np.int64)
    xyz = np.asarray(coords, dtype=np.float64).reshape(-1, 3)[:, :2]
    lines = np.asarray(mesh.getElementsByType(1)[1], dtype=np.int64).reshape(-1, 2)
    p2 = _P2(tri, lines, tags, xyz, rim, mids)
    tri, tags, xyz = p2.tri, p2.tags, p2.xyz
    if far_surfaces is None:
        used, cells = np.unique(tri, return_inverse=True)  # drop unused nodes, compact 0-based
        cells = cells.reshape(-1, 6).astype(np.int64)
        order = np.argsort(tags)
        x = xyz[order][np.searchsorted(tags[order], used)].copy()

        def index(node_tags) -> np.ndarray:
            return np.searchsorted(used, np.asarray(node_tags, dtype=np.int64))
        far = None
    else:
        far_tags = np.concatenate([np.asarray(mesh.getElementsByType(2, s)[0], dtype=np.int64)
                                   for s in far_surfaces])
        far = np.isin(np.asarray(element_tags, dtype=np.int64), far_tags)
        if far_cells is not None:
            tri, far, tags, xyz = _FarCache.merge(far_cells, far_surfaces, tri, far, tags, xyz, p2)
        at = _table(tags, np.arange(len(tags)))   # position in xyz by tag
        tri = _canonical_cells(tri, xyz[at[tri[:, :3]]])
        # far cells first (stable), nodes numbered as the cells meet them: the far field's
        # numbering is then the same in every call that meshes it alike, whatever gmsh's tags
        order = np.argsort(~far, kind="stable")
        tri, far = tri[order], far[order]
        flat = tri.ravel()
        uniq, first = np.unique(flat, return_index=True)
        rank = np.empty(len(uniq), dtype=np.int64)
        rank[np.argsort(first)] = np.arange(len(uniq))
        x = xyz[at[flat[np.sort(first)]]].copy()
        rank_of = _table(uniq, rank)

        def index(node_tags) -> np.ndarray:
            return rank_of[np.asarray(node_tags, dtype=np.int64)]
        cells = index(tri)
        if info is not None:
            interior = np.concatenate([np.asarray(mesh.getNodes(2, s, includeBoundary=False)[0], dtype=np.int64)
                                       for s in far_surfaces] + [p2.interior_mids()])
            info["far_interior"] = np.isin(tri[far], interior)

    def curve_edges(curve) -> np.ndarray:
        return index(p2.curve(curve))

    # Counter-clockwise cells: swap v1 <-> v2 and m01 <-> m20 where the area is negative.
    v = x[cells[:, :3]]
    area2 = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
    cells[area2 < 0] = cells[area2 < 0][:, [0, 2, 1, 5, 4, 3]]

    b_edges, b_names = [], []
    for c, name in boundary_curves:
        e = curve_edges(c)
        b_edges.append(e)
        b_names += [name] * len(e)

    c_edges, c_frac = [], []
    for c, f, d in crack_curves:
        e = curve_edges(c)
        backwards = np.einsum("ij,j->i", x[e[:, 1]] - x[e[:, 0]], d) < 0
        e[backwards] = e[backwards][:, [1, 0, 2]]
        e = e[np.argsort(x[e[:, 2]] @ d)]  # in order along d
        c_edges.append(e)
        c_frac += [f] * len(e)

    def point_node(tag) -> int:
        if tag is None:
            return -1
        return int(index(mesh.getNodes(0, tag, returnParametricCoord=False)[0])[0])

    on_divider = [curve_edges(c).ravel() for c in divider]
    return RawMesh(
        x=x,
        cells=cells,
        boundary_edges=np.concatenate(b_edges).astype(np.int64),
        boundary_name=tuple(b_names),
        crack_edges=np.concatenate(c_edges).astype(np.int64) if c_edges else np.zeros((0, 3), np.int64),
        crack_fracture=np.array(c_frac, dtype=np.int64),
        tip_node=np.array([point_node(centre if r0 is not None else None) for centre, r0 in tip_point],
                          dtype=np.int64),
        tip_corner=np.array([point_node(r0) for _, r0 in tip_point], dtype=np.int64),
        point_nodes=np.array([point_node(tag) for tag in point_tags], dtype=np.int64),
        divider_nodes=np.unique(np.concatenate(on_divider)) if on_divider else np.zeros(0, np.int64),
        far=far,
        far_reused=far_cells is not None,
    )


def _canonical_cells(tri, v) -> np.ndarray:
    """P2 cells (m, 6) counter-clockwise and each starting at its lowest
    vertex (by x, then y; v (m, 3, 2) the vertices): which vertex gmsh puts
    first follows its node tags, which differ between a mesh made whole and
    one made with the far field reused (_FarCache)."""
    area2 = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
    flip = area2 < 0
    tri, v = tri.copy(), v.copy()
    tri[flip] = tri[flip][:, [0, 2, 1, 5, 4, 3]]
    v[flip] = v[flip][:, [0, 2, 1]]
    k = np.zeros(len(tri), dtype=np.int64)
    for j in (1, 2):
        a, b = v[np.arange(len(v)), k], v[:, j]
        k = np.where((b[:, 0] < a[:, 0]) | ((b[:, 0] == a[:, 0]) & (b[:, 1] < a[:, 1])), j, k)
    turn = np.array([[0, 1, 2, 3, 4, 5], [1, 2, 0, 4, 5, 3], [2, 0, 1, 5, 3, 4]])
    return np.take_along_axis(tri, turn[k], axis=1)


# -- 4. tips after the split -----------------------------------------------------


def _tip_nodes(plan: _Plan, raw: RawMesh, split: SplitMesh) -> list[TipNodes]:
    out = []
    orig = raw.crack_edges
    for t, tip, corner in zip(plan.tips, raw.tip_node.tolist(), raw.tip_corner.tolist()):
        # the spoke on the crack: the crack edge joining the tip and its corner node
        ends = np.sort(orig[:, :2], axis=1)
        k = int(np.flatnonzero(np.all(ends == sorted((tip, corner)), axis=1))[0])
        plus, minus = (_quarter_and_corner(edges[k], tip) for edges in (split.crack_edges, split.crack_edges_minus))
        ex = -t.back
        out.append(
            TipNodes(
                fracture=t.fracture,
                end=t.end,
                node=int(tip),
                x=split.x[tip].copy(),
                ex=ex,
                ey=np.array([-ex[1], ex[0]]),
                h=float(np.linalg.norm(split.x[plus[1]] - split.x[tip])),
                upper=plus if t.end == 1 else minus,
                lower=minus if t.end == 1 else plus,
            )
        )
    return out


def _quarter_and_corner(edge, tip) -> tuple[int, int]:
    a, b, mid = (int(v) for v in edge)
    return mid, (a if b == tip else b)
