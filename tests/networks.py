"""Random valid fracture networks (issue 7): a seeded generator of case
files for the soak tests. Each case is a rectangle or a disc with 1-8
straight fractures of random position, orientation and length, random faces
(open, frictionless, slip) and random loads; fractures keep clear of each
other and of the boundary by a few rosette radii so that the first mesh is
valid (what happens after that is what the soak test explores)."""
from __future__ import annotations

import numpy as np


def _toml_value(v) -> str:
    if isinstance(v, str):
        return '"' + v + '"'
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (list, tuple, np.ndarray)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    return repr(float(v)) if isinstance(v, (float, np.floating)) else str(int(v))


def to_toml(case: dict) -> str:
    """The case dict (tables and arrays of tables, as tomllib returns them) as TOML."""
    out = [f"title = {_toml_value(case['title'])}"]
    for name, table in case.items():
        if isinstance(table, dict):
            out.append(f"\n[{name}]")
            out += [f"{k} = {_toml_value(v)}" for k, v in table.items()]
        elif isinstance(table, list):
            for item in table:
                out.append(f"\n[[{name}]]")
                out += [f"{k} = {_toml_value(v)}" for k, v in item.items()]
    return "\n".join(out) + "\n"


def _segment_distance(p, q, a, b) -> float:
    """Distance between segments pq and ab (0 if they cross)."""
    def point_seg(x, u, v):
        t = np.clip(np.dot(x - u, v - u) / np.dot(v - u, v - u), 0, 1)
        return np.linalg.norm(x - u - t * (v - u))

    d1, d2 = q - p, b - a
    den = d1[0] * d2[1] - d1[1] * d2[0]
    if abs(den) > 1e-15:
        t = ((a - p)[0] * d2[1] - (a - p)[1] * d2[0]) / den
        s = ((a - p)[0] * d1[1] - (a - p)[1] * d1[0]) / den
        if 0 <= t <= 1 and 0 <= s <= 1:
            return 0.0
    return min(point_seg(p, a, b), point_seg(q, a, b), point_seg(a, p, q), point_seg(b, p, q))


def random_case(seed: int, steps: int = 10) -> dict:
    rng = np.random.default_rng(seed)
    disc = rng.random() < 0.3
    n = int(rng.integers(1, 9))
    if disc:
        R = 1.0
        domain = {"shape": "disc", "center": [0.0, 0.0], "radius": R}
        scale = 2 * R
    else:
        W, H = float(rng.uniform(2.0, 4.0)), float(rng.uniform(2.0, 4.0))
        domain = {"shape": "rectangle", "corner": [0.0, 0.0], "size": [W, H]}
        scale = min(W, H)
    size, tip = 0.1 * scale, 0.01 * scale
    clear = 6 * tip

    def inside(p) -> float:  # distance to the boundary (negative outside)
        if disc:
            return R - np.linalg.norm(p)
        return min(p[0], p[1], W - p[0], H - p[1])

    fractures = []
    for _ in range(200):
        if len(fractures) == n:
            break
        c = rng.uniform(-0.6, 0.6, 2) if disc else rng.uniform([0.2 * W, 0.2 * H], [0.8 * W, 0.8 * H])
        half = rng.uniform(0.05, 0.2) * scale
        a = rng.uniform(0, np.pi)
        d = half * np.array([np.cos(a), np.sin(a)])
        p, q = c - d, c + d
        if min(inside(p), inside(q)) < clear:
            continue
        if any(_segment_distance(p, q, np.array(f["points"][0]), np.array(f["points"][1])) < clear
               for f in fractures):
            continue
        faces = str(rng.choice(["open", "frictionless", "frictionless", "slip"]))
        f = {"points": [p.tolist(), q.tolist()], "faces": faces}
        if faces == "slip":
            f["slip"] = float(rng.uniform(1e-6, 1e-5)) * scale
        fractures.append(f)

    E = float(rng.uniform(10e9, 70e9))
    case = {
        "title": f"random network {seed}",
        "material": {"E": E, "nu": float(rng.uniform(0.15, 0.3)), "KIc": float(rng.uniform(0.5e6, 2e6)),
                     "plane": str(rng.choice(["stress", "strain"]))},
        "domain": domain,
        "fractures": fractures,
    }
    s = float(rng.uniform(1e5, 1e7))
    if disc:
        case["bc"] = [
            {"at": [0.0, R], "force": [0.0, -s * 0.01]},
            {"at": [0.0, -R], "force": [0.0, s * 0.01]},
            {"at": [-R, 0.0], "displacement": [0.0, 0.0]},
            {"at": [R, 0.0], "displacement_y": 0.0},
        ]
    else:
        shear = float(rng.uniform(-1, 1))
        normal = float(rng.uniform(-1, 1))
        case["bc"] = [{"on": "bottom", "displacement": [0.0, 0.0]},
                      {"on": "top", "traction": [shear * s, normal * s]}]
        if rng.random() < 0.4:
            case["stress"] = {"sxx": -float(rng.uniform(0, 1)) * s, "syy": -float(rng.uniform(0, 1)) * s,
                              "sxy": 0.0}
    case["mesh"] = {"size": size, "tip_size": tip}
    case["propagation"] = {"steps": steps, "length": tip}
    return case
