"""The case model (wingcrack/case/) against the contract /work/shared/spec/case-format.md.

`INVALID` lists one bad input per row, each a patch of the valid `BASE` case,
with the key the error must name and a fragment of its reason; test_cli.py
runs the same rows through the command line.
"""
from __future__ import annotations

import copy
import math
import os
import signal
from pathlib import Path

import numpy as np
import pytest

from wingcrack import case_doc
from wingcrack.case import BC, DESCRIPTION, Case, Material, MeshOptions, Propagation, Tip
from wingcrack.errors import CaseError

CASES = sorted((Path(__file__).resolve().parents[2] / "cases").glob("*.toml"))

# A 4 m x 2 m plate: a kinked interior crack, an edge crack from the left side,
# tension on top and bottom, three scalar supports.
BASE = {
    "title": "base",
    "material": {"E": 1.0e10, "nu": 0.25, "KIc": 1.0e6, "plane": "strain"},
    "domain": {"shape": "rectangle", "corner": [0.0, 0.0], "size": [4.0, 2.0]},
    "fractures": [
        {"points": [[1.0, 1.0], [1.5, 1.2], [2.0, 1.0]], "faces": "frictionless"},
        {"points": [[0.0, 0.5], [0.5, 0.5]]},
    ],
    "bc": [
        {"on": "top", "traction": [0.0, 1.0e6]},
        {"on": "bottom", "traction": [0.0, -1.0e6]},
        {"at": [4.0, 1.0], "displacement": [0.0, 0.0]},
        {"at": [2.0, 0.0], "displacement_x": 0.0},
    ],
    "mesh": {"size": 0.2, "tip_size": 0.05},
}

DELETE = object()

# Same plate as a polygon (boundaries edge0 = bottom ... edge3 = left).
_POLYGON = {"shape": "polygon", "points": [[0.0, 0.0], [4.0, 0.0], [4.0, 2.0], [0.0, 2.0]]}
_POLYGON_BC = [
    {"on": "edge2", "traction": [0.0, 1.0e6]},
    {"on": "edge0", "traction": [0.0, -1.0e6]},
    {"at": [4.0, 1.0], "displacement": [0.0, 0.0]},
    {"at": [2.0, 0.0], "displacement_x": 0.0},
]
# An L-shaped (concave) domain, counter-clockwise: the block x < 2, y > 1 is cut away.
_L_SHAPE = {"shape": "polygon", "points": [[0.0, 0.0], [4.0, 0.0], [4.0, 2.0], [2.0, 2.0], [2.0, 1.0], [0.0, 1.0]]}
_DISC = {"shape": "disc", "center": [0.0, 0.0], "radius": 1.0}
_DISC_BC = [
    {"at": [0.0, 1.0], "force": [0.0, -1.0e6]},
    {"at": [0.0, -1.0], "force": [0.0, 1.0e6]},
    {"at": [-1.0, 0.0], "displacement": [0.0, 0.0]},
    {"at": [1.0, 0.0], "displacement_y": 0.0},
]
_DISC_FRACTURE = [{"points": [[-0.1, -0.1], [0.1, 0.1]]}]


def patched(*changes, base=BASE) -> dict:
    """A deep copy of `base` with each (dotted.path, value) set; value DELETE removes.
    List items are addressed by index ("fractures.0.faces"); index len(list) appends."""
    d = copy.deepcopy(base)
    for path, value in changes:
        *head, last = path.split(".")
        node = d
        for part in head:
            node = node[int(part)] if isinstance(node, list) else node[part]
        if isinstance(node, list):
            last = int(last)
        if value is DELETE:
            del node[last]
        elif isinstance(node, list) and last == len(node):
            node.append(copy.deepcopy(value))
        else:
            node[last] = copy.deepcopy(value)
    return d


def bad(id, changes, key, reason):
    return pytest.param(changes, key, reason, id=id)


