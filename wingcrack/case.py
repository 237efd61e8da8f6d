"""The case: what one case file describes, read and checked.

The contract is /work/shared/spec/case-format.md. `Case.from_toml(path)` reads a
file, `Case.from_dict(d)` a parsed table; both return a `Case` whose every part
has been checked, or raise `CaseError(key, reason)` naming the first offending
key by its full path (``mesh.tip_size``, ``fractures[1].points[0]``, ``bc[2].at``).

Every key is described once, below, as a `Key` (type, unit, default, the range
its meaning allows, the magnitude a case may ask for, documentation): on the
field of the dataclass that holds it (`Material.E`), or, where the file's
layout is not the dataclass's (`[domain]`, `[[bc]]`, the top level), in a
tuple of Keys. One reader, `_Table.read`, checks a table against its Keys;
the rules that tie keys together (one place and one condition per `[[bc]]`,
tip_size below size) follow it, then the geometric checks, then the rigid-body
check. docs/case-format.md's key tables are rendered from the Keys
(`python -m wingcrack.case_doc`).

Units are SI throughout (m, Pa, N; a point force is N per metre of thickness).
Points are (x, y) float64. Load scaling (done by the solver, not here): with
propagation.load = "scale" every bc force, traction and displacement, every
prescribed fracture slip and every fracture pressure is multiplied by the load
factor; with "pressure" only the fracture pressures are; the initial stress
and gravity never are.
"""
from __future__ import annotations

import dataclasses
import difflib
import functools
import math
import os
import stat
import tomllib
import typing
import unicodedata
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from meshing import admissibility  # the mesher's own rules: what `check` accepts it meshes
from meshing.domain import Domain  # pure numpy: `check` needs neither gmsh nor DOLFINx
import wingcrack_kernels as _kernels  # geometry predicates (C++)
from wingcrack.errors import CaseError
from wingcrack.propagation.growth_law import length_problem   # the Lmax rule lives with the growth law

PLANES = ("stress", "strain")
SHAPES = ("disc", "rectangle", "polygon")
FACES = ("open", "frictionless", "slip", "coulomb")
SLIP_PROFILES = ("uniform", "elliptic")
LOADS = ("scale", "pressure", "fixed")
SIFS = ("correlation", "interaction")
#: Relative tolerance (times the domain length scale) for "on the boundary",
#: "touching" and "zero length".
REL_TOL = admissibility.REL_TOL
#: Sample points per named boundary for the rigid-body check.
_SAMPLES = 8
#: A case file is a page of text; anything larger is refused before parsing
#: (a 10 MB list of points would otherwise take minutes in the O(n^2) checks).
MAX_FILE_BYTES = 1 << 20
#: The domain size (m) the mesher and solver are verified for, and how far
#: from the origin it may lie (in domain sizes): see meshing/admissibility.py.
LENGTH_RANGE = admissibility.LENGTH_RANGE
MAX_OFFSET = admissibility.MAX_OFFSET
MIN_TIP_FRACTION = admissibility.MIN_TIP_FRACTION
#: The most triangles mesh.size may ask for (area / (sqrt(3)/4 size^2)):
#: about 16 million P2 DOFs, beyond what the 2-core, 24 GB machines factorise.
MAX_ELEMENTS = 4_000_000
#: The most triangles in one tip rosette (one degree each).
MAX_SECTORS = 360
#: The most fractures, points per polyline and boundary conditions: the
#: pairwise checks are quadratic in these.
MAX_ITEMS = 1000
#: The largest stress a case may ask for, as a fraction of E (tractions, the
#: in-situ stress, the weight of the domain), and the largest displacement,
#: slip or gap as a fraction of the domain size: a strain of 10 % is already
#: beyond linear elasticity, and every product the solver forms stays finite.
MAX_STRAIN = 0.1
#: The largest Coulomb coefficient `friction` may be: far above any measured
#: one, and small enough that mu times a stress of 0.1 E stays finite.
MAX_FRICTION = 100.0


# ---------------------------------------------------------------- the description

NUMBER, INTEGER, BOOLEAN, STRING = "number", "integer", "boolean", "string"
POINT, POINTS, TABLE, TABLES = "[x, y]", "[[x, y], ...]", "table", "array of tables"


class _Required:
    def __repr__(self) -> str:
        return "REQUIRED"


REQUIRED = _Required()


@dataclass(frozen=True)
class Ref:
    """A default taken from another key of the case, named by its full path."""

    key: str


@dataclass(frozen=True)
class Range:
    """What the key's meaning allows: lo < x < hi (`open`) or lo <= x <= hi;
    either end may be None. `note` is added to the message."""

    lo: float | None = None
    hi: float | None = None
    open: bool = False
    note: str = ""

    def check(self, x, key: str, what: str = "") -> None:
        got = _shown(x) if isinstance(x, float) else str(x)
        lo, hi = self.lo, self.hi
        if lo is not None and hi is not None and self.open:
            if not lo < x < hi:
                raise CaseError(key, f"{what}must lie in ({lo:g}, {hi:g}){self.note}, got {got}")
            return
        if lo is not None and not (x > lo if self.open else x >= lo):
            raise CaseError(key, f"{what}must be {'>' if self.open else '>='} {lo:g}{self.note}, got {got}")
        if hi is not None and not (x < hi if self.open else x <= hi):
            raise CaseError(key, f"{what}must be {'<' if self.open else '<='} {hi:g}{self.note}, got {got}")


