"""Case tables (as tomllib returns them) for the verification tests."""
from __future__ import annotations

import numpy as np


def material(E=10e9, nu=0.25, plane="strain"):
    return {"E": E, "nu": nu, "KIc": 1.0e6, "plane": plane}


def square_plate_with_cracks(L, cracks, sigma0, size, tip_size, nu=0.25, plane="strain", sectors=32):
    """Square plate of side L centred at 0 holding `cracks` (polylines), loaded
    by the uniform far-field stress sigma0 = (sxx, syy, sxy) as in-situ
    stress: the outer boundary carries sigma0.n, the faces are freed of it.
    Three point constraints remove rigid motion without reactions."""
    sxx, syy, sxy = sigma0
    return {
        "title": "plate",
        "material": material(nu=nu, plane=plane),
        "domain": {"shape": "rectangle", "corner": [-L / 2, -L / 2], "size": [L, L]},
        "fractures": [{"points": np.asarray(c, float).tolist(), "faces": "open"} for c in cracks],
        "bc": [
            {"at": [-L / 2, -L / 2], "displacement": [0.0, 0.0]},
            {"at": [L / 2, -L / 2], "displacement_y": 0.0},
        ],
        "stress": {"sxx": sxx, "syy": syy, "sxy": sxy},
        "mesh": {"size": size, "tip_size": tip_size, "sectors": sectors},
        "propagation": {"length": tip_size},
    }


def brazilian_disc(phi_deg, f0=1.0e6, R=0.042, a=0.005, size=0.004, tip_size=0.0005, sectors=32, faces="open"):
    """Paper section 4.2: disc of radius R, central crack 2a at phi to the
    vertical load axis, line loads f0 (N/m) at the poles, plane stress."""
    u = np.radians(phi_deg)
    # the crack is turned counter-clockwise from the vertical load axis, so
    # that KII > 0 in the contract's tip frame, as in the paper's Table 2
    d = a * np.array([-np.sin(u), np.cos(u)])
    return {
        "title": f"Brazilian disc {phi_deg} deg",
        "material": {"E": 15e9, "nu": 0.21, "KIc": 2.0e6, "plane": "stress"},
        "domain": {"shape": "disc", "center": [0.0, 0.0], "radius": R},
        "fractures": [{"points": [(-d).tolist(), d.tolist()], "faces": faces}],
        "bc": [
            {"at": [0.0, R], "force": [0.0, -f0]},
            {"at": [0.0, -R], "force": [0.0, f0]},
            {"at": [-R, 0.0], "displacement": [0.0, 0.0]},
            {"at": [R, 0.0], "displacement_y": 0.0},
        ],
        "mesh": {"size": size, "tip_size": tip_size, "sectors": sectors},
        "propagation": {"length": tip_size},
    }


def edge_crack_strip(a_over_b, b=1.0, height=8.0, sigma=1.0e6, size=0.1, tip_size=0.01, nu=0.25):
    """Single edge crack of depth a from the left edge of a strip of width b
    and height `height` (in units of b), uniform tension on its ends."""
    H = height * b
    a = a_over_b * b
    return {
        "title": f"edge crack a/b = {a_over_b}",
        "material": material(nu=nu, plane="strain"),
        "domain": {"shape": "rectangle", "corner": [0.0, -H / 2], "size": [b, H]},
        "fractures": [{"points": [[0.0, 0.0], [a, 0.0]], "faces": "open"}],
        "bc": [
            {"on": "top", "traction": [0.0, sigma]},
            {"on": "bottom", "traction": [0.0, -sigma]},
            {"at": [b, -H / 2], "displacement": [0.0, 0.0]},
            {"at": [b, H / 2], "displacement_x": 0.0},
        ],
        "mesh": {"size": size, "tip_size": tip_size},
        "propagation": {"length": tip_size},
    }
