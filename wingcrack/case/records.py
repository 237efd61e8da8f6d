"""The parts of a case (material, fracture, tip, boundary condition, body
force, in-situ stress, mesh sizes, growth control), each a frozen dataclass
whose fields carry their Keys. Units are SI (m, Pa, N; a point force is N per
metre of thickness); points are (x, y) float64."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from wingcrack.case.bounds import (FACES, LOADS, MAX_COMPRESSIBILITY_E, MAX_ELEMENTS, MAX_FRICTION, MAX_SECTORS,
                                   MAX_STRAIN, MAX_TIME, MIN_TIP_FRACTION, PLANES, SIFS, SLIP_PROFILES,
                                   WATER_COMPRESSIBILITY)
from wingcrack.case.keys import NON_NEGATIVE, POSITIVE, Limit, Range, Ref, key
from wingcrack.face_law import FaceLaw

SMALL = "beyond it strains are not small and linear elasticity fails"


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
                      "The load factor scales it.", limit=Limit(hi=MAX_STRAIN, of="L", why=SMALL))
    gap: float = key(0.0, unit="m", range=NON_NEGATIVE, doc="Initial normal gap g. It acts on `frictionless`, "
                     "`slip` and `coulomb` faces. It is accepted on `open` faces, where it has no effect.",
                     limit=Limit(hi=MAX_STRAIN, of="L", why=SMALL))
    friction: float = key(0.0, range=NON_NEGATIVE, only_with=("faces", "coulomb"), required_with=("faces", "coulomb"),
                          doc="Coulomb coefficient mu of the faces and of the wings the fracture grows. mu = 0 (with "
                              "`cohesion` 0) gives the `frictionless` result.",
                          limit=Limit(hi=MAX_FRICTION, why="measured coefficients lie below about 1.5; rock's, by "
                                                            "Byerlee's rule, at 0.6-0.85"))
    cohesion: float = key(0.0, unit="Pa", range=NON_NEGATIVE, only_with=("faces", "coulomb"),
                          doc="Cohesion c of the Coulomb bound, on the faces and the wings: the shear traction closed "
                              "faces carry without slipping at zero normal traction. The load factor does not scale "
                              "it.",
                          limit=Limit(hi=MAX_STRAIN, of="E", why=SMALL))
    pressure: float = key(0.0, unit="Pa", range=NON_NEGATIVE,
                          doc="Fluid pressure p inside the fracture and the wings it grows. It pushes both faces "
                              "apart on every kind of face: the total face traction is the contact traction - p n, "
                              "and contact and friction act on the contact (effective) traction. Connected "
                              "fractures share the highest pressure among them (`propagation.connect_pressure`). "
                              "The load factor scales it with `load = \"scale\"` and `\"pressure\"` (see \"Fluid "
                              "pressure\" below).",
                          limit=Limit(hi=MAX_STRAIN, of="E", why=SMALL))
    grow: bool = key(True, doc="Whether this fracture's tips may grow wing cracks.")
    slip_profile: str = key("uniform", choices=SLIP_PROFILES, only_with=("faces", "slip"), added=True,
                            doc="`uniform`: the same slip everywhere, which acts as a dislocation at the tips, so K "
                                "depends on `mesh.tip_size`. `elliptic`: slip·sqrt(1 - (2s/L - 1)^2) along the arc "
                                "length s of a fracture of length L, which gives a mesh-independent KII.")

    @property
    def length(self) -> float:
        """Arc length (m)."""
        return float(np.linalg.norm(np.diff(self.points, axis=0), axis=1).sum())

    @property
    def midpoint(self) -> np.ndarray:
        """(2,) the point halfway along the polyline (m)."""
        seg = np.linalg.norm(np.diff(self.points, axis=0), axis=1)
        s = np.r_[0.0, np.cumsum(seg)]
        k = min(int(np.searchsorted(s, 0.5 * s[-1], side="right")) - 1, len(seg) - 1)
        t = (0.5 * s[-1] - s[k]) / seg[k] if seg[k] > 0 else 0.0
        return self.points[k] + t * (self.points[k + 1] - self.points[k])

    @property
    def law(self) -> FaceLaw:
        """The face law these keys give (faces, gap, slip, slip_profile,
        friction, cohesion, pressure): the one record the run carries."""
        return FaceLaw.of(self)


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

    sxx: float = key(0.0, unit="Pa", doc=_IN_SITU, limit=Limit(hi=MAX_STRAIN, of="E", why=SMALL))
    syy: float = key(0.0, unit="Pa", doc="As `sxx`.", limit=Limit(hi=MAX_STRAIN, of="E", why=SMALL))
    sxy: float = key(0.0, unit="Pa", doc="As `sxx`.", limit=Limit(hi=MAX_STRAIN, of="E", why=SMALL))

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
                        rule="at least L_min = 0.4 `mesh.tip_size` (wingcrack/shortest_advance.length_problem)",
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
                    "is 1, and the run stops when no tip reaches KIc. `injection`: the `[injection]` table's pump "
                    "drives the run in time; every other load stays as given, and the injected network's "
                    "pressure follows from its fluid mass (see \"Injection\" below); the load factor is that "
                    "pressure in Pa.",
                    rule="`pressure` needs a fracture with `pressure` > 0; `injection` needs an `[injection]` table")
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


@dataclass(frozen=True)
class Injection:
    """A pump into one fracture (propagation.load = "injection"): a constant
    rate or a schedule of piecewise constant rates, and the fluid. Volumes
    are per metre of thickness, at the fluid's density at
    `initial_pressure`."""

    fracture: int = key(range=NON_NEGATIVE, rule="a fracture of the case, with no `pressure` of its own",
                        doc="The fracture injected into. With the fractures it meets (and, with "
                            "`propagation.connect_pressure`, those its wings join later) it is the injected "
                            "network: one pressure, the root of its fluid balance.")
    point: tuple[float, float] = key(None, unit="m", default_doc="the fracture's midpoint",
                                     rule="on the injected fracture",
                                     doc="Where the fluid enters. With one pressure per network it changes no "
                                         "result; it is the flow's source when the flow along the fractures comes.")
    rate: float = key(None, unit="m^3/s per m", range=POSITIVE, rule="`rate`, or `times` with `rates`",
                      limit=Limit(hi=1.0, of="L^2", why="the domain's area each second"),
                      doc="A constant injection rate from t = 0.")
    times: tuple[float, ...] = key(None, unit="s", range=NON_NEGATIVE, rule="strictly increasing, before `end_time`",
                                   limit=Limit(hi=MAX_TIME, why="about 30,000 years"),
                                   doc="The schedule: the start of each interval of `rates` (before the first, "
                                       "nothing is injected).")
    rates: tuple[float, ...] = key(None, unit="m^3/s per m", range=NON_NEGATIVE,
                                   rule="one per entry of `times`, not all 0",
                                   limit=Limit(hi=1.0, of="L^2", why="the domain's area each second"),
                                   doc="The rate from each of `times` to the next (the last one to the end); a "
                                       "zero rate is shut-in: the network keeps its fluid and waits.")
    compressibility: float = key(WATER_COMPRESSIBILITY, unit="1/Pa", range=NON_NEGATIVE,
                                 limit=Limit(hi=MAX_COMPRESSIBILITY_E, of="E^-1",
                                             why="c (p - p0) below 100 at the largest pressure 0.1 E"),
                                 doc="c of the fluid's density, rho = rho0 exp(c (p - p0)) (p0 the "
                                     "`initial_pressure`); 0: incompressible. The default is water's.")
    residual_aperture: float = key(0.0, unit="m", range=NON_NEGATIVE, limit=Limit(hi=MAX_STRAIN, of="L", why=SMALL),
                                   doc="The aperture a pre-existing fracture's faces hold beyond their opening "
                                       "(their roughness): the fluid a closed fracture holds. Wings, fresh cracks "
                                       "whose faces mate, hold none. A fracture's volume is the integral of its "
                                       "normal opening, wings included, plus (this + its `gap` on contact faces) "
                                       "times its pre-existing length.")
    initial_pressure: float = key(0.0, unit="Pa", range=NON_NEGATIVE, limit=Limit(hi=MAX_STRAIN, of="E", why=SMALL),
                                  doc="p0: the pressure of the injected network at t = 0 (it holds its volume at "
                                      "p0), and the density law's reference.")
    end_time: float = key(None, unit="s", range=POSITIVE, default_doc="none",
                          limit=Limit(hi=MAX_TIME, why="about 30,000 years"),
                          doc="The run stops there (`stopped: end_time reached ...`), with a record of the state "
                              "at that time, if propagation.steps do not end it first.")