# (changes, the key the message names, a fragment of the reason)
INVALID = [
    # unknown keys, with suggestions
    bad("top-typo", [("meshh", {"size": 1.0})], "meshh", "unknown key (did you mean mesh?)"),
    bad("mesh-typo", [("mesh", {"size": 0.2, "tip_sise": 0.05})], "mesh.tip_sise", "unknown key (did you mean tip_size?)"),
    bad("material-unknown", [("material.Young", 1.0)], "material.Young", "unknown key"),
    bad("fracture-typo", [("fractures.0.face", "open")], "fractures[0].face", "did you mean faces?"),
    bad("bc-typo", [("bc.2.displacment", [0.0, 0.0])], "bc[2].displacment", "did you mean displacement?"),
    bad("propagation-typo", [("propagation", {"step": 3})], "propagation.step", "did you mean steps?"),
    bad("stress-typo", [("stress", {"sxz": 1.0})], "stress.sxz", "unknown key"),
    bad("body-typo", [("body", {"gravitiy": [0.0, -9.8]})], "body.gravitiy", "did you mean gravity?"),
    bad("domain-other-shape-key", [("domain.radius", 1.0)], "domain.radius", 'not a key of shape "rectangle"'),
    # missing
    bad("no-material", [("material", DELETE)], "material", "missing"),
    bad("no-E", [("material.E", DELETE)], "material.E", "missing"),
    bad("no-KIc", [("material.KIc", DELETE)], "material.KIc", "missing"),
    bad("no-domain", [("domain", DELETE)], "domain", "missing"),
    bad("no-shape", [("domain.shape", DELETE)], "domain.shape", "missing"),
    bad("no-mesh", [("mesh", DELETE)], "mesh", "missing"),
    bad("no-mesh-size", [("mesh.size", DELETE)], "mesh.size", "missing"),
    bad("no-tip-size", [("mesh.tip_size", DELETE)], "mesh.tip_size", "missing"),
    bad("no-fracture-points", [("fractures.0.points", DELETE)], "fractures[0].points", "missing"),
    # types
    bad("E-string", [("material.E", "15e9")], "material.E", "expected a number, got a string"),
    bad("E-bool", [("material.E", True)], "material.E", "expected a number, got a boolean"),
    bad("nu-nan", [("material.nu", math.nan)], "material.nu", "finite"),
    bad("E-inf", [("material.E", math.inf)], "material.E", "finite"),
    bad("point-3d", [("bc.2.at", [4.0, 1.0, 0.0])], "bc[2].at", "expected [x, y]"),
    bad("point-nan", [("fractures.0.points.1", [1.5, math.nan])], "fractures[0].points[1][1]", "finite"),
    bad("vector-string", [("bc.0.traction", "up")], "bc[0].traction", "expected [x, y]"),
    bad("plane-number", [("material.plane", 1)], "material.plane", "expected a string"),
    bad("grow-string", [("fractures.0.grow", "yes")], "fractures[0].grow", "expected true or false"),
    bad("adaptive-int", [("mesh.adaptive", 1)], "mesh.adaptive", "expected true or false"),
    bad("sectors-float", [("mesh.sectors", 16.0)], "mesh.sectors", "expected an integer"),
    bad("steps-bool", [("propagation", {"steps": True})], "propagation.steps", "expected an integer"),
    bad("title-number", [("title", 3)], "title", "expected a string"),
    bad("material-not-table", [("material", 1.0)], "material", "expected a table"),
    bad("fractures-table", [("fractures", {"points": [[1.0, 1.0], [2.0, 1.0]]})], "fractures", "array of tables"),
    bad("bc-item-not-table", [("bc.3", 1.0)], "bc[3]", "expected a table"),
    # material
    bad("E-zero", [("material.E", 0.0)], "material.E", "must be > 0"),
    bad("E-negative", [("material.E", -1e9)], "material.E", "must be > 0"),
    bad("nu-half", [("material.nu", 0.5)], "material.nu", "(-1, 0.5)"),
    bad("nu-minus-one", [("material.nu", -1.0)], "material.nu", "(-1, 0.5)"),
    bad("KIc-zero", [("material.KIc", 0)], "material.KIc", "must be > 0"),
    bad("thickness-zero", [("material.thickness", 0.0)], "material.thickness", "must be > 0"),
    bad("density-negative", [("material.density", -1.0)], "material.density", "must be >= 0"),
    bad("plane-typo", [("material.plane", "strian")], "material.plane", '"stress" | "strain"'),
    # domain
    bad("shape-unknown", [("domain.shape", "circle")], "domain.shape", '"circle" is not one of'),
    bad("disc-no-radius", [("domain", {"shape": "disc", "center": [0.0, 0.0]})], "domain.radius", "missing"),
    bad("disc-no-center", [("domain", {"shape": "disc", "radius": 1.0})], "domain.center", "missing"),
    bad("disc-radius-zero", [("domain", dict(_DISC, radius=0.0))], "domain.radius", "must be > 0"),
    bad("rect-no-size", [("domain.size", DELETE)], "domain.size", "missing"),
    bad("rect-width-zero", [("domain.size", [0.0, 2.0])], "domain.size[0]", "width must be > 0"),
    bad("rect-height-negative", [("domain.size", [4.0, -2.0])], "domain.size[1]", "height must be > 0"),
    bad("polygon-no-points", [("domain", {"shape": "polygon"})], "domain.points", "missing"),
    bad("polygon-two-points", [("domain", {"shape": "polygon", "points": [[0.0, 0.0], [4.0, 0.0]]})],
        "domain.points", "at least 3 points"),
    bad("polygon-clockwise", [("domain", {"shape": "polygon", "points": _POLYGON["points"][::-1]})],
        "domain.points", "counter-clockwise"),
    bad("polygon-bowtie", [("domain", {"shape": "polygon", "points": [[0.0, 0.0], [4.0, 2.0], [4.0, 0.0], [0.0, 2.0]]})],
        "domain.points", "intersects itself"),
    bad("polygon-no-area", [("domain", {"shape": "polygon", "points": [[0.0, 0.0], [4.0, 0.0], [2.0, 0.0]]})],
        "domain.points", "intersects itself"),
    bad("polygon-repeated-point",
        [("domain", {"shape": "polygon", "points": [[0.0, 0.0], [4.0, 0.0], [4.0, 0.0], [4.0, 2.0], [0.0, 2.0]]})],
        "domain.points", "zero length"),
    # fractures
    bad("fracture-one-point", [("fractures.0.points", [[1.0, 1.0]])], "fractures[0].points", "at least 2 points"),
    bad("fracture-zero-segment", [("fractures.0.points", [[1.0, 1.0], [1.0, 1.0], [2.0, 1.0]])],
        "fractures[0].points", "zero length"),
    bad("fracture-self-intersecting", [("fractures.0.points", [[1.0, 1.0], [2.0, 1.5], [2.0, 1.0], [1.0, 1.5]])],
        "fractures[0].points", "intersects itself"),
    # fractures may cross and touch (tests/unit/test_admissibility_network.py), not so:
    bad("fractures-overlapping", [("fractures.2", {"points": [[1.25, 1.1], [1.75, 1.3]]})], "fractures[2].points",
        "runs along fractures[0] from (1.25, 1.1) to (1.5, 1.2)"),
    bad("fractures-crossing-flat", [("fractures.2", {"points": [[1.606341, 1.101356], [2.193659, 0.978644]]})],
        "fractures[2].points", "meets fractures[0] at (1.9, 1.04) at 10 degrees"),
    bad("fracture-end-near-a-vertex", [("fractures.2", {"points": [[1.5, 1.2001], [1.5, 1.6]]})],
        "fractures[2].points[0]", "0.0001 m from fractures[0]: an end on a fracture lies on it"),
    bad("slip-fractures-crossing", [("fractures.0.faces", "slip"), ("fractures.0.slip", 1e-4),
                                    ("fractures.2", {"points": [[1.6, 1.5], [1.9, 0.7]], "faces": "slip",
                                                     "slip": 1e-4})],
        "fractures[2].faces", 'meets "slip" fractures[0] at'),
    bad("fractures-sharing-a-mouth", [("fractures.2", {"points": [[0.0, 0.5], [0.3, 0.9]]})],
        "fractures[2].points[0]", "the end (0, 0.5) on the boundary lies on fractures[1]"),
    bad("fracture-outside", [("fractures.0.points", [[1.0, 1.0], [5.0, 1.0]])], "fractures[0].points[1]",
        "outside the domain"),
    bad("fracture-interior-point-on-boundary", [("fractures.0.points", [[1.0, 1.0], [2.0, 0.0], [3.0, 1.0]])],
        "fractures[0].points[1]", "on the boundary"),
    bad("fracture-along-boundary", [("fractures.1.points", [[0.0, 0.5], [0.0, 1.5]])], "fractures[1].points",
        "along or outside the boundary"),
    bad("fracture-crosses-concave-boundary",
        [("domain", _L_SHAPE), ("bc", _POLYGON_BC[2:] + [{"on": "edge0", "displacement_y": 0.0}]),
         ("fractures", [{"points": [[1.5, 0.8], [3.0, 1.8]]}])],
        "fractures[0].points", "crosses the boundary edge3"),
    bad("faces-unknown", [("fractures.0.faces", "closed")], "fractures[0].faces", '"open" | "frictionless" | "slip"'),
    bad("slip-without-slip-faces", [("fractures.0.slip", 0.001)], "fractures[0].slip", 'only with faces = "slip"'),
    bad("slip-profile-without-slip-faces", [("fractures.0.slip_profile", "elliptic")], "fractures[0].slip_profile",
        'only with faces = "slip"'),
    bad("slip-profile-unknown", [("fractures.0.faces", "slip"), ("fractures.0.slip_profile", "parabolic")],
        "fractures[0].slip_profile", '"uniform" | "elliptic"'),
    bad("gap-negative", [("fractures.0.gap", -1e-4)], "fractures[0].gap", "must be >= 0"),
    # Coulomb faces (issue 14): fractures[0] has frictionless faces in BASE
    bad("coulomb-without-friction", [("fractures.0.faces", "coulomb")], "fractures[0].friction",
        'missing (required with faces = "coulomb")'),
    bad("friction-negative", [("fractures.0.faces", "coulomb"), ("fractures.0.friction", -0.6)],
        "fractures[0].friction", "must be >= 0, got -0.6"),
    bad("friction-nan", [("fractures.0.faces", "coulomb"), ("fractures.0.friction", math.nan)],
        "fractures[0].friction", "finite"),
    bad("friction-inf", [("fractures.0.faces", "coulomb"), ("fractures.0.friction", math.inf)],
        "fractures[0].friction", "finite"),
    bad("friction-string", [("fractures.0.faces", "coulomb"), ("fractures.0.friction", "0.6")],
        "fractures[0].friction", "expected a number, got a string"),
    bad("friction-on-frictionless-faces", [("fractures.0.friction", 0.6)], "fractures[0].friction",
        'only with faces = "coulomb" (faces is "frictionless")'),
    bad("friction-on-open-faces", [("fractures.1.friction", 0.6)], "fractures[1].friction",
        'only with faces = "coulomb" (faces is "open")'),
    bad("friction-on-slip-faces", [("fractures.0.faces", "slip"), ("fractures.0.friction", 0.6)],
        "fractures[0].friction", 'only with faces = "coulomb" (faces is "slip")'),
    bad("cohesion-negative", [("fractures.0.faces", "coulomb"), ("fractures.0.friction", 0.6),
                              ("fractures.0.cohesion", -1.0)], "fractures[0].cohesion", "must be >= 0"),
    bad("cohesion-on-frictionless-faces", [("fractures.0.cohesion", 1e5)], "fractures[0].cohesion",
        'only with faces = "coulomb"'),
    # boundary conditions
    bad("bc-at-and-on", [("bc.2.on", "right")], "bc[2]", "not both"),
    bad("bc-no-place", [("bc.2.at", DELETE)], "bc[2]", "missing place"),
    bad("bc-no-condition", [("bc.2.displacement", DELETE)], "bc[2]", "no condition"),
    bad("bc-two-conditions", [("bc.2.force", [1.0, 0.0])], "bc[2]", "two conditions"),
    bad("bc-displacement-and-x", [("bc.2.displacement_x", 0.0)], "bc[2].displacement_x", "conflicts with displacement"),
    bad("bc-conflicting-entries", [("bc.4", {"at": [2.0, 0.0], "displacement_x": 0.001})], "bc[4]",
        "conflicts with bc[3]"),
    bad("bc-point-inside", [("bc.2.at", [3.9, 1.0])], "bc[2].at", "not on the boundary"),
    bad("bc-point-outside", [("bc.2.at", [4.5, 1.0])], "bc[2].at", "not on the boundary"),
    bad("bc-point-at-crack-mouth", [("bc.3", {"at": [0.0, 0.5], "displacement_x": 0.0})], "bc[3].at", "mouth"),
    bad("bc-unknown-boundary", [("bc.0.on", "rim")], "bc[0].on", 'no boundary named "rim"'),
    bad("bc-boundary-typo", [("bc.0.on", "tpo")], "bc[0].on", "did you mean top?"),
    bad("bc-force-on-boundary", [("bc.0", {"on": "top", "force": [0.0, 1.0]})], "bc[0].force", "acts at a point"),
    bad("bc-traction-at-point", [("bc.0", {"at": [2.0, 2.0], "traction": [0.0, 1.0]})], "bc[0].traction",
        "acts on a boundary"),
    # body
    # mesh
    bad("mesh-size-zero", [("mesh.size", 0.0)], "mesh.size", "must be > 0"),
    bad("tip-size-negative", [("mesh.tip_size", -0.01)], "mesh.tip_size", "must be > 0"),
    bad("tip-size-not-below-size", [("mesh.tip_size", 0.2)], "mesh.tip_size", "smaller than mesh.size"),
    bad("tip-size-vs-segment", [("mesh.size", 1.0), ("mesh.tip_size", 0.51)], "mesh.tip_size",
        "shortest segment of fractures[1]"),
    bad("rosette-reaches-boundary", [("fractures.0.points", [[1.0, 0.04], [2.0, 0.5]])], "mesh.tip_size",
        "reaches the boundary"),
    bad("rosette-reaches-fracture", [("fractures.2", {"points": [[2.03, 1.0], [3.0, 1.0]]})], "mesh.tip_size",
        "fractures[0] end 1 (radius 0.05) reaches fractures[2]"),
    bad("sectors-few", [("mesh.sectors", 4)], "mesh.sectors", "must be >= 8"),
    # propagation
    bad("steps-negative", [("propagation", {"steps": -1})], "propagation.steps", "must be >= 0"),
    bad("length-zero", [("propagation", {"length": 0.0})], "propagation.length", "must be > 0"),
    bad("alpha-zero", [("propagation", {"alpha": 0.0})], "propagation.alpha", "must be > 0"),
    bad("load-unknown", [("propagation", {"load": "ramp"})], "propagation.load", '"scale" | "pressure" | "fixed"'),
    bad("max-load-factor-zero", [("propagation", {"max_load_factor": 0.0})], "propagation.max_load_factor",
        "must be > 0"),
    bad("sif-unknown", [("propagation", {"sif": "j-integral"})], "propagation.sif", '"correlation" | "interaction"'),
    # fluid pressure (issue 15): on every kind of face, so fracture 0 (frictionless) and 1 (open) alike
    bad("pressure-negative", [("fractures.0.pressure", -1e5)], "fractures[0].pressure", "must be >= 0, got -100000"),
    bad("pressure-negative-open", [("fractures.1.pressure", -1.0)], "fractures[1].pressure", "must be >= 0, got -1"),
    bad("pressure-nan", [("fractures.0.pressure", math.nan)], "fractures[0].pressure", "must be a finite number"),
    bad("pressure-inf", [("fractures.1.pressure", math.inf)], "fractures[1].pressure", "must be a finite number"),
    bad("pressure-string", [("fractures.0.pressure", "1e6")], "fractures[0].pressure",
        "expected a number, got a string"),
    bad("pressure-boolean", [("fractures.0.pressure", True)], "fractures[0].pressure",
        "expected a number, got a boolean"),
    bad("load-pressure-without-pressure", [("propagation", {"load": "pressure"})], "propagation.load",
        "no fracture has a pressure above 0"),
    bad("load-pressure-with-zero-pressures", [("propagation", {"load": "pressure"}), ("fractures.0.pressure", 0.0),
                                              ("fractures.1.pressure", 0)], "propagation.load",
        "no fracture has a pressure above 0"),
    bad("connect-pressure-string", [("propagation", {"connect_pressure": "true"})], "propagation.connect_pressure",
        "expected true or false, got a string"),
    bad("connect-pressure-integer", [("propagation", {"connect_pressure": 1})], "propagation.connect_pressure",
        "expected true or false, got a number"),
    # magnitudes no case may ask for: each overflowed or underflowed in the solve
    bad("E-tiny", [("material.E", 1e-300)], "material.E", "must lie within 1000 .. 1e+13 Pa"),
    bad("E-subnormal", [("material.E", 5e-324)], "material.E", "must lie within 1000 .. 1e+13 Pa"),
    bad("E-below-gels", [("material.E", 999.0)], "material.E", "must lie within"),
    bad("E-huge", [("material.E", 1e300)], "material.E", "must lie within"),
    bad("KIc-tiny", [("material.KIc", 1e-300)], "material.KIc", "must lie within 1 .. 1e+09"),
    bad("KIc-huge", [("material.KIc", 1e300)], "material.KIc", "must lie within"),
    bad("density-huge", [("material.density", 1e200)], "material.density", "at most 100000 kg/m^3"),
    bad("gravity-huge", [("material.density", 2700.0), ("body", {"gravity": [0.0, -1e300]})], "body.gravity[1]",
        "at most 0.1 E / (density L) = 8.282e+04 m/s^2"),
    bad("stress-huge", [("stress", {"sxx": -1e300})], "stress.sxx", "at most 0.1 E = 1e+09 Pa in magnitude"),
    bad("stress-over-a-tenth-of-E", [("stress", {"sxy": 1.01e9})], "stress.sxy", "0.1 E"),
    bad("traction-huge", [("bc.0.traction", [1e300, 0.0])], "bc[0].traction[0]", "0.1 E"),
    bad("force-huge", [("domain", _DISC), ("fractures", _DISC_FRACTURE), ("bc", _DISC_BC),
                       ("bc.0.force", [0.0, -1e300])], "bc[0].force[1]", "0.1 E L = 2e+09 N/m"),
    bad("displacement-huge", [("bc.2.displacement", [0.0, 1e300])], "bc[2].displacement[1]", "0.1 L"),
    bad("displacement-x-huge", [("bc.3.displacement_x", -1e300)], "bc[3].displacement_x", "0.1 L"),
    bad("slip-huge", [("fractures.0.faces", "slip"), ("fractures.0.slip", 1e300)], "fractures[0].slip", "0.1 L"),
    bad("slip-huge-on-open-faces", [("fractures.0.slip", 1e300)], "fractures[0].slip", 'only with faces = "slip"'),
    bad("gap-huge", [("fractures.0.gap", 1e300)], "fractures[0].gap", "0.1 L"),
    bad("friction-huge", [("fractures.0.faces", "coulomb"), ("fractures.0.friction", 1e300)],
        "fractures[0].friction", "must be at most 100"),
    bad("cohesion-over-a-tenth-of-E", [("fractures.0.faces", "coulomb"), ("fractures.0.friction", 0.6),
                                       ("fractures.0.cohesion", 1.01e9)], "fractures[0].cohesion",
        "must be at most 0.1 E = 1e+09 Pa"),
    bad("pressure-over-a-tenth-of-E", [("fractures.0.pressure", 1.01e9)], "fractures[0].pressure",
        "must be at most 0.1 E = 1e+09 Pa"),
    bad("pressure-huge", [("fractures.1.pressure", 1e300)], "fractures[1].pressure", "at most 0.1 E"),
    bad("mesh-size-huge", [("mesh.size", 1e300)], "mesh.size", "at most L = 4.472 m"),
    bad("length-huge", [("propagation", {"length": 1e300})], "propagation.length", "at most L = 4.472 m"),
    bad("max-load-factor-huge", [("propagation", {"max_load_factor": 1e300})], "propagation.max_load_factor",
        "at most 1e+09"),
    bad("title-huge", [("title", "x" * 500_000)], "title", "at most 200 characters"),
    # statically undetermined
    bad("no-supports", [("bc", BASE["bc"][:2])], "bc", "translation x, translation y and rotation are free"),
    bad("no-bc-at-all", [("bc", DELETE)], "bc", "statically undetermined"),
    bad("one-pinned-point", [("bc.3", DELETE)], "bc", "rotation about (4, 1) is free"),
    bad("rollers-on-left", [("bc", BASE["bc"][:2] + [{"on": "left", "displacement_x": 0.0}])], "bc",
        "translation y is free"),
    bad("rollers-on-bottom", [("bc", BASE["bc"][:2] + [{"on": "bottom", "displacement_y": 0.0}])], "bc",
        "translation x is free"),
    bad("two-x-rollers", [("bc.2", {"at": [4.0, 1.0], "displacement_x": 0.0})], "bc", "translation y is free"),
    bad("disc-rim-x", [("domain", _DISC), ("fractures", _DISC_FRACTURE),
                       ("bc", _DISC_BC[:2] + [{"on": "rim", "displacement_x": 0.0}])], "bc", "translation y is free"),
]