def _shown(x) -> str:
    """A refused number as %g, or with the digits it takes to be exact: a value
    just beyond a bound (E = 1.0000001e13) must not read as the bound itself
    ("got 1e+13")."""
    x = float(x)
    for digits in range(6, 18):
        text = f"{x:.{digits}g}"
        if float(text) == x:
            return text
    return repr(x)


POSITIVE = Range(0, open=True)
NON_NEGATIVE = Range(0)


@dataclass(frozen=True)
class Limit:
    """The magnitude a case may ask for, lo*scale <= |x| <= hi*scale, where
    `of` names a scale of the case ("E", "L", "E L", "E / (density L)"; ""
    for none) and `why` says where the bound comes from. A string's limit
    counts its characters. These bound what the meaning would allow, so that
    nothing a case asks for overflows or underflows in the solve."""

    lo: float = 0.0
    hi: float = math.inf
    of: str = ""
    why: str = ""

    def check(self, x, key: str, unit: str, signed: bool, scales: dict) -> None:
        if isinstance(x, str):
            if len(x) > self.hi:
                raise CaseError(key, f"at most {self.hi:g} characters ({self.why}), got {len(x)}")
            return
        scale = scales[self.of] if self.of else 1.0
        if abs(x) <= self.hi * scale and (self.lo == 0 or abs(x) >= self.lo * scale):
            return
        unit = f" {unit}" if unit else ""
        if self.lo > 0:
            raise CaseError(key, f"must lie within {self.lo:g} .. {self.hi:g}{unit} ({self.why}), got {_shown(x)}")
        bound = f"{self.bound} = {self.hi * scale:.4g}{unit}" if self.of else f"{self.hi:g}{unit}"
        size = " in magnitude" if signed else ""
        raise CaseError(key, f"must be at most {bound}{size} ({self.why}), got {_shown(x)}")

    @property
    def bound(self) -> str:
        """The upper bound as text: "0.1 E", "L", "1e+09"."""
        return self.of if self.of and self.hi == 1 else f"{self.hi:g} {self.of}".strip()


@dataclass(frozen=True)
class Key:
    """One key of a case table.

    name and type (NUMBER, INTEGER, BOOLEAN, STRING, POINT, POINTS, TABLE,
    TABLES) come from the dataclass field when the Key sits on one. default:
    REQUIRED, a value, None (absent means not given) or a Ref. choices: the
    allowed strings. range: what the meaning allows (a point's components
    each, named by `parts`). limit: the magnitude a case may ask for.
    only_with (key, value): a value other than the default only when that
    earlier key of the table has that value. required_with (key, value):
    required when that earlier key has that value (elsewhere the default
    applies). min_points with `noun`: the fewest points of a POINTS key.
    doc: the reference's text; `rule`: what the checks further on ask of it;
    added: a key wingcrack adds to the contract.
    """

    name: str = ""
    type: str = ""
    default: object = REQUIRED
    unit: str = ""
    choices: tuple[str, ...] = ()
    range: Range | None = None
    limit: Limit | None = None
    only_with: tuple[str, str] | None = None
    required_with: tuple[str, str] | None = None
    parts: tuple[str, ...] = ()
    min_points: int = 0
    noun: str = ""
    doc: str = ""
    rule: str = ""
    default_doc: str = ""
    added: bool = False

    @property
    def signed(self) -> bool:
        return self.range is None or self.range.lo is None or self.range.lo < 0

    def check(self, v, key: str, values: dict, known: dict) -> None:
        """Everything this key asks of its (converted) value v."""
        if self.choices and v not in self.choices:
            options = " | ".join(f'"{c}"' for c in self.choices)
            raise CaseError(key, f'"{v}" is not one of {options}')
        if self.type == POINTS and len(v) < self.min_points:
            raise CaseError(key, f"{self.noun} needs at least {self.min_points} points, got {len(v)}")
        if self.only_with is not None:
            other, want = self.only_with
            if v != self.default and values[other] != want:
                raise CaseError(key, f'only with {other} = "{want}" ({other} is "{values[other]}")')
        items = list(enumerate(v)) if self.type == POINT else [(None, v)]
        for i, x in items:
            at = key if i is None else f"{key}[{i}]"
            if self.range is not None:
                self.range.check(x, at, f"{self.parts[i]} " if self.parts else "")
            if self.limit is not None:
                self.limit.check(x, at, self.unit, self.signed, known)


def key(default=REQUIRED, **spec) -> dataclasses.Field:
    """A dataclass field described by a Key (its name and type are the field's)."""
    k = Key(default=default, **spec)
    if default is REQUIRED or isinstance(default, Ref):
        return field(metadata={"key": k})
    return field(default=default, metadata={"key": k})


_TYPES = {float: NUMBER, int: INTEGER, bool: BOOLEAN, str: STRING, tuple[float, float]: POINT, np.ndarray: POINTS}


@functools.cache
def keys_of(cls) -> tuple[Key, ...]:
    """The Keys on the fields of dataclass `cls`, in field order."""
    hints = typing.get_type_hints(cls)
    return tuple(replace(f.metadata["key"], name=f.name, type=_TYPES[hints[f.name]])
                 for f in dataclasses.fields(cls) if "key" in f.metadata)


