"""Geometries on the edge of the mesher's rules (meshing/admissibility.py),
as case tables, for tests/*/test_admissibility*.py.

The base case of issue 12: the rectangle [-1, 1]^2, a crack
(-0.1, -0.1)-(0.1, 0.1), tractions +-1 MPa on top and bottom, pins at
(-1, 0) (both components) and (1, 0) (y), mesh.size 0.2, tip_size 0.02,
E 10 GPa, nu 0.25, KIc 1 MPa m^0.5, 3 steps. Every family puts one
feature k rosette radii (or tip sizes) from a rule's threshold; `place`
then rotates the whole case (the rectangle becomes a polygon), scales it
and moves it away from the origin.
"""
from __future__ import annotations

import json
import math

import numpy as np

from meshing.admissibility import GAP, JUNCTION_GAP, MIN_JUNCTION_ANGLE, NEIGHBOUR_CLEARANCE, TIP_CLEARANCE

H = 0.02        # tip_size of the base case
SIZE = 0.2      # mesh.size
Y0 = 0.013      # off the pins' line (y = 0), which a point-symmetric divider would like


def base(fractures=None, extra_bc=(), tip=H, size=SIZE) -> dict:
    """The base case in the unit frame (domain [-1, 1]^2) with these fractures."""
    return {
        "title": "admissibility",
        "material": {"E": 10e9, "nu": 0.25, "KIc": 1e6, "plane": "strain"},
        "domain": {"shape": "rectangle", "corner": [-1.0, -1.0], "size": [2.0, 2.0]},
        "fractures": [{"points": np.asarray(f, float).tolist()} for f in
                      (fractures if fractures is not None else [[(-0.1, -0.1), (0.1, 0.1)]])],
        "bc": [{"on": "top", "traction": [0.0, 1e6]}, {"on": "bottom", "traction": [0.0, -1e6]},
               {"at": [-1.0, 0.0], "displacement": [0.0, 0.0]}, {"at": [1.0, 0.0], "displacement_y": 0.0},
               *extra_bc],
        "mesh": {"size": size, "tip_size": tip},
        "propagation": {"steps": 3},
    }


def _turn(phi):
    return np.array([math.cos(phi), math.sin(phi)])