def _error(d) -> CaseError:
    with pytest.raises(CaseError) as info:
        Case.from_dict(d)
    return info.value


@pytest.mark.parametrize("changes, key, reason", INVALID)
def test_invalid_case_names_key_and_reason(changes, key, reason):
    err = _error(patched(*changes))
    assert err.key == key, str(err)
    assert reason in err.reason, str(err)
    assert str(err) == f"{err.key}: {err.reason}"


def test_base_is_valid():
    case = Case.from_dict(BASE)
    assert case.title == "base"
    assert case.material == Material(E=1.0e10, nu=0.25, KIc=1.0e6, plane="strain", thickness=1.0, density=0.0)
    assert [f.faces for f in case.fractures] == ["frictionless", "open"]
    assert [bc.kind for bc in case.bcs] == ["traction", "traction", "displacement", "displacement"]
    assert case.bcs[3] == BC("displacement", (0.0, 0.0), at=(2.0, 0.0), components=(True, False))
    assert case.source is None


def test_defaults():
    d = patched(("material.plane", DELETE), ("title", DELETE))
    case = Case.from_dict(d)
    assert case.title == ""
    assert case.material.plane == "stress"  # as the contract example
    assert (case.material.thickness, case.material.density) == (1.0, 0.0)
    f = case.fractures[1]
    assert (f.faces, f.slip, f.gap, f.grow, f.slip_profile) == ("open", 0.0, 0.0, True, "uniform")
    assert (f.friction, f.cohesion, f.pressure) == (0.0, 0.0, 0.0)
    assert case.mesh == MeshOptions(size=0.2, tip_size=0.05, adaptive=True, sectors=32)
    assert case.propagation == Propagation(length=0.05, steps=35, alpha=0.35, load="scale", max_load_factor=100.0,
                                           sif="correlation", connect_pressure=True)
    assert case.body.gravity == (0.0, 0.0)
    assert np.all(case.stress.tensor() == 0.0)