# ---------------------------------------------------------------- data model

_SMALL = "beyond it strains are not small and linear elasticity fails"


@dataclass(frozen=True)
class Material:
    """Linear elastic isotropic material."""

    E: float = key(unit="Pa", range=POSITIVE, doc="Young's modulus.",
                   limit=Limit(1e3, 1e13, why="from soft gels, 1 kPa, to above diamond, 1.2e12 Pa"))
    nu: float = key(range=Range(-1.0, 0.5, open=True), doc="Poisson's ratio.")
    KIc: float = key(unit="Pa m^0.5", range=POSITIVE, doc="Fracture toughness. A tip grows when its K_eq reaches "
                     "KIc.", limit=Limit(1.0, 1e9, why="from below the softest gels, ~10, to five times the toughest "
                                                       "steels, ~2e8"))
    plane: str = key("stress", choices=PLANES, doc="Plane stress or plane strain: E' = E, or E/(1-nu^2).")
    thickness: float = key(1.0, unit="m", range=POSITIVE, doc="Checked and printed by `check`, but no result "
                           "depends on it: loads and results are per metre of thickness.")
    density: float = key(0.0, unit="kg/m^3", range=NON_NEGATIVE, doc="Used only with a non-zero `body.gravity` "
                         "(with density 0 there is no body force).",
                         limit=Limit(hi=1e5, why="osmium, the densest element, has 22,590 kg/m^3"))