def family(name: str, k: float, phi: float = 0.0, n: int = 3) -> dict:
    """The base case with one feature k units from its threshold's measure
    (k = threshold * (1 + delta) gives a case delta from the rule). phi: an
    angle (rad) the family uses for its approach; n: points of a polyline."""
    h = H
    if name == "boundary":      # tip k h from the right edge, approaching at phi
        tip = np.array([1 - k * h, Y0])
        return base([[tip - 0.4 * _turn(phi), tip]])
    if name == "corner":        # tip k h from both edges at the top right corner
        tip = np.array([1 - k * h, 1 - k * h * (1 + 1e-3)])
        return base([[tip - 0.4 * _turn(phi), tip]])
    if name == "T":             # tip k h from the side of another fracture
        tip = np.array([-k * h, Y0])
        return base([[tip - 0.4 * _turn(phi), tip], [(0.0, -0.3), (0.0, 0.3)]])
    if name == "tiptip":        # two tips k h apart, the cracks at phi to each other's line
        a, b = np.array([-k * h / 2, Y0]), np.array([k * h / 2, Y0])
        return base([[a - 0.4 * _turn(phi), a], [b, b + 0.4 * _turn(-phi)]])
    if name == "sidebyside":    # parallel cracks overlapping by 0.1, k h apart
        return base([[(-0.5, Y0), (0.05, Y0)], [(-0.05, Y0 + k * h), (0.5, Y0 + k * h)]])
    if name == "short":         # one segment k h long: its two rosettes
        d = 0.5 * k * h * _turn(phi)
        return base([[np.array([0, Y0]) - d, np.array([0, Y0]) + d]])
    if name == "segment":       # the segment at a tip k tip sizes long
        return base([[(-0.3, Y0), (0.0, Y0), (k * h * math.cos(phi), Y0 + k * h * math.sin(phi))]])
    if name == "kink":          # the tip k h from the segment before its own
        a = math.asin(min(1.0, k / 3.0))
        return base([[(-0.3, Y0), (0.0, Y0), (-3 * h * math.cos(a), Y0 + 3 * h * math.sin(a))]])
    if name == "uturn":         # back over its first segment, the tip k h above it
        return base([[(-0.3, Y0), (0.3, Y0), (0.3, Y0 + k * h), (-0.1, Y0 + k * h)]])
    if name == "doubleback":    # back over itself k h above it (the tip near its neighbour)
        return base([[(-0.1, Y0), (0.1, Y0), (-0.05, Y0 + k * h)]])
    if name == "graze":         # an edge crack leaving the bottom at k degrees, then turning up
        a = math.radians(k)
        return base([[(0.2, -1.0), (0.2 + 0.3 * math.cos(a), -1.0 + 0.3 * math.sin(a)), (0.6, -0.5)]])
    if name == "pin":           # a second pin k tip sizes along the left edge from the first
        return base(extra_bc=[{"at": [-1.0, k * h], "displacement_x": 0.0}])
    if name == "pin_corner":    # a pin k tip sizes from a corner
        return base(extra_bc=[{"at": [-1.0 + k * h, -1.0], "displacement_y": 0.0}])
    if name == "mouth":         # an edge crack's mouth k tip sizes from a pin
        return base([[(-1.0, k * h), (-0.7, k * h + 0.1)]])
    if name == "rim":           # a disc (the Brazilian test): a tip k h from the rim at phi
        d = base([[0.6 * _turn(phi), (1 - k * h) * _turn(phi)]])
        d["domain"] = {"shape": "disc", "center": [0.0, 0.0], "radius": 1.0}
        d["bc"] = [{"at": [0.0, 1.0], "force": [0.0, -1e6]}, {"at": [0.0, -1.0], "force": [0.0, 1e6]},
                   {"at": [-1.0, 0.0], "displacement": [0.0, 0.0]}, {"at": [1.0, 0.0], "displacement_y": 0.0}]
        return d
    if name == "X":             # two fractures crossing at k degrees (phi turns the pair)
        a, u = math.radians(k), _turn(phi)
        w = _turn(phi + a)
        x = np.array([0.0, Y0])
        p1, p2 = x - 0.15 * w, x + 0.15 * w          # then bending away, so that the tips stay clear
        n = np.array([-u[1], u[0]])
        return base([[x - 0.4 * u, x + 0.4 * u], [p1 - 0.3 * n, p1, p2, p2 + 0.3 * n]])
    if name == "T_angle":       # an end on another fracture, at k degrees to it
        a = math.radians(k)
        x = np.array([0.05, Y0])
        return base([[(-0.3, Y0), (0.3, Y0)], [x + 0.15 * _turn(a) + [0.0, 0.25], x + 0.15 * _turn(a), x]])
    if name == "star":          # three fractures through one point, k degrees between neighbouring rays
        x = np.array([0.0, Y0])
        ang = [phi, phi + math.radians(k), phi + 2 * math.radians(k)]
        return base([[x - 0.3 * _turn(b), x + 0.3 * _turn(b)] for b in ang])
    if name == "XX":            # two crossings on one fracture k tip sizes apart (the second crossing
        d = k * h               # fracture runs parallel to the first there, then bends away)
        b = 0.2 * math.cos(phi)
        return base([[(-0.3, Y0), (0.3, Y0)], [(0.0, Y0 - 0.3), (0.0, Y0 + 0.3)],
                     [(d + b, Y0 - 0.3), (d, Y0 - 0.1), (d, Y0 + 0.1), (d + b, Y0 + 0.3)]])
    if name == "T_kink":        # an end on another fracture k tip sizes from its kink
        return base([[(-0.3, Y0), (0.0, Y0), (0.3, Y0 + 0.1)], [(-k * h + 0.1 * math.sin(phi), 0.3),
                                                                  (-k * h, Y0)]])
    if name == "T_mouth":       # an end on an edge crack k tip sizes from its mouth
        x = np.array([-1.0 + k * h, 0.3])
        return base([[(-1.0, 0.3), (-0.5, 0.3)], [x, x + 0.25 * _turn(1.0 + 0.3 * phi)]])
    if name == "through":       # a fracture from bottom to top, crossed at k degrees; both pieces held
        a = math.radians(k)
        x = np.array([0.1, Y0])
        w = _turn(math.pi / 2 - a)
        d = base([[(0.1, -1.0), (0.1, 1.0)], [x - 0.3 * w, x + 0.3 * w]])
        d["bc"] = [{"on": "top", "traction": [2e5, -1e6]}, {"on": "bottom", "traction": [-2e5, 1e6]},
                   {"on": "left", "displacement": [0.0, 0.0]}, {"on": "right", "displacement": [0.0, 0.0]}]
        return d
    if name == "zigzag":        # n points, segments k tip sizes long
        t = np.arange(n) * k * h
        x = t - 0.5 * t[-1]
        y = Y0 + 0.3 * h * np.where(np.arange(n) % 2, 1.0, -1.0) * math.sin(phi) + 0.1 * np.sin(3 * x)
        return base([np.column_stack([x, y])])
    raise KeyError(name)