def test_optional_sections_are_read():
    d = patched(
        ("material.density", 2700),
        ("body", {"gravity": [0.0, -9.8]}),
        ("stress", {"sxx": -1.0e7, "syy": -2.7e7}),
        ("mesh.adaptive", False),
        ("mesh.sectors", 8),
        ("propagation", {"steps": 0, "length": 0.02, "alpha": 1, "load": "fixed", "max_load_factor": 5,
                         "sif": "interaction"}),
        ("fractures.0.faces", "slip"),
        ("fractures.0.slip", 1e-4),
        ("fractures.0.slip_profile", "elliptic"),
        ("fractures.0.gap", 1e-5),
        ("fractures.0.grow", False),
    )
    case = Case.from_dict(d)
    assert case.material.density == 2700.0 and isinstance(case.material.density, float)
    assert case.body.gravity == (0.0, -9.8)
    assert np.allclose(case.stress.tensor(), [[-1.0e7, 0.0], [0.0, -2.7e7]])
    assert case.mesh == MeshOptions(0.2, 0.05, False, 8)
    assert case.propagation == Propagation(length=0.02, steps=0, alpha=1.0, load="fixed", max_load_factor=5.0,
                                           sif="interaction")
    f = case.fractures[0]
    assert (f.faces, f.slip, f.slip_profile, f.gap, f.grow) == ("slip", 1e-4, "elliptic", 1e-5, False)


