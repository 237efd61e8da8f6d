"""The choices and bounds of a case's keys: the allowed strings, the
tolerances, and the largest magnitudes and counts a case may ask for (the
mesher's own bounds come from meshing/admissibility.py, so that what `check`
accepts the mesher meshes)."""
from __future__ import annotations

from meshing import admissibility
from wingcrack.face_law import FACES, SLIP_PROFILES   # noqa: F401 - the face law's choices are the case's

PLANES = ("stress", "strain")
SHAPES = ("disc", "rectangle", "polygon")
LOADS = ("scale", "pressure", "fixed", "injection")
SIFS = ("correlation", "interaction")
#: Relative tolerance (times the domain length scale) for "on the boundary",
#: "touching" and "zero length".
REL_TOL = admissibility.REL_TOL
#: A case file is a page of text; anything larger is refused before parsing
#: (the pairwise checks are quadratic in the points a file lists).
MAX_FILE_BYTES = 1 << 20
#: The domain size (m) the mesher and solver are verified for, and how far
#: from the origin it may lie (in domain sizes): see meshing/admissibility.py.
LENGTH_RANGE = admissibility.LENGTH_RANGE
MAX_OFFSET = admissibility.MAX_OFFSET
MIN_TIP_FRACTION = admissibility.MIN_TIP_FRACTION
#: The most triangles mesh.size may ask for (area / (sqrt(3)/4 size^2)):
#: about 16 million P2 DOFs, more than a direct factorisation holds in a
#: workstation's memory.
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
#: Water's compressibility (1/Pa, at 20 C): the fluid's default.
WATER_COMPRESSIBILITY = 4.5e-10
#: The largest compressibility times E: the fluid's density law is exp(c (p - p0)) with p at most
#: 0.1 E (MAX_STRAIN), so c (p - p0) stays below 100 and the law in floating point (water in granite:
#: c E = 32).
MAX_COMPRESSIBILITY_E = 1000.0
#: The longest time (s) a schedule may name: about 30,000 years.
MAX_TIME = 1e12
#: Keys of the flow along the fractures (a later version), refused by name rather than as unknown
#: ({table: {key: what it is}}): one pressure per connected network is the model here.
NOT_YET = {"injection": {"viscosity": "the fluid's viscosity", "leak_off": "a leak-off coefficient",
                         "pressure": "a given pressure at the injection point"},
           "fractures": {"hydraulic_aperture": "a fixed hydraulic aperture"}}
#: The largest Coulomb coefficient `friction` may be: far above any measured
#: one, and small enough that friction times a stress of 0.1 E stays finite.
MAX_FRICTION = 100.0
