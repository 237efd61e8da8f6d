"""The case: what one case file describes, read and checked.

The contract is /work/shared/spec/case-format.md. `Case.from_toml(path)` reads a
file, `Case.from_dict(d)` a parsed table; both return a `Case` whose every part
has been checked, or raise `CaseError(key, reason)` naming the first offending
key by its full path (``mesh.tip_size``, ``fractures[1].points[0]``, ``bc[2].at``).

Units are SI throughout (m, Pa, N; a point force is N per metre of thickness).
Points are (x, y) float64. Load scaling: every bc force, traction and
displacement and every prescribed fracture slip is multiplied by the load
factor (`Case.at_load`); the initial stress and gravity are not.
"""
from __future__ import annotations

import difflib
import math
import tomllib
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from meshing.domain import Domain  # pure numpy: `check` needs neither gmsh nor DOLFINx
from wingcrack import _kernels  # geometry predicates (C++)
from wingcrack.errors import CaseError
from wingcrack.propagation.growth_law import length_problem   # the Lmax rule lives with the growth law

PLANES = ("stress", "strain")
SHAPES = ("disc", "rectangle", "polygon")
FACES = ("open", "frictionless", "slip")
SLIP_PROFILES = ("uniform", "elliptic")
LOADS = ("scale", "fixed")
SIF_METHODS = ("correlation", "interaction")   # propagation.sif: which SIFs drive growth
#: Relative tolerance (times the domain length scale) for "on the boundary",
#: "touching" and "zero length".
REL_TOL = 1e-9
#: Sample points per named boundary for the rigid-body check.
_SAMPLES = 8
#: A case file is a page of text; anything larger is refused before parsing
#: (a 10 MB list of points would otherwise take minutes in the O(n^2) checks).
MAX_FILE_BYTES = 1 << 20
#: The domain size (m) the mesher and solver are verified for: a plate of
#: 1e-9 m and of 1e9 m give the same scaled SIFs; at 1e20 m gmsh aborts and
#: at 1e30 m it hangs.
LENGTH_RANGE = (1e-9, 1e9)
#: Coordinates at most this many domain sizes from the origin: beyond it the
#: rounding of a coordinate (|x| 2.2e-16) nears the geometric tolerance REL_TOL.
MAX_OFFSET = 1e6
#: mesh.tip_size at least this fraction of the domain size: a smaller rosette
#: lies within 1000 geometric tolerances of its tip.
MIN_TIP_FRACTION = 1e3 * REL_TOL
#: The most triangles mesh.size may ask for (area / (sqrt(3)/4 size^2)):
#: about 16 million P2 DOFs, beyond what the 2-core, 24 GB machines factorise.
MAX_ELEMENTS = 4_000_000
#: The most triangles in one tip rosette (one degree each).
MAX_SECTORS = 360
#: The most fractures, points per polyline and boundary conditions: the
#: pairwise checks are quadratic in these.
MAX_ITEMS = 1000


# ---------------------------------------------------------------- data model


@dataclass(frozen=True)
class Material:
    """Linear elastic isotropic material.

    E: Young's modulus (Pa), > 0. nu: Poisson's ratio, in (-1, 0.5).
    KIc: fracture toughness (Pa m^0.5), > 0. plane: "stress" (default, as the
    contract example) or "strain". thickness: out-of-plane thickness (m),
    default 1.0. density: kg/m^3, default 0.0 (used only with body.gravity).
    """

    E: float
    nu: float
    KIc: float
    plane: str = "stress"
    thickness: float = 1.0
    density: float = 0.0


@dataclass(frozen=True, eq=False)
class Fracture:
    """A pre-existing fracture: a polyline `points` (n, 2), n >= 2, read-only.

    Direction d runs from point 0 to point n-1 (docs/architecture.md).
    faces: "open" (default, traction free), "frictionless" (contact, no
    friction) or "slip" (prescribed tangential jump). slip: [u].t in m, only
    with faces = "slip", default 0.0; scaled by the load factor.
    slip_profile: "uniform" (default) or "elliptic" (slip * sqrt(1 - (2s/L - 1)^2)
    along the arc length s of a fracture of length L), only with faces = "slip".
    gap: initial normal gap g >= 0 (m), default 0.0. grow: may its tips grow
    wing cracks, default True.
    """

    points: np.ndarray
    faces: str = "open"
    slip: float = 0.0
    gap: float = 0.0
    grow: bool = True
    slip_profile: str = "uniform"

    @property
    def length(self) -> float:
        """Arc length (m)."""
        return float(np.linalg.norm(np.diff(self.points, axis=0), axis=1).sum())

    def scaled(self, factor: float) -> Fracture:
        """The same fracture with its prescribed slip times `factor`."""
        return replace(self, slip=self.slip * factor)


@dataclass(frozen=True)
class Tip:
    """A fracture end strictly inside the domain: `end` 0 is point 0, 1 the last."""

    fracture: int
    end: int
    point: tuple[float, float]