def test_coulomb_faces_are_read():
    """friction and cohesion as given, as floats (an integer mu too); a
    coulomb fracture's mu may be 0, the frictionless law."""
    case = Case.from_dict(patched(("fractures.0.faces", "coulomb"), ("fractures.0.friction", 1),
                                  ("fractures.0.cohesion", 2.5e5), ("fractures.0.gap", 1e-5)))
    f = case.fractures[0]
    assert (f.faces, f.friction, f.cohesion, f.gap) == ("coulomb", 1.0, 2.5e5, 1e-5)
    assert isinstance(f.friction, float) and isinstance(f.cohesion, float)
    assert case.fractures[1].faces == "open" and (case.fractures[1].friction, case.fractures[1].cohesion) == (0, 0)
    zero = Case.from_dict(patched(("fractures.0.faces", "coulomb"), ("fractures.0.friction", 0.0))).fractures[0]
    assert (zero.friction, zero.cohesion) == (0.0, 0.0)


def test_zero_friction_and_cohesion_are_no_condition_on_other_faces():
    """As slip = 0.0 on frictionless faces: mu = 0 and c = 0 ask for nothing,
    accepted on any faces; a non-zero value stays an error (INVALID)."""
    for i, faces in enumerate(("frictionless", "open")):
        f = Case.from_dict(patched((f"fractures.{i}.friction", 0.0), (f"fractures.{i}.cohesion", 0))).fractures[i]
        assert (f.faces, f.friction, f.cohesion) == (faces, 0.0, 0.0)