@dataclass(frozen=True, eq=False)
class Fracture:
    """A pre-existing fracture: a polyline `points` (n, 2), n >= 2, read-only."""

    points: np.ndarray = key(unit="m", min_points=2, noun="a fracture", rule="the geometry checks below",
                             doc="The polyline. Its direction d runs from point 0 to point n-1. The + face is on the "
                                 "left of d, and the tip frames and the `end` numbers in `summary.json` follow it.")
    faces: str = key("open", choices=FACES, doc="`open`: traction free, with no contact condition (the faces may "
                     "interpenetrate). `frictionless`: non-penetration w + gap >= 0, no friction. `slip`: "
                     "non-penetration, and the tangential jump [u].t is prescribed. `coulomb`: non-penetration and "
                     "Coulomb friction, |t_t| <= `cohesion` + `friction` (-t_n) (see \"Coulomb faces\" below).")
    slip: float = key(0.0, unit="m", only_with=("faces", "slip"), doc="Prescribed [u].t = u(+) - u(-) along d. "
                      "The load factor scales it.", limit=Limit(hi=MAX_STRAIN, of="L", why=_SMALL))
    gap: float = key(0.0, unit="m", range=NON_NEGATIVE, doc="Initial normal gap g. It acts on `frictionless`, "
                     "`slip` and `coulomb` faces. It is accepted on `open` faces, where it has no effect.",
                     limit=Limit(hi=MAX_STRAIN, of="L", why=_SMALL))
    friction: float = key(0.0, range=NON_NEGATIVE, only_with=("faces", "coulomb"), required_with=("faces", "coulomb"),
                          doc="Coulomb coefficient mu of the faces and of the wings the fracture grows. mu = 0 (with "
                              "`cohesion` 0) gives the `frictionless` result.",
                          limit=Limit(hi=MAX_FRICTION, why="measured coefficients lie below about 1.5; rock's, by "
                                                            "Byerlee's rule, at 0.6-0.85"))
    cohesion: float = key(0.0, unit="Pa", range=NON_NEGATIVE, only_with=("faces", "coulomb"),
                          doc="Cohesion c of the Coulomb bound, on the faces and the wings: the shear traction closed "
                              "faces carry without slipping at zero normal traction. The load factor does not scale "
                              "it.",
                          limit=Limit(hi=MAX_STRAIN, of="E", why=_SMALL))
    pressure: float = key(0.0, unit="Pa", range=NON_NEGATIVE,
                          doc="Fluid pressure p inside the fracture and the wings it grows. It pushes both faces "
                              "apart on every kind of face: the total face traction is the contact traction - p n, "
                              "and contact and friction act on the contact (effective) traction. Connected "
                              "fractures share the highest pressure among them (`propagation.connect_pressure`). "
                              "The load factor scales it with `load = \"scale\"` and `\"pressure\"` (see \"Fluid "
                              "pressure\" below).",
                          limit=Limit(hi=MAX_STRAIN, of="E", why=_SMALL))
    grow: bool = key(True, doc="Whether this fracture's tips may grow wing cracks.")
    slip_profile: str = key("uniform", choices=SLIP_PROFILES, only_with=("faces", "slip"), added=True,
                            doc="`uniform`: the same slip everywhere, which acts as a dislocation at the tips, so K "
                                "depends on `mesh.tip_size`. `elliptic`: slip·sqrt(1 - (2s/L - 1)^2) along the arc "
                                "length s of a fracture of length L, which gives a mesh-independent KII.")

    @property
    def length(self) -> float:
        """Arc length (m)."""
        return float(np.linalg.norm(np.diff(self.points, axis=0), axis=1).sum())


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
    by the load factor. The file's keys are BC_KEYS.
    """

    kind: str
    value: tuple[float, float]
    at: tuple[float, float] | None = None
    on: str | None = None
    components: tuple[bool, bool] = (True, True)


@dataclass(frozen=True)
class Body:
    """Body force; acts through material.density (with density 0 there is none)."""

    gravity: tuple[float, float] = key((0.0, 0.0), unit="m/s^2", doc="Body force density·gravity (none when "
                                       "`material.density` is 0). It is not scaled by the load factor.",
                                       limit=Limit(hi=MAX_STRAIN, of="E / (density L)",
                                                   why="the weight of the domain, density |g| L, below "
                                                       f"{MAX_STRAIN:g} E"))


_IN_SITU = ("Initial (in-situ) stress sigma0, uniform, compression < 0. It is not scaled by the load factor. The "
            "total stress is sigma0 + C:eps(u), and u is measured from the in-situ state. Reported stresses and "
            "SIFs are totals.")


@dataclass(frozen=True)
class Stress:
    """Initial (in situ) stress in Pa, compression < 0. Not scaled."""

    sxx: float = key(0.0, unit="Pa", doc=_IN_SITU, limit=Limit(hi=MAX_STRAIN, of="E", why=_SMALL))
    syy: float = key(0.0, unit="Pa", doc="As `sxx`.", limit=Limit(hi=MAX_STRAIN, of="E", why=_SMALL))
    sxy: float = key(0.0, unit="Pa", doc="As `sxx`.", limit=Limit(hi=MAX_STRAIN, of="E", why=_SMALL))

    def tensor(self) -> np.ndarray:
        """The 2x2 stress tensor (Pa)."""
        return np.array([[self.sxx, self.sxy], [self.sxy, self.syy]])


@dataclass(frozen=True)
class MeshOptions:
    """Mesh sizing."""

    size: float = key(unit="m", range=POSITIVE, doc="Target element size away from the fractures.",
                      limit=Limit(hi=1.0, of="L", why="an element no larger than the domain"),
                      rule=f"at most about {MAX_ELEMENTS:,} triangles (area / (sqrt(3)/4 · size^2))")
    tip_size: float = key(unit="m", range=POSITIVE, doc="Radius h of the structured crack-tip rosette. The "
                          "quarter-point elements sit next to the tip.",
                          rule=f"< `size`, < the shortest fracture segment, >= {MIN_TIP_FRACTION:g} L; its rosette "
                               "must stay clear of the boundary and of other fractures")
    adaptive: bool = key(True, doc="`run` only: each step's mesh is sized from the previous step's error estimate. "
                         "With `false` the sizes are fixed, and `run` remeshes step after step only a circle around "
                         "the growing fractures (its patch): outside it the mesh and its factorisation are reused.")
    sectors: int = key(32, range=Range(8, MAX_SECTORS, note=" (32 recommended)"), added=True,
                       doc="Triangles per tip rosette. Displacement correlation's KII error is 2.5 % at 8 sectors, "
                           "0.7 % at 16 and 0.3 % at 32. Use fewer than 16 only for convergence studies.")


@dataclass(frozen=True)
class Propagation:
    """Growth control (only `run` reads it)."""

    length: float = key(Ref("mesh.tip_size"), unit="m", range=POSITIVE,
                        rule="at least L_min = 0.4 `mesh.tip_size` (propagation/growth_law.length_problem)",
                        doc="Lmax: the longest advance of any tip in one step. Under L_min no kinked tip could "
                            "ever grow (a kinked tip never advances less than L_min), so `check` refuses it, naming "
                            "the smallest length that works. Every length from L_min up works: a wing's rosette is "
                            "then min(`tip_size`, 0.75 L) >= 0.3 `tip_size`, and a length under 0.75 `tip_size`, "
                            "whose next step lands within the join distance (1.5 `tip_size`) of the wing's own "
                            "kink, goes straight on there when the mesher has room for the rosette.",
                        limit=Limit(hi=1.0, of="L", why="no step longer than the domain"))
    steps: int = key(35, range=NON_NEGATIVE, doc="The most propagation steps. A run whose every tip joined "
                     "another fracture or reached the boundary is `finished` earlier. With `0`, `run` "
                     "does nothing and says so (`stopped: propagation.steps = 0 ...`; use `sif`).")
    alpha: float = key(0.35, range=POSITIVE, doc="The growth-law exponent: L_i = Lmax (G_i / max G)^alpha over the "
                       "tips with K_eq >= KIc (relative tolerance 1e-3). A tip whose L_i < 0.4·`mesh.tip_size` does "
                       "not advance, unless it grows straight on.")
    load: str = key("scale", choices=LOADS, doc="`scale`: one load factor multiplies every bc value, every "
                    "fracture slip and every fracture pressure. It starts at 0, and each step it rises to the "
                    "smallest factor at which the first tip reaches KIc, never below the previous step's. "
                    "`pressure` (injection): the factor, found the same way, multiplies the fracture pressures "
                    "only; bc values, slip, the in-situ stress and gravity stay at factor 1, and the critical "
                    "factor times a fracture's `pressure` is its critical injection pressure. `fixed`: the factor "
                    "is 1, and the run stops when no tip reaches KIc.",
                    rule="`pressure` needs a fracture with `pressure` > 0")
    max_load_factor: float = key(100.0, range=POSITIVE, added=True,
                                 doc="With `load = \"scale\"` or `\"pressure\"`, the run stops (\"no tip reaches "
                                     "KIc below the load factor limit\") if the critical factor would exceed this.",
                                 limit=Limit(hi=1e9, why="a larger factor means loads in the wrong unit; the search "
                                                         "doubles the factor, 30 solves up to 1e9"))
    sif: str = key("correlation", choices=SIFS, added=True,
                   doc="Which SIFs drive growth (the critical load, the kink angle theta, K_eq and G): displacement "
                       "correlation (the paper's) or the interaction integral (at a tip where it has no room, "
                       "correlation). Both are always reported. Use `\"interaction\"` for nearly incompressible "
                       "plane strain (nu above about 0.495), where correlation locks; see the README.")
    connect_pressure: bool = key(True, doc="Fractures joined through a T-junction, linked tip to tip or "
                                 "crossing are hydraulically connected: after each step's growth every connected "
                                 "group takes "
                                 "the highest pressure among its fractures, from the next step on. `false`: each "
                                 "fracture keeps its own `pressure`.")


# The layouts that are not a dataclass's: the top level, [domain], [[bc]].

TOP_KEYS = (
    Key("title", STRING, "", default_doc="the file name without `.toml` (`Case.from_dict` gives `\"\"`)",
        doc="The name shown in `check`, in pictures and in `summary.json`.",
        limit=Limit(hi=200, why="one line of a picture's title"),
        rule="no control characters (newline, tab, NUL)"),
    Key("material", TABLE, doc="See below."),
    Key("domain", TABLE, doc="See below."),
    Key("fractures", TABLES, None, default_doc="none", doc="Pre-existing fractures. A case with no fractures is valid.",
        rule=f"at most {MAX_ITEMS} entries"),
    Key("bc", TABLES, None, default_doc="none", rule=f"at most {MAX_ITEMS} entries",
        doc="Boundary conditions, in file order. Without displacement conditions the case is statically "
            "undetermined."),
    Key("body", TABLE, None, default_doc="gravity 0", doc="Body force."),
    Key("stress", TABLE, None, default_doc="all 0", doc="Initial (in-situ) stress."),
    Key("mesh", TABLE, doc="Mesh sizes."),
    Key("propagation", TABLE, None, default_doc="all defaults", doc="Growth control. Only `run` reads it."),
)

SHAPE = Key("shape", STRING, choices=SHAPES, doc="Which of the keys below the table takes.")
SHAPE_KEYS = {
    "disc": (Key("center", POINT, unit="m", doc="The centre."),
             Key("radius", NUMBER, unit="m", range=POSITIVE, doc="The radius.")),
    "rectangle": (Key("corner", POINT, unit="m", doc="The lower left corner [x0, y0]."),
                  Key("size", POINT, unit="m", range=POSITIVE, parts=("width", "height"), doc="[width, height].")),
    "polygon": (Key("points", POINTS, unit="m", min_points=3, noun="a polygon",
                    doc="The vertices, counter-clockwise.", rule=f"at most {MAX_ITEMS} points"),),
}

_BC_VALUE = "Global x and y components."
BC_KEYS = (
    Key("at", POINT, None, "m", doc="A boundary point. It becomes a mesh node, and duplicate points share one node.",
        rule="within 1e-9 L of the boundary, and not on a fracture (a mouth): that would be ambiguous"),
    Key("on", STRING, None, doc="A boundary name of the domain (see `[domain]`). An unknown name gets a list of the "
                                "names and a suggestion."),
    Key("force", POINT, None, "N/m", doc=_BC_VALUE, rule="only with `at`",
        limit=Limit(hi=MAX_STRAIN, of="E L", why=_SMALL)),
    Key("traction", POINT, None, "Pa", doc=_BC_VALUE, rule="only with `on`",
        limit=Limit(hi=MAX_STRAIN, of="E", why=_SMALL)),
    Key("displacement", POINT, None, "m", doc="Both components prescribed. Works with `at` or `on`.",
        limit=Limit(hi=MAX_STRAIN, of="L", why=_SMALL)),
    Key("displacement_x", NUMBER, None, "m", doc="One component prescribed. Giving both equals `displacement`. "
        "Neither may be combined with `displacement`.", limit=Limit(hi=MAX_STRAIN, of="L", why=_SMALL)),
    Key("displacement_y", NUMBER, None, "m", doc="As `displacement_x`.",
        limit=Limit(hi=MAX_STRAIN, of="L", why=_SMALL)),
)
BC_PLACES = ("at", "on")
BC_CONDITIONS = tuple(k.name for k in BC_KEYS if k.name not in BC_PLACES)

#: Every table of a case, in reading order: what the reader reads and the
#: reference documents ([domain]: every shape's keys).
DESCRIPTION = {
    "top": TOP_KEYS, "material": keys_of(Material),
    "domain": (SHAPE,) + tuple(k for keys in SHAPE_KEYS.values() for k in keys),
    "fractures": keys_of(Fracture), "bc": BC_KEYS, "body": keys_of(Body), "stress": keys_of(Stress),
    "mesh": keys_of(MeshOptions), "propagation": keys_of(Propagation),
}


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
        """Read and check a case file. A file that is not a regular one (a
        directory, a FIFO, a device), unreadable files and TOML syntax errors
        are CaseError too, keyed by the file name."""
        path = Path(path)
        raw = _read_file(path)
        try:
            # "utf-8-sig": a byte-order mark (Windows editors write one) is not TOML, but not the
            # user's text either: dropped, not refused as an invalid statement at line 1, column 1
            text = raw.decode("utf-8-sig")
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
        """Fracture ends strictly inside the domain and on no fracture (an end
        on the boundary is an edge crack's mouth, an end on a fracture a
        junction: neither is a tip), in fracture order, end 0 before end 1."""
        tol = REL_TOL * self.length_scale
        joined = admissibility.joined_ends(self.domain, self.fracture_points())
        out = []
        for i, f in enumerate(self.fractures):
            for end, p in ((0, f.points[0]), (1, f.points[-1])):
                if not self.domain.on_boundary(p, tol) and (i, end) not in joined:
                    out.append(Tip(i, end, (float(p[0]), float(p[1]))))
        return out

    def junctions(self) -> list[tuple[float, float]]:
        """The points where fractures meet (an end on a fracture, ends met end
        to end, a crossing), as the mesher joins them."""
        net = admissibility.joined(self.domain, self.fracture_points())
        return sorted((float(x), float(y)) for x, y in net.node_points())

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


_FILE_KINDS = ((stat.S_ISDIR, "a directory"), (stat.S_ISFIFO, "a FIFO"), (stat.S_ISCHR, "a character device"),
               (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket"))


def _read_file(path: Path) -> bytes:
    """At most MAX_FILE_BYTES + 1 bytes of a regular file. Opened without
    blocking and checked before reading: a FIFO would wait for a writer
    forever, a device never ends."""
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK)
    except OSError as err:
        raise CaseError(str(path), f"cannot read: {err.strerror or err}") from None
    mode = os.fstat(fd).st_mode
    if not stat.S_ISREG(mode):
        os.close(fd)
        kind = next((name for test, name in _FILE_KINDS if test(mode)), "not a file")
        raise CaseError(str(path), f"not a regular file ({kind}): a case is a TOML file")
    with os.fdopen(fd, "rb") as fh:
        try:
            raw = fh.read(MAX_FILE_BYTES + 1)
        except OSError as err:
            raise CaseError(str(path), f"cannot read: {err.strerror or err}") from None
    if len(raw) > MAX_FILE_BYTES:
        raise CaseError(str(path), f"too large for a case file (over {MAX_FILE_BYTES} bytes)")
    return raw


# ---------------------------------------------------------------- the reader


def _scalar(v):
    """A numpy scalar (np.float32, np.int64, np.bool_: what arrays hand a Python user) as the
    Python value a TOML file would have given; anything else as it is."""
    return v.item() if isinstance(v, np.generic) and v.shape == () else v


def _what(v) -> str:
    v = _scalar(v)
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
    v = _scalar(v)
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


def _as_integer(v, key: str) -> int:
    v = _scalar(v)
    if isinstance(v, bool) or not isinstance(v, int):
        raise CaseError(key, f"expected an integer, got {_what(v)}")
    return v


def _as_boolean(v, key: str) -> bool:
    v = _scalar(v)
    if not isinstance(v, bool):
        raise CaseError(key, f"expected true or false, got {_what(v)}")
    return v


def _as_string(v, key: str) -> str:
    if not isinstance(v, str):
        raise CaseError(key, f"expected a string, got {_what(v)}")
    return v


def _as_points(v, key: str) -> np.ndarray:
    if not isinstance(v, list):
        raise CaseError(key, f"expected an array of [x, y], got {_what(v)}")
    if len(v) > MAX_ITEMS:
        raise CaseError(key, f"at most {MAX_ITEMS} points, got {len(v)}")
    pts = [_as_point(p, f"{key}[{i}]") for i, p in enumerate(v)]
    return np.array(pts, dtype=float).reshape(-1, 2)


def _as_tables(v, key: str) -> list[_Table]:
    if not isinstance(v, list):
        raise CaseError(key, f"expected an array of tables ([[{key}]]), got {_what(v)}")
    if len(v) > MAX_ITEMS:
        raise CaseError(key, f"at most {MAX_ITEMS} entries, got {len(v)}")
    return [_Table(item, f"{key}[{i}]") for i, item in enumerate(v)]


class _Table:
    """A TOML table being read: knows its key path, reads its keys by their Keys."""

    def __init__(self, data, path: str):
        if not isinstance(data, dict):
            raise CaseError(path, f"expected a table, got {_what(data)}")
        self.data = data
        self.path = path

    def key(self, k: str) -> str:
        return f"{self.path}.{k}" if self.path else k

    def refuse_unknown(self, keys) -> None:
        """Refuse any key not among `keys`, suggesting the closest one."""
        allowed = [k.name for k in keys]
        for k in self.data:
            if not isinstance(k, str):   # Case.from_dict: a TOML key is always a string
                raise CaseError(self.key(repr(k)), f"unknown key (keys are strings, got {_what(k)})")
            if k not in allowed:
                near = difflib.get_close_matches(k, allowed, n=1)
                hint = f" (did you mean {near[0]}?)" if near else ""
                raise CaseError(self.key(k), f"unknown key{hint}")

    def read(self, keys, known: dict | None = None) -> dict:
        """{name: value} of every Key, checked, in order. `known` holds what
        was read before: the scales a Limit names and the keys a Ref names."""
        self.refuse_unknown(keys)
        values: dict = {}
        for k in keys:
            values[k.name] = self.value(k, values, known or {})
        return values

    def value(self, k: Key, values: dict | None = None, known: dict | None = None):
        """Key k's value, converted and checked (`values`: the table's keys
        read before it), or its default."""
        key = self.key(k.name)
        if k.name not in self.data:
            if k.default is REQUIRED:
                raise CaseError(key, "missing (required table)" if k.type == TABLE else "missing (required)")
            if k.required_with is not None and (values or {}).get(k.required_with[0]) == k.required_with[1]:
                other, want = k.required_with
                raise CaseError(key, f'missing (required with {other} = "{want}")')
            if isinstance(k.default, Ref):
                return known[k.default.key]
            if k.type == TABLE:  # an optional table left out reads as an empty one
                return _Table({}, key)
            return [] if k.type == TABLES else k.default
        v = _READERS[k.type](self.data[k.name], key)
        k.check(v, key, values or {}, known or {})
        return v


_READERS = {NUMBER: _as_number, INTEGER: _as_integer, BOOLEAN: _as_boolean, STRING: _as_string, POINT: _as_point,
            POINTS: _as_points, TABLE: _Table, TABLES: _as_tables}


# ---------------------------------------------------------------- rules across keys


def _parse_domain(t: _Table):
    """Check the domain table and build the meshing.Domain."""
    t.refuse_unknown(DESCRIPTION["domain"])
    shape = t.value(SHAPE)
    keys = SHAPE_KEYS[shape]
    for k in t.data:
        if k != "shape" and k not in [s.name for s in keys]:
            raise CaseError(t.key(k), f'not a key of shape "{shape}" (it takes {", ".join(s.name for s in keys)})')
    geo = t.read((SHAPE,) + keys)
    del geo["shape"]
    if shape == "disc":
        _check_scale(2 * geo["radius"], np.abs(geo["center"]).max(), t.key("radius"), t.key("center"))
    elif shape == "rectangle":
        _check_scale(max(geo["size"]), np.abs(geo["corner"]).max(), t.key("size"), t.key("corner"))
    else:
        pts = geo["points"]
        # before _check_polygon, whose products would overflow
        with np.errstate(over="ignore"):
            extent = float(np.ptp(pts, axis=0).max())
        _check_scale(extent, np.abs(pts).max(), t.key("points"), t.key("points"))
        _check_polygon(pts, t.key("points"))
    try:
        return Domain(shape, **geo)
    except ValueError as err:  # anything meshing refuses that the checks above let through
        raise CaseError(t.path, str(err)) from None


def _refuse(problem: admissibility.Problem | None) -> None:
    """The mesher's rules speak in the case file's keys: a problem is the case's error."""
    if problem is not None:
        raise CaseError(problem.key, problem.message)