@dataclass(frozen=True)
class BC:
    """One boundary condition: one place and one condition.

    Exactly one of `at` (a boundary point, which becomes a mesh node) and `on`
    (a boundary name) is set. kind:
      "force" (N/m, global x/y; `at` only),
      "traction" (Pa, global x/y; `on` only),
      "displacement" (m; `at` or `on`); `components` says which of x, y are
      prescribed (displacement_x / displacement_y prescribe one; the value of a
      free component is 0.0 and means nothing).
    For force and traction `components` is (True, True). Every value is scaled
    by the load factor.
    """

    kind: str
    value: tuple[float, float]
    at: tuple[float, float] | None = None
    on: str | None = None
    components: tuple[bool, bool] = (True, True)

    def scaled(self, factor: float) -> BC:
        """The same condition with its value times `factor`."""
        return replace(self, value=(self.value[0] * factor, self.value[1] * factor))


@dataclass(frozen=True)
class Body:
    """Body force: gravity (m/s^2, global x/y), default (0, 0); acts through
    material.density (with density 0 there is no body force)."""

    gravity: tuple[float, float] = (0.0, 0.0)


@dataclass(frozen=True)
class Stress:
    """Initial (in situ) stress in Pa, compression < 0; default all 0.0. Not scaled."""

    sxx: float = 0.0
    syy: float = 0.0
    sxy: float = 0.0

    def tensor(self) -> np.ndarray:
        """The 2x2 stress tensor (Pa)."""
        return np.array([[self.sxx, self.sxy], [self.sxy, self.syy]])


@dataclass(frozen=True)
class MeshOptions:
    """Mesh sizing. size: target element size away from fractures (m), required.
    tip_size: crack-tip rosette radius h (m), required, < size and < the
    shortest fracture segment. adaptive: error-estimator-driven sizing between
    steps, default True. sectors: elements in a tip rosette, int >= 8,
    default 32: displacement correlation's KII is 0.7% off with 16 sectors,
    0.3% with 32 (see the README); below 16 only for convergence studies.
    """

    size: float
    tip_size: float
    adaptive: bool = True
    sectors: int = 32


@dataclass(frozen=True)
class Propagation:
    """Growth control. steps: most propagation steps, int >= 0, default 35.
    length: Lmax, the longest advance of any tip in one step (m), default
    mesh.tip_size (the paper's choice for a single crack). alpha: exponent of
    the growth law L_adv = Lmax (G / max G)^alpha, default 0.35.
    load: "scale" (default: every bc and slip scaled by one factor that rises
    until a tip reaches KIc) or "fixed" (factor 1). max_load_factor: the
    scaling gives up above this factor, default 100.0. sif: which SIFs
    drive growth (critical load, kink angle, G): "correlation" (default,
    the paper's displacement correlation) or "interaction" (the
    interaction integral).
    """

    length: float
    steps: int = 35
    alpha: float = 0.35
    load: str = "scale"
    max_load_factor: float = 100.0
    sif: str = "correlation"


@dataclass(frozen=True, eq=False)
class Case:
    """A checked case. Build it with `Case.from_toml(path)` or `Case.from_dict(d)`.

    Fields: title, material, domain (meshing.Domain), fractures (tuple of
    Fracture), bcs (tuple of BC, in file order), body, stress, mesh
    (MeshOptions), propagation, source (the file, or None).
    """

    title: str
    material: Material
    domain: Domain
    fractures: tuple[Fracture, ...]
    bcs: tuple[BC, ...]
    body: Body
    stress: Stress
    mesh: MeshOptions
    propagation: Propagation
    source: Path | None = field(default=None, compare=False)

    @classmethod
    def from_toml(cls, path) -> Case:
        """Read and check a case file. Unreadable files and TOML syntax errors
        are CaseError too, keyed by the file name."""
        path = Path(path)
        try:
            with open(path, "rb") as fh:
                raw = fh.read(MAX_FILE_BYTES + 1)
        except OSError as err:
            raise CaseError(str(path), f"cannot read: {err.strerror or err}") from None
        if len(raw) > MAX_FILE_BYTES:
            raise CaseError(str(path), f"too large for a case file (over {MAX_FILE_BYTES} bytes)")
        try:
            text = raw.decode("utf-8")
        except UnicodeDecodeError as err:
            line = raw.count(b"\n", 0, err.start) + 1
            column = err.start - (raw.rfind(b"\n", 0, err.start) + 1) + 1
            raise CaseError(str(path), f"not UTF-8 text: byte 0x{raw[err.start]:02x} "
                                       f"at line {line}, column {column}") from None
        try:
            data = tomllib.loads(text)
        except tomllib.TOMLDecodeError as err:
            raise CaseError(str(path), f"not valid TOML: {err}") from None
        except RecursionError:
            raise CaseError(str(path), "not valid TOML: arrays or tables nested too deeply") from None
        except ValueError as err:  # an integer over Python's 4300-digit limit of int(str)
            raise CaseError(str(path), f"not valid TOML: {str(err).split(';')[0]}") from None
        case = cls.from_dict(data, source=path)
        if "title" not in data:
            case = replace(case, title=path.stem)
        return case

    @classmethod
    def from_dict(cls, d: dict, source: Path | None = None) -> Case:
        """Check a parsed case table (as tomllib returns it) and build the Case."""
        return _parse_case(d, source)

    # ---- accessors the solver needs

    @property
    def length_scale(self) -> float:
        """The domain's length scale (m); tolerances are relative to it."""
        return float(self.domain.length_scale())

    def fracture_points(self) -> list[np.ndarray]:
        """Each fracture's polyline, (n, 2) float64, in case order."""
        return [f.points for f in self.fractures]

    def tips(self) -> list[Tip]:
        """Fracture ends strictly inside the domain (an end on the boundary is an
        edge crack's mouth, not a tip), in fracture order, end 0 before end 1."""
        tol = REL_TOL * self.length_scale
        out = []
        for i, f in enumerate(self.fractures):
            for end, p in ((0, f.points[0]), (1, f.points[-1])):
                if not self.domain.on_boundary(p, tol):
                    out.append(Tip(i, end, (float(p[0]), float(p[1]))))
        return out

    def bc_points(self) -> list[np.ndarray]:
        """The distinct points of point conditions (`at`), to embed in the mesh."""
        tol = REL_TOL * self.length_scale
        pts: list[np.ndarray] = []
        for bc in self.bcs:
            if bc.at is None:
                continue
            p = np.array(bc.at, dtype=float)
            if all(np.linalg.norm(p - q) > tol for q in pts):
                pts.append(p)
        return pts

    def at_load(self, factor: float) -> Case:
        """The case with every bc value and every fracture slip times `factor`
        (initial stress and gravity unchanged)."""
        return replace(
            self,
            bcs=tuple(bc.scaled(factor) for bc in self.bcs),
            fractures=tuple(f.scaled(factor) for f in self.fractures),
        )