def test_fluid_pressure_is_read():
    """pressure on every kind of face, as a float (an integer too); load =
    "pressure" with one pressurised fracture; connect_pressure false."""
    for faces, extra in (("open", ()), ("frictionless", ()), ("slip", (("fractures.0.slip", 1e-4),)),
                         ("coulomb", (("fractures.0.friction", 0.6),))):
        case = Case.from_dict(patched(("fractures.0.faces", faces), ("fractures.0.pressure", 2_000_000), *extra,
                                      ("propagation", {"load": "pressure", "connect_pressure": False})))
        f = case.fractures[0]
        assert (f.faces, f.pressure) == (faces, 2e6) and isinstance(f.pressure, float)
        assert case.fractures[1].pressure == 0.0
        assert (case.propagation.load, case.propagation.connect_pressure) == ("pressure", False)
    # one pressurised fracture of two is enough for load = "pressure"
    case = Case.from_dict(patched(("fractures.1.pressure", 1.0), ("propagation", {"load": "pressure"})))
    assert [f.pressure for f in case.fractures] == [0.0, 1.0] and case.propagation.connect_pressure is True
    # with the other load modes a pressure is a load like any other, and none is needed
    for load in ("scale", "fixed"):
        assert Case.from_dict(patched(("fractures.0.pressure", 3e5), ("propagation", {"load": load}))).fractures[0] \
            .pressure == 3e5
        assert Case.from_dict(patched(("propagation", {"load": load}))).propagation.load == load


def test_density_without_gravity_is_allowed():
    assert Case.from_dict(patched(("material.density", 2700.0))).material.density == 2700.0


def test_zero_gravity_needs_no_density():
    assert Case.from_dict(patched(("body", {"gravity": [0.0, 0.0]}))).body.gravity == (0.0, 0.0)


def test_displacement_x_and_y_together_are_one_condition():
    case = Case.from_dict(patched(("bc.2", {"at": [4.0, 1.0], "displacement_x": 0.0, "displacement_y": 1e-3})))
    assert case.bcs[2] == BC("displacement", (0.0, 1e-3), at=(4.0, 1.0), components=(True, True))


def test_repeated_equal_condition_is_allowed():
    assert len(Case.from_dict(patched(("bc.4", {"at": [2.0, 0.0], "displacement_x": 0.0}))).bcs) == 5


def test_tips_skip_edge_crack_mouth():
    case = Case.from_dict(BASE)
    assert case.tips() == [Tip(0, 0, (1.0, 1.0)), Tip(0, 1, (2.0, 1.0)), Tip(1, 1, (0.5, 0.5))]


def test_no_fractures_is_valid():
    case = Case.from_dict(patched(("fractures", DELETE)))
    assert case.fractures == () and case.tips() == []


def test_fracture_points_are_read_only_arrays():
    case = Case.from_dict(BASE)
    pts = case.fracture_points()
    assert pts[0].shape == (3, 2) and pts[0].dtype == np.float64
    with pytest.raises(ValueError):
        pts[0][0, 0] = 9.0
    assert math.isclose(case.fractures[1].length, 0.5)


def test_bc_points_are_distinct_points():
    case = Case.from_dict(patched(("bc.4", {"at": [4.0, 1.0], "force": [1.0, 0.0]})))
    pts = case.bc_points()
    assert [tuple(p) for p in pts] == [(4.0, 1.0), (2.0, 0.0)]


def test_polygon_domain_and_edge_names():
    case = Case.from_dict(patched(("domain", _POLYGON), ("bc", _POLYGON_BC)))
    assert list(case.domain.boundary_names()) == ["edge0", "edge1", "edge2", "edge3"]


def test_concave_polygon_with_fracture_inside():
    d = patched(("domain", _L_SHAPE), ("bc", _POLYGON_BC[2:] + [{"on": "edge0", "displacement_y": 0.0}]),
                ("fractures", [{"points": [[2.5, 0.5], [3.5, 1.5]]}, {"points": [[0.0, 0.5], [0.5, 0.5]]}]))
    assert len(Case.from_dict(d).tips()) == 3


def test_disc_rim_condition_counts_as_support():
    d = patched(("domain", _DISC), ("fractures", _DISC_FRACTURE),
                ("bc", _DISC_BC[:2] + [{"on": "rim", "displacement": [0.0, 0.0]}]))
    assert Case.from_dict(d).bcs[2].on == "rim"


def test_from_toml_reads_file_and_defaults_title(tmp_path):
    path = tmp_path / "my_case.toml"
    path.write_text(
        '[material]\nE = 1e10\nnu = 0.2\nKIc = 1e6\n'
        '[domain]\nshape = "disc"\ncenter = [0, 0]\nradius = 1\n'
        '[[bc]]\nat = [-1, 0]\ndisplacement = [0, 0]\n[[bc]]\nat = [1, 0]\ndisplacement_y = 0\n'
        '[mesh]\nsize = 0.1\ntip_size = 0.01\n'
    )
    case = Case.from_toml(path)
    assert case.title == "my_case" and case.source == path
    assert case.domain.length_scale() > 0


def test_from_toml_syntax_error_is_a_case_error(tmp_path):
    path = tmp_path / "broken.toml"
    path.write_text("[material\nE = 1\n")
    with pytest.raises(CaseError) as info:
        Case.from_toml(path)
    assert info.value.key == str(path) and "not valid TOML" in info.value.reason


def test_from_toml_missing_file_is_a_case_error(tmp_path):
    with pytest.raises(CaseError) as info:
        Case.from_toml(tmp_path / "nope.toml")
    assert "cannot read" in info.value.reason


@pytest.mark.parametrize("path", CASES, ids=[p.stem for p in CASES])
def test_every_shipped_case_is_valid(path):
    case = Case.from_toml(path)
    assert case.title and case.fractures
    assert path.read_text().startswith("#"), "each case starts with a comment saying what it reproduces"