#: family -> the threshold of its k (what the rule asks, in its units)
THRESHOLD = {
    "boundary": TIP_CLEARANCE, "corner": TIP_CLEARANCE, "T": TIP_CLEARANCE, "sidebyside": TIP_CLEARANCE,
    "tiptip": 2 + GAP, "short": 2 + GAP, "segment": 1.0, "kink": NEIGHBOUR_CLEARANCE, "uturn": TIP_CLEARANCE,
    "doubleback": NEIGHBOUR_CLEARANCE, "graze": 1.0, "pin": 1.0, "pin_corner": 1.0, "mouth": 1.0,
    "zigzag": 1.05, "rim": TIP_CLEARANCE,
    "X": MIN_JUNCTION_ANGLE, "T_angle": MIN_JUNCTION_ANGLE, "star": MIN_JUNCTION_ANGLE, "through": MIN_JUNCTION_ANGLE,
    "XX": JUNCTION_GAP, "T_kink": JUNCTION_GAP, "T_mouth": JUNCTION_GAP,
}


def place(case: dict, angle: float = 0.0, scale: float = 1.0, offset: float = 0.0) -> dict:
    """The case turned by `angle` (rad) about the origin (the rectangle then
    a polygon, its edges named edge0 (bottom) .. edge3 (left)), scaled by
    `scale` and moved by `offset` domain sizes along (1, 1)/sqrt(2)."""
    R = np.array([[math.cos(angle), -math.sin(angle)], [math.sin(angle), math.cos(angle)]])
    shift = offset * 2 * math.sqrt(2) * scale * np.array([1.0, 1.0]) / math.sqrt(2)

    def move(p):
        return ((np.asarray(p, float) @ R.T) * scale + shift).tolist()

    out = {key: (dict(v) if isinstance(v, dict) else v) for key, v in case.items()}
    if case["domain"]["shape"] == "disc":
        out["domain"] = {"shape": "disc", "center": move(case["domain"]["center"]),
                         "radius": case["domain"]["radius"] * scale}
    elif angle:
        corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
        out["domain"] = {"shape": "polygon", "points": [move(c) for c in corners]}
    else:
        out["domain"] = {"shape": "rectangle", "corner": move((-1.0, -1.0)), "size": [2.0 * scale, 2.0 * scale]}
    names = {"top": "edge2", "bottom": "edge0", "right": "edge1", "left": "edge3"} \
        if angle and case["domain"]["shape"] != "disc" else {}
    out["fractures"] = [dict(f, points=[move(p) for p in f["points"]]) for f in case["fractures"]]
    bcs = []
    for bc in case["bc"]:
        bc = dict(bc)
        if "at" in bc:
            bc["at"] = move(bc["at"])
        if "on" in bc:
            bc["on"] = names.get(bc["on"], bc["on"])
        for load in ("traction", "force"):
            if load in bc:
                bc[load] = (np.asarray(bc[load]) @ R.T).tolist()
        if angle and "displacement_y" in bc:   # the roller keeps its direction in the turned frame
            bc.pop("displacement_y")
            bc["displacement"] = [0.0, 0.0]
        if angle and "displacement_x" in bc:
            bc.pop("displacement_x")
            bc["displacement"] = [0.0, 0.0]
        bcs.append(bc)
    out["bc"] = bcs
    out["mesh"] = {k: v * scale for k, v in case["mesh"].items()}
    return out


def to_toml(d: dict) -> str:
    """A case table as the TOML text of a case file."""
    def v(x):
        if isinstance(x, str):
            return json.dumps(x)
        if isinstance(x, (list, tuple)):
            return "[" + ", ".join(v(y) for y in x) + "]"
        return repr(float(x)) if isinstance(x, float) else str(x)

    lines = [f"title = {v(d['title'])}"]
    for table in ("material", "domain", "mesh", "propagation"):
        lines += [f"[{table}]"] + [f"{k} = {v(x)}" for k, x in d[table].items()]
    for array in ("fractures", "bc"):
        for entry in d[array]:
            lines += [f"[[{array}]]"] + [f"{k} = {v(x)}" for k, x in entry.items()]
    return "\n".join(lines) + "\n"