# ---------------------------------------------------------------- reading

_REQUIRED = object()


def _what(v) -> str:
    if isinstance(v, bool):
        return "a boolean"
    if isinstance(v, (int, float)):
        return "a number"
    if isinstance(v, str):
        return "a string"
    if isinstance(v, list):
        return "an array"
    if isinstance(v, dict):
        return "a table"
    return f"a {type(v).__name__}"


def _as_number(v, key: str) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise CaseError(key, f"expected a number, got {_what(v)}")
    try:
        x = float(v)
    except OverflowError:
        x = math.inf
    if not math.isfinite(x):
        got = f"an integer of {len(str(abs(v)))} digits" if isinstance(v, int) else str(v)
        raise CaseError(key, f"must be a finite number, got {got}")
    return x


def _as_point(v, key: str) -> tuple[float, float]:
    if not isinstance(v, list) or len(v) != 2:
        got = f"{len(v)} values" if isinstance(v, list) else _what(v)
        raise CaseError(key, f"expected [x, y] (2 numbers), got {got}")
    return (_as_number(v[0], f"{key}[0]"), _as_number(v[1], f"{key}[1]"))


class _Table:
    """A TOML table being read: knows its key path, checks key names and types."""

    def __init__(self, data, path: str):
        if not isinstance(data, dict):
            raise CaseError(path, f"expected a table, got {_what(data)}")
        self.data = data
        self.path = path

    def key(self, k: str) -> str:
        return f"{self.path}.{k}" if self.path else k

    def only(self, allowed) -> None:
        """Refuse any key outside `allowed`, suggesting the closest one."""
        allowed = list(allowed)
        for k in self.data:
            if k not in allowed:
                near = difflib.get_close_matches(k, allowed, n=1)
                hint = f" (did you mean {near[0]}?)" if near else ""
                raise CaseError(self.key(k), f"unknown key{hint}")

    def has(self, k: str) -> bool:
        return k in self.data

    def _get(self, k, default):
        if k in self.data:
            return self.data[k], True
        if default is _REQUIRED:
            raise CaseError(self.key(k), "missing (required)")
        return default, False

    def number(self, k, default=_REQUIRED) -> float:
        v, given = self._get(k, default)
        return _as_number(v, self.key(k)) if given else v

    def integer(self, k, default=_REQUIRED) -> int:
        v, given = self._get(k, default)
        if given and (isinstance(v, bool) or not isinstance(v, int)):
            raise CaseError(self.key(k), f"expected an integer, got {_what(v)}")
        return v

    def boolean(self, k, default=_REQUIRED) -> bool:
        v, given = self._get(k, default)
        if given and not isinstance(v, bool):
            raise CaseError(self.key(k), f"expected true or false, got {_what(v)}")
        return v

    def choice(self, k, choices, default=_REQUIRED) -> str:
        v, given = self._get(k, default)
        if not given:
            return v
        if not isinstance(v, str):
            raise CaseError(self.key(k), f"expected a string, got {_what(v)}")
        if v not in choices:
            options = " | ".join(f'"{c}"' for c in choices)
            raise CaseError(self.key(k), f'"{v}" is not one of {options}')
        return v

    def string(self, k, default=_REQUIRED) -> str:
        v, given = self._get(k, default)
        if given and not isinstance(v, str):
            raise CaseError(self.key(k), f"expected a string, got {_what(v)}")
        return v

    def point(self, k, default=_REQUIRED) -> tuple[float, float]:
        v, given = self._get(k, default)
        return _as_point(v, self.key(k)) if given else v

    def points(self, k) -> np.ndarray:
        """A required array of [x, y] as (n, 2) float64."""
        v, _ = self._get(k, _REQUIRED)
        if not isinstance(v, list):
            raise CaseError(self.key(k), f"expected an array of [x, y], got {_what(v)}")
        if len(v) > MAX_ITEMS:
            raise CaseError(self.key(k), f"at most {MAX_ITEMS} points, got {len(v)}")
        pts = [_as_point(p, f"{self.key(k)}[{i}]") for i, p in enumerate(v)]
        return np.array(pts, dtype=float).reshape(-1, 2)

    def table(self, k, required=False) -> _Table:
        if k not in self.data:
            if required:
                raise CaseError(self.key(k), "missing (required table)")
            return _Table({}, self.key(k))
        return _Table(self.data[k], self.key(k))

    def array_of_tables(self, k) -> list[_Table]:
        if k not in self.data:
            return []
        v = self.data[k]
        if not isinstance(v, list):
            raise CaseError(self.key(k), f"expected an array of tables ([[{k}]]), got {_what(v)}")
        if len(v) > MAX_ITEMS:
            raise CaseError(self.key(k), f"at most {MAX_ITEMS} entries, got {len(v)}")
        return [_Table(item, f"{self.key(k)}[{i}]") for i, item in enumerate(v)]