def test_brazilian_disc_45_matches_the_paper():
    """cases/brazilian_disc_45.toml against the text of section 4.2 of Dang-Trung,
    Keilegavlen and Berre (2020), sentence by sentence. What the paper leaves
    open (the load's magnitude f0: its SIFs are given per f0 sqrt(a) / (sqrt(pi) R);
    plane stress; the mesh and step sizes) is the case file's own choice and
    not checked here."""
    case = Case.from_toml(Path(__file__).resolve().parents[2] / "cases" / "brazilian_disc_45.toml")
    # "Comparison of KI and KII for different crack inclination angles (a = 5 mm, R = 42 mm)." (Table 2)
    R, a = 0.042, 0.005
    # "The computational domain is a disc-shaped rock specimen containing a
    # central single pre-existing fracture"
    assert case.domain.shape == "disc" and case.domain.radius == pytest.approx(R, rel=1e-12)
    assert len(case.fractures) == 1 and len(case.tips()) == 2
    f = case.fractures[0]
    assert len(f.points) == 2 and f.length == pytest.approx(2 * a, rel=1e-9)   # "2a is the length of the fracture"
    np.testing.assert_allclose(f.points.mean(axis=0), case.domain.center, atol=1e-12 * R)
    # "The fracture is inclined at an angle u to the vertical direction at the
    # center of the specimen." ... "For u = 45o, the wing cracks obtained by the experiment ..."
    d = f.points[-1] - f.points[0]
    assert math.degrees(math.acos(abs(d[1]) / np.linalg.norm(d))) == pytest.approx(45.0, abs=1e-9)
    # "The specimen is compressed by two line loads f0 = {0, f0} and -f0 = {0, -f0}
    # acting parallel to the y-axis." (at the ends of the vertical diameter, Fig. 13)
    forces = sorted((bc for bc in case.bcs if bc.kind == "force"), key=lambda bc: bc.at[1])
    assert len(forces) == 2
    (bottom, top) = forces
    np.testing.assert_allclose([bottom.at, top.at], [[0.0, -R], [0.0, R]], atol=1e-12 * R)
    assert bottom.value[0] == top.value[0] == 0.0                       # parallel to the y-axis
    assert top.value[1] < 0 < bottom.value[1] and top.value[1] == -bottom.value[1]   # equal, opposite, pressing in
    # "The material parameters are the Young's modulus E = 15 GPa, Poisson's
    # ratio m = 0.21, and fracture toughness KIC = 2 MPa m1/2 (Haeri et al., 2014b)."
    assert (case.material.E, case.material.nu, case.material.KIc) == (15e9, 0.21, 2e6)
    # "On the existing fracture, a no-friction condition is assigned in the tangential direction."
    assert f.faces == "frictionless"
    # the supports hold the disc only: nothing else loads it
    assert all(bc.kind == "displacement" and not np.any(bc.value) for bc in case.bcs if bc.kind != "force")


def test_what_the_contract_example_writes_is_accepted():
    """The shared contract's example writes slip = 0.0 on frictionless faces
    and gravity with density 0.0: a zero slip and a zero body force are no
    conditions, accepted; a non-zero slip on non-slip faces stays an error."""
    import copy
    from wingcrack.case import Case
    d = copy.deepcopy(BASE)
    d["fractures"][0]["slip"] = 0.0
    d["body"] = {"gravity": [0.0, -9.8]}
    d["material"]["density"] = 0.0
    case = Case.from_dict(d)
    assert case.fractures[0].slip == 0.0 and case.material.density == 0.0


def test_uniform_slip_profile_is_no_condition():
    """Like slip = 0.0, the default profile names no condition: accepted on any faces."""
    assert Case.from_dict(patched(("fractures.1.slip_profile", "uniform"))).fractures[1].slip_profile == "uniform"


@pytest.mark.parametrize("changes", [
    [("material.E", 1e3), ("bc.0.traction", [0.0, 100.0]), ("bc.1.traction", [0.0, -100.0])],
    [("material.E", 1e13)], [("material.KIc", 1.0)], [("material.KIc", 1e9)],
    [("material.density", 1e5)],
    [("stress", {"sxx": -1e9, "syy": 1e9, "sxy": -1e9})],        # 0.1 E
    [("bc.0.traction", [1e9, -1e9])],
    [("fractures.0.faces", "coulomb"), ("fractures.0.friction", 100.0), ("fractures.0.cohesion", 1e9)],  # 0.1 E
    [("fractures.0.pressure", 1e9), ("fractures.1.pressure", 1e9)],  # 0.1 E
    [("bc.2.displacement", [0.4472, -0.4472])],                   # 0.1 L, L = sqrt(20) m
    [("propagation", {"length": 4.472, "max_load_factor": 1e9})],  # L
    [("mesh", {"size": 4.472, "tip_size": 0.05})],
    [("title", "x" * 200)],
    # with density 0 gravity is no body force, whatever its size
    [("body", {"gravity": [0.0, -1e300]})],
    # the weight of the 4.47 m domain, density g L, at 0.1 E
    [("material.density", 1e4), ("body", {"gravity": [0.0, -1e9 / (1e4 * 20 ** 0.5) * 0.999]})],
], ids=["E-lo", "E-hi", "KIc-lo", "KIc-hi", "density", "stress", "traction", "coulomb", "pressure", "displacement", "length",
        "mesh-size", "title", "gravity-no-density", "gravity-weight"])
def test_magnitudes_at_their_limits_are_accepted(changes):
    assert Case.from_dict(patched(*changes)).title


def _fifo(tmp_path):
    path = tmp_path / "case.toml"
    os.mkfifo(path)
    return path


@pytest.mark.parametrize("make, kind", [
    (_fifo, "a FIFO"),
    (lambda tmp_path: tmp_path, "a directory"),
    (lambda tmp_path: Path("/dev/zero"), "a character device"),
], ids=["fifo", "directory", "dev-zero"])
def test_from_toml_refuses_what_is_not_a_regular_file(tmp_path, make, kind):
    """Refused before reading: opening a FIFO for reading would wait for a
    writer forever and /dev/zero never ends, so an alarm guards the test."""
    path = make(tmp_path)

    def hung(signum, frame):
        raise TimeoutError(f"Case.from_toml({path}) blocked")

    old = signal.signal(signal.SIGALRM, hung)
    signal.setitimer(signal.ITIMER_REAL, 10.0)
    try:
        with pytest.raises(CaseError) as info:
            Case.from_toml(path)
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0.0)
        signal.signal(signal.SIGALRM, old)
    assert info.value.key == str(path)
    assert info.value.reason.startswith(f"not a regular file ({kind})")