def _check_scale(size: float, offset: float, size_key: str, offset_key: str) -> None:
    _refuse(admissibility.scale(size, offset, size_key, offset_key))


def _check_polygon(pts: np.ndarray, key: str) -> None:
    _refuse(admissibility.polygon(pts, key))


def _parse_bc(t: _Table, boundary_names, known: dict) -> BC:
    """One place and one condition; displacement_x and displacement_y
    together are one displacement condition."""
    t.refuse_unknown(DESCRIPTION["bc"])
    if all(p in t.data for p in BC_PLACES):
        raise CaseError(t.path, "give one place: either at (a point) or on (a boundary), not both")
    if not any(p in t.data for p in BC_PLACES):
        raise CaseError(t.path, "missing place: give at = [x, y] or on = \"<boundary>\"")
    given = [c for c in BC_CONDITIONS if c in t.data]
    if "displacement" in t.data:
        for c in ("displacement_x", "displacement_y"):
            if c in t.data:
                raise CaseError(t.key(c), "conflicts with displacement (give displacement, or displacement_x / displacement_y)")
    kinds = {c.split("_")[0] for c in given}
    if not given:
        raise CaseError(t.path, "no condition: give one of " + ", ".join(BC_CONDITIONS))
    if len(kinds) > 1:
        raise CaseError(t.path, "two conditions (" + " and ".join(given) + "): each [[bc]] holds one")
    kind = kinds.pop()
    v = t.read(DESCRIPTION["bc"], known)
    at, on = v["at"], v["on"]
    if on is not None:
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
        return BC(kind, v[kind], at=at, on=on)
    if v["displacement"] is not None:
        return BC("displacement", v["displacement"], at=at, on=on)
    ux, uy = v["displacement_x"], v["displacement_y"]
    return BC("displacement", (ux or 0.0, uy or 0.0), at=at, on=on, components=(ux is not None, uy is not None))