def _require_positive(x: float, key: str, what: str = "must be > 0") -> None:
    if not x > 0:
        raise CaseError(key, f"{what}, got {x:g}")


# ---------------------------------------------------------------- sections


def _parse_material(t: _Table) -> Material:
    t.only(["E", "nu", "KIc", "plane", "thickness", "density"])
    E = t.number("E")
    _require_positive(E, t.key("E"))
    nu = t.number("nu")
    if not -1.0 < nu < 0.5:
        raise CaseError(t.key("nu"), f"must lie in (-1, 0.5), got {nu:g}")
    KIc = t.number("KIc")
    _require_positive(KIc, t.key("KIc"))
    plane = t.choice("plane", PLANES, "stress")
    thickness = t.number("thickness", 1.0)
    _require_positive(thickness, t.key("thickness"))
    density = t.number("density", 0.0)
    if density < 0:
        raise CaseError(t.key("density"), f"must be >= 0, got {density:g}")
    return Material(E, nu, KIc, plane, thickness, density)


_SHAPE_KEYS = {"disc": ("center", "radius"), "rectangle": ("corner", "size"), "polygon": ("points",)}


def _parse_domain(t: _Table):
    """Check the domain table and build the meshing.Domain."""
    t.only(["shape", "center", "radius", "corner", "size", "points"])
    shape = t.choice("shape", SHAPES)
    keys = _SHAPE_KEYS[shape]
    for k in t.data:
        if k != "shape" and k not in keys:
            raise CaseError(t.key(k), f'not a key of shape "{shape}" (it takes {", ".join(keys)})')
    geo: dict = {}
    if shape == "disc":
        geo["center"] = t.point("center")
        geo["radius"] = t.number("radius")
        _require_positive(geo["radius"], t.key("radius"))
        _check_scale(2 * geo["radius"], np.abs(geo["center"]).max(), t.key("radius"), t.key("center"))
    elif shape == "rectangle":
        geo["corner"] = t.point("corner")
        geo["size"] = t.point("size")
        for i, name in enumerate(("width", "height")):
            _require_positive(geo["size"][i], f"{t.key('size')}[{i}]", f"{name} must be > 0")
        _check_scale(max(geo["size"]), np.abs(geo["corner"]).max(), t.key("size"), t.key("corner"))
    else:
        pts = t.points("points")
        if len(pts) < 3:
            raise CaseError(t.key("points"), f"a polygon needs at least 3 points, got {len(pts)}")
        # before _check_polygon, whose products would overflow
        with np.errstate(over="ignore"):
            extent = float(np.ptp(pts, axis=0).max())
        _check_scale(extent, np.abs(pts).max(), t.key("points"), t.key("points"))
        _check_polygon(pts, t.key("points"))
        geo["points"] = pts
    try:
        return Domain(shape, **geo)
    except ValueError as err:  # anything meshing refuses that the checks above let through
        raise CaseError(t.path, str(err)) from None


def _check_scale(size: float, offset: float, size_key: str, offset_key: str) -> None:
    """The domain's size within LENGTH_RANGE, and its coordinates within MAX_OFFSET sizes of the origin."""
    lo, hi = LENGTH_RANGE
    if not lo <= size <= hi:
        raise CaseError(size_key, f"a domain {size:g} m across is outside the verified range {lo:g} .. {hi:g} m")
    if offset > MAX_OFFSET * size:
        raise CaseError(offset_key, f"coordinates {offset:g} m from the origin are over {MAX_OFFSET:g} times "
                                    f"the domain size ({size:g} m): move the origin near the domain")