# ---------------------------------------------------------------- the reference and the description


DOC = Path(__file__).resolve().parents[2] / "docs" / "case-format.md"


def test_reference_tables_are_rendered_from_the_description():
    """docs/case-format.md holds a key table for every table of the case, each
    exactly as wingcrack.case_doc renders it (`python -m wingcrack.case_doc`)."""
    text = DOC.read_text()
    assert case_doc.blocks(text) == list(DESCRIPTION)
    assert case_doc.render(text) == text


def test_every_key_is_documented_with_its_default():
    text = DOC.read_text()
    for name, keys in DESCRIPTION.items():
        rendered = case_doc.table(name, keys)
        for k in keys:
            assert k.doc, f"{name}.{k.name} has no doc"
            row = next(line for line in rendered.splitlines() if line.startswith(f"| `{k.name}`"))
            assert row in text
        # and the doc's table holds no key the description lacks
        block = text.split(f"<!-- keys: {name} -->")[1].split("<!-- end keys -->")[0]
        documented = [line.split("`")[1] for line in block.splitlines() if line.startswith("| `")]
        assert documented == [k.name for k in keys]


def test_every_key_of_the_description_is_read():
    """A case that gives every key of the description at its default reads
    back as the case that leaves them out: the defaults written once in the
    Keys are the ones applied, and every Key is a key the reader takes."""
    d = patched(("material.thickness", 1.0), ("material.density", 0.0), ("body", {"gravity": [0.0, 0.0]}),
                ("stress", {"sxx": 0.0, "syy": 0.0, "sxy": 0.0}), ("mesh.adaptive", True), ("mesh.sectors", 32),
                ("propagation", {"steps": 35, "length": 0.05, "alpha": 0.35, "load": "scale",
                                 "max_load_factor": 100.0, "sif": "correlation", "connect_pressure": True}),
                ("fractures.1.faces", "open"), ("fractures.1.slip", 0.0), ("fractures.1.gap", 0.0),
                ("fractures.1.grow", True), ("fractures.1.slip_profile", "uniform"),
                ("fractures.1.friction", 0.0), ("fractures.1.cohesion", 0.0), ("fractures.1.pressure", 0.0))
    given = {name: set() for name in DESCRIPTION}
    given["top"] = set(d)
    for name in ("material", "mesh", "body", "stress", "propagation"):
        given[name] = set(d[name])
    given["domain"] = set(d["domain"])
    given["fractures"] = set(d["fractures"][1])
    given["bc"] = {k for bc in d["bc"] for k in bc}
    # the pump (propagation.load = "injection" and its table): tests/unit/test_case_injection.py
    given["top"].add("injection")
    given["injection"] = {k.name for k in DESCRIPTION["injection"]}
    for name, keys in DESCRIPTION.items():
        if name not in ("domain", "bc"):  # one shape, one condition kind at a time
            assert given[name] == {k.name for k in keys}, name
    given_all, defaults = Case.from_dict(d), Case.from_dict(BASE)
    for part in ("material", "body", "stress", "mesh", "propagation"):
        assert getattr(given_all, part) == getattr(defaults, part), part
    f, g = given_all.fractures[1], defaults.fractures[1]
    names = [k.name for k in DESCRIPTION["fractures"] if k.name != "points"]
    assert [getattr(f, n) for n in names] == [getattr(g, n) for n in names]


def test_from_dict_refuses_a_key_that_is_not_a_string():
    """Case.from_dict of a table with an int key: a CaseError naming it, not
    a TypeError from difflib's suggestion."""
    d = copy.deepcopy(BASE)
    d["material"][5] = 1.0
    err = _error(d)
    assert err.key == "material.5" and "keys are strings" in err.reason


def _same(a: Case, b: Case) -> bool:
    """Equal cases, arrays bit for bit (a Case's fields hold arrays, so == is ambiguous); the file
    read aside."""
    import pickle
    from dataclasses import replace

    return pickle.dumps(replace(a, source=None)) == pickle.dumps(replace(b, source=None))


def test_a_byte_order_mark_is_not_part_of_the_case(tmp_path):
    """Editors on Windows begin UTF-8 files with a BOM: the case reads as without it (it said
    "Invalid statement (at line 1, column 1)")."""
    text = CASES[0].read_bytes()
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    plain, marked = tmp_path / "a" / "case.toml", tmp_path / "b" / "case.toml"
    plain.write_bytes(text)
    marked.write_bytes(b"\xef\xbb\xbf" + text)
    assert _same(Case.from_toml(marked), Case.from_toml(plain))


def test_numpy_scalars_are_the_numbers_they_hold():
    """A Python user's numbers often come out of arrays (np.float32, np.int64, np.bool_): the case is
    the one the same Python numbers give (np.float32 was refused: 'expected a number, got a float32');
    a numpy NaN is refused as a Python one is."""
    d = copy.deepcopy(BASE)
    d["material"]["E"] = float(np.float32(7e10))   # the float32's value, exactly
    d["mesh"]["adaptive"] = False
    d["propagation"] = {"steps": 3}
    n = copy.deepcopy(d)
    n["material"]["E"] = np.float32(7e10)
    n["material"]["nu"] = np.float64(d["material"]["nu"])
    n["mesh"]["adaptive"] = np.bool_(False)
    n["propagation"]["steps"] = np.int64(3)
    n["fractures"][1]["points"] = [[np.float32(x) for x in p] for p in d["fractures"][1]["points"]]
    assert _same(Case.from_dict(n), Case.from_dict(d))
    n["material"]["nu"] = np.float64("nan")
    with pytest.raises(CaseError, match="material.nu: must be a finite number"):
        Case.from_dict(n)