def _parse_mesh(t: _Table, known: dict) -> MeshOptions:
    mesh = MeshOptions(**t.read(DESCRIPTION["mesh"], known))
    if mesh.tip_size >= mesh.size:
        raise CaseError(t.key("tip_size"), f"must be smaller than mesh.size ({mesh.tip_size:g} >= {mesh.size:g})")
    return mesh


def _scales(material: Material, domain) -> dict:
    """What Limits scale by: E, L (the domain's length scale) and their products."""
    E, L = material.E, float(domain.length_scale())
    weight = material.density * L  # may underflow to 0: no body force then
    return {"E": E, "L": L, "E L": E * L, "E / (density L)": E / weight if weight > 0 else math.inf}


def _check_mesh_against_domain(mesh: MeshOptions, domain) -> None:
    """Sizes the mesher can honour in this domain: not too many triangles, a
    rosette well above the geometric tolerance."""
    cells = domain.area() / (math.sqrt(3) / 4 * mesh.size**2)
    if cells > MAX_ELEMENTS:
        raise CaseError("mesh.size", f"{mesh.size:g} m asks for about {cells:.2g} elements in this domain of "
                                     f"{domain.area():.4g} m^2 (at most {MAX_ELEMENTS:.2g}): use a larger size")
    _refuse(admissibility.tip_size(mesh.tip_size, domain))