def _check_polygon(pts: np.ndarray, key: str) -> None:
    extent = float(np.ptp(pts, axis=0).max())
    tol = REL_TOL * max(extent, np.finfo(float).tiny)
    edges = np.roll(pts, -1, axis=0) - pts
    for i, e in enumerate(edges):
        if np.linalg.norm(e) <= tol:
            raise CaseError(key, f"edge{i} has zero length (points {i} and {(i + 1) % len(pts)} coincide)")
    # Shoelace: twice the signed area, > 0 counter-clockwise.
    area2 = float(np.sum(pts[:, 0] * np.roll(pts[:, 1], -1) - np.roll(pts[:, 0], -1) * pts[:, 1]))
    if _kernels.polyline_self_intersects(pts, REL_TOL):
        raise CaseError(key, "the polygon intersects itself")
    n = len(pts)
    # The closing edge (n-1 -> 0) against every edge not adjacent to it.
    for j in range(1, n - 2):
        hit = _kernels.segment_intersection(pts[n - 1], pts[0], pts[j], pts[j + 1], REL_TOL)[0]
        if hit:
            raise CaseError(key, f"the polygon intersects itself (edge{n - 1} meets edge{j})")
    if abs(area2) <= tol * extent:
        raise CaseError(key, "the polygon has no area")
    if area2 < 0:
        raise CaseError(key, "points must run counter-clockwise (they run clockwise)")


def _parse_fracture(t: _Table) -> tuple[np.ndarray, dict]:
    t.only(["points", "faces", "slip", "slip_profile", "gap", "grow"])
    pts = t.points("points")
    if len(pts) < 2:
        raise CaseError(t.key("points"), f"a fracture needs at least 2 points, got {len(pts)}")
    faces = t.choice("faces", FACES, "open")
    slip = t.number("slip", 0.0)
    profile = t.choice("slip_profile", SLIP_PROFILES, "uniform")
    # the contract's own example writes slip = 0.0 on frictionless faces: a
    # zero slip is no condition and is accepted anywhere; a real one is not
    if faces != "slip":
        if slip != 0.0:
            raise CaseError(t.key("slip"), f'only with faces = "slip" (faces is "{faces}")')
        if t.has("slip_profile"):
            raise CaseError(t.key("slip_profile"), f'only with faces = "slip" (faces is "{faces}")')
    gap = t.number("gap", 0.0)
    if gap < 0:
        raise CaseError(t.key("gap"), f"must be >= 0, got {gap:g}")
    grow = t.boolean("grow", True)
    pts.setflags(write=False)
    return pts, dict(faces=faces, slip=slip, slip_profile=profile, gap=gap, grow=grow)


def _parse_bc(t: _Table, boundary_names) -> BC:
    conditions = ("force", "traction", "displacement", "displacement_x", "displacement_y")
    t.only(("at", "on") + conditions)
    has_at, has_on = t.has("at"), t.has("on")
    if has_at and has_on:
        raise CaseError(t.path, "give one place: either at (a point) or on (a boundary), not both")
    if not (has_at or has_on):
        raise CaseError(t.path, "missing place: give at = [x, y] or on = \"<boundary>\"")
    given = [c for c in conditions if t.has(c)]
    if t.has("displacement"):
        for c in ("displacement_x", "displacement_y"):
            if t.has(c):
                raise CaseError(t.key(c), "conflicts with displacement (give displacement, or displacement_x / displacement_y)")
    # displacement_x and displacement_y together are one displacement condition.
    kinds = {c.split("_")[0] for c in given}
    if not given:
        raise CaseError(t.path, "no condition: give one of " + ", ".join(conditions))
    if len(kinds) > 1:
        raise CaseError(t.path, "two conditions (" + " and ".join(given) + "): each [[bc]] holds one")
    kind = kinds.pop()
    at = t.point("at") if has_at else None
    on = None
    if has_on:
        on = t.string("on")
        names = list(boundary_names)
        if on not in names:
            near = difflib.get_close_matches(on, names, n=1)
            hint = f"; did you mean {near[0]}?" if near else ""
            raise CaseError(t.key("on"), f'no boundary named "{on}" (this domain has {", ".join(names)}{hint})')
    if kind == "force" and on is not None:
        raise CaseError(t.key("force"), "a force (N/m) acts at a point: use at = [x, y], or traction on a boundary")
    if kind == "traction" and at is not None:
        raise CaseError(t.key("traction"), "a traction (Pa) acts on a boundary: use on = \"<boundary>\", or force at a point")
    if kind in ("force", "traction"):
        return BC(kind, t.point(kind), at=at, on=on)
    if t.has("displacement"):
        return BC("displacement", t.point("displacement"), at=at, on=on)
    ux = t.number("displacement_x", None)
    uy = t.number("displacement_y", None)
    return BC("displacement", (ux or 0.0, uy or 0.0), at=at, on=on, components=(ux is not None, uy is not None))


def _parse_mesh(t: _Table) -> MeshOptions:
    t.only(["size", "tip_size", "adaptive", "sectors"])
    size = t.number("size")
    _require_positive(size, t.key("size"))
    tip = t.number("tip_size")
    _require_positive(tip, t.key("tip_size"))
    if tip >= size:
        raise CaseError(t.key("tip_size"), f"must be smaller than mesh.size ({tip:g} >= {size:g})")
    adaptive = t.boolean("adaptive", True)
    sectors = t.integer("sectors", 32)
    if sectors < 8:
        raise CaseError(t.key("sectors"), f"must be >= 8 (32 recommended), got {sectors}")
    if sectors > MAX_SECTORS:
        raise CaseError(t.key("sectors"), f"must be <= {MAX_SECTORS} (32 recommended), got {sectors}")
    return MeshOptions(size, tip, adaptive, sectors)


def _check_mesh_against_domain(mesh: MeshOptions, domain) -> None:
    """Sizes the mesher can honour in this domain: not too many triangles, a
    rosette well above the geometric tolerance."""
    L = float(domain.length_scale())
    cells = domain.area() / (math.sqrt(3) / 4 * mesh.size**2)
    if cells > MAX_ELEMENTS:
        raise CaseError("mesh.size", f"{mesh.size:g} m asks for about {cells:.2g} elements in this domain of "
                                     f"{domain.area():.4g} m^2 (at most {MAX_ELEMENTS:.2g}): use a larger size")
    if mesh.tip_size < MIN_TIP_FRACTION * L:
        raise CaseError("mesh.tip_size", f"{mesh.tip_size:g} m is below {MIN_TIP_FRACTION:g} of the domain size "
                                         f"({L:g} m): too close to the geometric tolerance")


def _parse_propagation(t: _Table, tip_size: float, domain_size: float) -> Propagation:
    t.only(["steps", "length", "alpha", "load", "max_load_factor", "sif"])
    steps = t.integer("steps", 35)
    if steps < 0:
        raise CaseError(t.key("steps"), f"must be >= 0, got {steps}")
    length = t.number("length", tip_size)
    _require_positive(length, t.key("length"))
    problem = length_problem(length, tip_size, domain_size)
    if problem:
        raise CaseError(t.key("length"), problem)
    alpha = t.number("alpha", 0.35)
    _require_positive(alpha, t.key("alpha"))
    load = t.choice("load", LOADS, "scale")
    mlf = t.number("max_load_factor", 100.0)
    _require_positive(mlf, t.key("max_load_factor"))
    sif = t.choice("sif", SIF_METHODS, "correlation")
    return Propagation(length=length, steps=steps, alpha=alpha, load=load, max_load_factor=mlf, sif=sif)


# ---------------------------------------------------------------- the case


def _parse_case(d: dict, source: Path | None) -> Case:
    top = _Table(d, "")
    top.only(["title", "material", "domain", "fractures", "bc", "body", "stress", "mesh", "propagation"])
    title = top.string("title", "")

    material = _parse_material(top.table("material", required=True))
    domain = _parse_domain(top.table("domain", required=True))
    L = float(domain.length_scale())
    tol = REL_TOL * L

    fr_tables = top.array_of_tables("fractures")
    parsed = [_parse_fracture(ft) for ft in fr_tables]
    for ft, (pts, _) in zip(fr_tables, parsed):
        _check_fracture_geometry(pts, ft.key("points"), domain, tol)
    _check_fractures_apart([p for p, _ in parsed], tol)
    fractures = tuple(Fracture(pts, **opts) for pts, opts in parsed)

    bc_tables = top.array_of_tables("bc")
    bcs = tuple(_parse_bc(bt, domain.boundary_names()) for bt in bc_tables)
    for bt, bc in zip(bc_tables, bcs):
        if bc.at is not None:
            _check_bc_point(bc.at, bt.key("at"), domain, fractures, tol)
    _check_bc_conflicts(bcs, domain, tol)

    bt = top.table("body")
    bt.only(["gravity"])
    body = Body(bt.point("gravity", (0.0, 0.0)))
    # gravity with density 0 (the contract's example) is no body force: allowed

    st = top.table("stress")
    st.only(["sxx", "syy", "sxy"])
    stress = Stress(st.number("sxx", 0.0), st.number("syy", 0.0), st.number("sxy", 0.0))

    mesh = _parse_mesh(top.table("mesh", required=True))
    _check_mesh_against_domain(mesh, domain)
    _check_mesh_against_fractures(mesh, fractures, domain, tol)
    propagation = _parse_propagation(top.table("propagation"), mesh.tip_size, L)

    _check_statically_determined(bcs, domain)

    return Case(title, material, domain, fractures, bcs, body, stress, mesh, propagation, source)


# ---------------------------------------------------------------- geometry checks


def _strictly_inside(domain, p, tol) -> bool:
    return bool(domain.contains(p)) and not domain.on_boundary(p, tol)