# ---------------------------------------------------------------- the case


def _parse_case(d: dict, source: Path | None) -> Case:
    top = _Table(d, "")
    top.refuse_unknown(DESCRIPTION["top"])
    section = {k.name: k for k in DESCRIPTION["top"]}  # each read in its turn: errors in reading order
    title = top.value(section["title"])
    bad = next((c for c in title if unicodedata.category(c) in ("Cc", "Zl", "Zp")), None)
    if bad is not None:
        raise CaseError("title", f"one line of text, without control characters (it holds {ascii(bad)} at "
                                 f"character {title.index(bad) + 1})")

    material = Material(**top.value(section["material"]).read(DESCRIPTION["material"]))
    domain = _parse_domain(top.value(section["domain"]))
    L = float(domain.length_scale())
    tol = REL_TOL * L
    known = _scales(material, domain)

    fr_tables = top.value(section["fractures"])
    parsed = [ft.read(DESCRIPTION["fractures"], known) for ft in fr_tables]
    for ft, f in zip(fr_tables, parsed):
        _refuse(admissibility.fracture(f["points"], ft.key("points"), domain))
    _refuse(admissibility.fractures_meet(domain, [f["points"] for f in parsed]))
    for f in parsed:
        f["points"].setflags(write=False)
    fractures = tuple(Fracture(**f) for f in parsed)
    _check_slip_junctions(fractures, domain)

    bc_tables = top.value(section["bc"])
    bcs = tuple(_parse_bc(bt, domain.boundary_names(), known) for bt in bc_tables)
    for bt, bc in zip(bc_tables, bcs):
        if bc.at is not None:
            _refuse(admissibility.bc_point(bc.at, bt.key("at"), domain, [f.points for f in fractures]))
    _check_bc_conflicts(bcs, domain, tol)

    # gravity with density 0 (the contract's example) is no body force: allowed
    body = Body(**top.value(section["body"]).read(DESCRIPTION["body"], known))
    stress = Stress(**top.value(section["stress"]).read(DESCRIPTION["stress"], known))

    mesh = _parse_mesh(top.value(section["mesh"]), known)
    _check_mesh_against_domain(mesh, domain)
    at = [(bt.key("at"), bc.at) for bt, bc in zip(bc_tables, bcs) if bc.at is not None]
    _refuse(admissibility.case_geometry(domain, [f.points for f in fractures], [p for _, p in at],
                                        [k for k, _ in at], mesh.tip_size))
    known["mesh.tip_size"] = mesh.tip_size  # a Ref: the default of propagation.length
    propagation = Propagation(**top.value(section["propagation"]).read(DESCRIPTION["propagation"], known))
    problem = length_problem(propagation.length, mesh.tip_size)
    if problem is not None:
        raise CaseError("propagation.length", problem)
    if propagation.load == "pressure" and not any(f.pressure > 0 for f in fractures):
        raise CaseError("propagation.load", '"pressure" scales the fracture pressures, but no fracture has a '
                                            "pressure above 0 (give fractures[i].pressure)")

    _check_statically_determined(bcs, domain)

    return Case(title, material, domain, fractures, bcs, body, stress, mesh, propagation, source)


# ---------------------------------------------------------------- geometry checks
# The geometric admissibility of a case (sizes, positions, polygon, fractures,
# points, rosettes): one block, kept apart from the reading above.


def _check_slip_junctions(fractures, domain) -> None:
    """Two fractures with prescribed slip do not meet: at their junction the
    node copies' jumps sum to zero around it, so the slip rows of both
    fix more components than the copies have (the pair system is singular)."""
    slip = [i for i, f in enumerate(fractures) if f.faces == "slip"]
    if len(slip) < 2:
        return
    net = admissibility.joined(domain, [f.points for f in fractures])
    for members in net.nodes.values():
        met = sorted({f for f, _ in members if fractures[f].faces == "slip"})
        if len(met) > 1:
            f, v = members[0]
            x = net.polylines[f][v]
            raise CaseError(f"fractures[{met[1]}].faces", f'"slip" fractures[{met[1]}] meets "slip" '
                            f"fractures[{met[0]}] at ({x[0]:.6g}, {x[1]:.6g}): two prescribed slips over-determine "
                            "the faces' jumps at a junction; give one of them other faces")


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