def _far_outside(domain, p) -> bool:
    """p outside the domain's bounding box grown by its size: decided without
    the distance computations, whose squares overflow for p ~ 1e200."""
    L = float(domain.length_scale())
    if domain.shape == "disc":
        lo, hi = domain.center - domain.radius, domain.center + domain.radius
    else:
        lo, hi = domain.vertices().min(axis=0), domain.vertices().max(axis=0)
    return bool(np.any(np.asarray(p) < lo - L) or np.any(np.asarray(p) > hi + L))


def _check_fracture_geometry(pts: np.ndarray, key: str, domain, tol: float) -> None:
    for i, p in enumerate(pts):
        if _far_outside(domain, p):
            raise CaseError(f"{key}[{i}]", f"({p[0]:g}, {p[1]:g}) is outside the domain")
    seg = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    for i, s in enumerate(seg):
        if s <= tol:
            raise CaseError(key, f"segment {i} (points {i} and {i + 1}) has zero length")
    if len(pts) > 2 and _kernels.polyline_self_intersects(pts, REL_TOL):
        raise CaseError(key, "the polyline intersects itself")
    n = len(pts)
    for i, p in enumerate(pts):
        if (i == 0 or i == n - 1) and domain.on_boundary(p, tol):
            continue  # an edge crack's mouth
        if not _strictly_inside(domain, p, tol):
            where = "on the boundary (only an end may be)" if domain.on_boundary(p, tol) else "outside the domain"
            raise CaseError(f"{key}[{i}]", f"({p[0]:g}, {p[1]:g}) is {where}")
    # Every point inside does not keep a segment inside: a chord between two
    # boundary ends may run along the boundary, and a polygon may be concave.
    for i in range(n - 1):
        mid = 0.5 * (pts[i] + pts[i + 1])
        if not _strictly_inside(domain, mid, tol):
            raise CaseError(key, f"segment {i} runs along or outside the boundary")
    if domain.shape == "polygon":  # rectangles and discs are convex
        poly = domain.vertices()
        m = len(poly)
        for i in range(n - 1):
            for j in range(m):
                hit, _, _, x = _kernels.segment_intersection(pts[i], pts[i + 1], poly[j], poly[(j + 1) % m], REL_TOL)
                if not hit:
                    continue
                x = np.asarray(x)
                at_mouth = (i == 0 and np.linalg.norm(x - pts[0]) <= tol) or (
                    i == n - 2 and np.linalg.norm(x - pts[-1]) <= tol
                )
                if not at_mouth:
                    raise CaseError(key, f"segment {i} crosses the boundary edge{j}")
    if domain.on_boundary(pts[0], tol) and domain.on_boundary(pts[-1], tol):
        raise CaseError(key, "both ends lie on the boundary: the fracture cuts the domain in two")


def _check_fractures_apart(polylines: list[np.ndarray], tol: float) -> None:
    for i in range(len(polylines)):
        for j in range(i + 1, len(polylines)):
            if _kernels.polylines_intersect(polylines[i], polylines[j], REL_TOL):
                raise CaseError(f"fractures[{j}].points", f"crosses or touches fractures[{i}]")


def _check_bc_point(p, key: str, domain, fractures, tol: float) -> None:
    if _far_outside(domain, p):
        raise CaseError(key, f"({p[0]:g}, {p[1]:g}) is not on the boundary (it is far outside the domain)")
    if not domain.on_boundary(np.asarray(p, dtype=float), tol):
        d = float(domain.distance_to_boundary(np.asarray(p, dtype=float)))
        raise CaseError(key, f"({p[0]:g}, {p[1]:g}) is not on the boundary (it is {d:.3g} m away)")
    for i, f in enumerate(fractures):
        if _kernels.point_polyline_distance(np.asarray(p, dtype=float), f.points) <= tol:
            raise CaseError(key, f"({p[0]:g}, {p[1]:g}) is the mouth of fractures[{i}]; a point condition there is ambiguous")


def _on_named_boundary(domain, name: str, p, tol: float) -> bool:
    if domain.shape == "disc":
        return bool(domain.on_boundary(np.asarray(p, dtype=float), tol))
    v = domain.vertices()
    i = domain.edge_names().index(name)
    return _kernels.point_segment_distance(np.asarray(p, dtype=float), v[i], v[(i + 1) % len(v)])[0] <= tol


def _meeting_place(a: BC, b: BC, domain, tol: float) -> str | None:
    """Where the places of two conditions meet, as text, or None when apart:
    two points, a point on a named boundary, one boundary twice, or two
    boundaries sharing a corner."""
    if a.at is not None and b.at is not None:
        return "at the same place" if math.dist(a.at, b.at) <= tol else None
    if a.at is not None or b.at is not None:
        p, name = (a.at, b.on) if a.at is not None else (b.at, a.on)
        return f"at ({p[0]:g}, {p[1]:g})" if _on_named_boundary(domain, name, p, tol) else None
    if a.on == b.on:
        return "at the same place"
    if domain.shape == "disc":
        return None
    names, v = domain.edge_names(), domain.vertices()
    i, j = names.index(a.on), names.index(b.on)
    n = len(v)
    shared = [k for k in ((i + 1) % n, i) if k in ((j + 1) % n, j)]  # edge k runs from vertex k to k+1
    if not shared:
        return None
    x, y = v[shared[0]]
    return f"at the corner ({x:g}, {y:g})"


def _check_bc_conflicts(bcs, domain, tol: float) -> None:
    """Two displacement conditions prescribing one component differently at a
    place they share: a point, a point on a boundary, a boundary's corner."""
    seen: list[tuple[int, BC]] = []
    for j, bc in enumerate(bcs):
        if bc.kind != "displacement":
            continue
        for i, other in seen:
            differ = [name for c, name in enumerate("xy")
                      if bc.components[c] and other.components[c] and bc.value[c] != other.value[c]]
            if not differ:
                continue
            where = _meeting_place(bc, other, domain, tol)
            if where is not None:
                raise CaseError(f"bc[{j}]", f"displacement {differ[0]} conflicts with bc[{i}] {where}")
        seen.append((j, bc))


def _check_mesh_against_fractures(mesh: MeshOptions, fractures, domain, tol: float) -> None:
    h = mesh.tip_size
    for i, f in enumerate(fractures):
        shortest = float(np.linalg.norm(np.diff(f.points, axis=0), axis=1).min())
        if h >= shortest:
            raise CaseError(
                "mesh.tip_size", f"must be smaller than the shortest segment of fractures[{i}] ({h:g} >= {shortest:g})"
            )
    for i, f in enumerate(fractures):
        for end, p in ((0, f.points[0]), (1, f.points[-1])):
            if domain.on_boundary(p, tol):
                continue
            if float(domain.distance_to_boundary(p)) <= h:
                raise CaseError(
                    "mesh.tip_size", f"the rosette of fractures[{i}] end {end} (radius {h:g}) reaches the boundary"
                )
            for j, g in enumerate(fractures):
                if j != i and _kernels.point_polyline_distance(p, g.points) <= h:
                    raise CaseError(
                        "mesh.tip_size", f"the rosette of fractures[{i}] end {end} (radius {h:g}) reaches fractures[{j}]"
                    )


# ---------------------------------------------------------------- rigid-body check


def _boundary_samples(domain, name: str) -> np.ndarray:
    """Points along the named boundary: inside each straight edge, around a disc rim."""
    t = (np.arange(_SAMPLES) + 0.5) / _SAMPLES
    if domain.shape == "disc":
        a = 2 * np.pi * t
        return domain.center + domain.radius * np.column_stack([np.cos(a), np.sin(a)])
    v = domain.vertices()
    i = domain.edge_names().index(name)
    a, b = v[i], v[(i + 1) % len(v)]
    return a + t[:, None] * (b - a)


def _check_statically_determined(bcs, domain) -> None:
    """Rank of the rigid motions (1,0), (0,1), (-y,x) under the displacement conditions.

    Each prescribed component at a point p gives a row: x: [1, 0, -y], y: [0, 1, x],
    with (x, y) = (p - origin) / L (origin inside the domain, L its length scale,
    so the rows are well scaled). A boundary condition counts at sample points.
    """
    L = float(domain.length_scale())
    origin = domain.center if domain.shape == "disc" else domain.vertices().mean(axis=0)
    rows = []
    for bc in bcs:
        if bc.kind != "displacement":
            continue
        pts = np.array([bc.at]) if bc.at is not None else _boundary_samples(domain, bc.on)
        for x, y in (pts - origin) / L:
            if bc.components[0]:
                rows.append([1.0, 0.0, -y])
            if bc.components[1]:
                rows.append([0.0, 1.0, x])
    A = np.array(rows, dtype=float).reshape(-1, 3)
    rank = np.linalg.matrix_rank(A, tol=1e-8) if len(A) else 0
    if rank < 3:
        raise CaseError("bc", f"statically undetermined: {_free_motions(A, origin / L, L)} free; "
                              "add displacement conditions")


def _free_motions(A: np.ndarray, origin: np.ndarray, L: float) -> str:
    """Name the rigid motions the rows of A leave free (A uses coordinates (p - origin)/L)."""
    if len(A) == 0:
        return "translation x, translation y and rotation are"
    _, s, vt = np.linalg.svd(A)
    null = vt[np.sum(s > 1e-8 * max(s.max(), 1.0)):]
    free = []
    tx = np.linalg.norm(A @ [1.0, 0.0, 0.0]) < 1e-8
    ty = np.linalg.norm(A @ [0.0, 1.0, 0.0]) < 1e-8
    if tx:
        free.append("translation x")
    if ty:
        free.append("translation y")
    if any(abs(v[2]) > 1e-8 for v in null):
        if len(null) == 1:
            a, b, c = null[0]
            centre = (origin + np.array([-b / c, a / c])) * L
            free.append(f"rotation about ({centre[0]:.4g}, {centre[1]:.4g})")
        else:
            free.append("rotation")
    if not free:  # pragma: no cover - a null space always contains one of the above
        free.append("a rigid motion")
    verb = "is" if len(free) == 1 else "are"
    return ", ".join(free[:-1]) + (" and " if len(free) > 1 else "") + free[-1] + f" {verb}"
