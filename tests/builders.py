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


def flowing_fault(half_length=30.0, T=0.5, frames=4, end_time=0.4, tip_size=0.5, steps=12):
    """A closed Coulomb fault of fixed hydraulic aperture (1e-4 m) in a
    plate ten times its length, friction 0.6 under 20 MPa of isotropic
    compression and a shear that leaves (f sigma' - tau0) / (f dp) = T at
    the initial pressure 5 MPa, the pressure held 7.5 MPa above that at its
    centre: fluid-driven slip (tests/verification/test_flow_fault_slip.py's
    case, run by the loop), frames evenly up to end_time."""
    f, s0, p0 = 0.6, 20e6, 5e6
    dp = 0.5 * (s0 - p0)
    W = 10 * half_length
    return {
        "title": "fluid-driven slip on a fault",
        "material": {"E": 10e9, "nu": 0.25, "KIc": 1e9, "plane": "strain"},
        "domain": {"shape": "rectangle", "corner": [-W, -W], "size": [2 * W, 2 * W]},
        "fractures": [{"points": [[-half_length, 0.0], [half_length, 0.0]], "faces": "coulomb", "friction": f,
                       "hydraulic_aperture": 1e-4}],
        "bc": [{"at": [-W, -W], "displacement": [0.0, 0.0]}, {"at": [W, -W], "displacement_y": 0.0}],
        "stress": {"sxx": -s0, "syy": -s0, "sxy": f * (s0 - p0) - T * f * dp},
        "mesh": {"size": W / 5, "tip_size": tip_size},
        "propagation": {"load": "injection", "steps": steps},
        "injection": {"fracture": 0, "pressure": p0 + dp, "initial_pressure": p0, "compressibility": 1e-9,
                      "viscosity": 1e-3, "end_time": end_time, "frames": frames},
    }


def flowing_kgd(viscosity=1e-6, steps=10, residual_aperture=1e-6, W=1000.0, tip_size=0.2, frames=1,
                end_time=1e6):
    """The KGD plate of tests/verification/test_injection_kgd.py (a crack of
    half-length 1 m in a plate of 1000 m, no far stress, 1e-4 m^3/s per m,
    an incompressible fluid) with the flow along the fractures: a fluid of
    `viscosity` and a residual aperture on the pre-existing faces (the flow
    needs a path into the closed crack at the start)."""
    return {"title": "KGD with flow", "material": {"E": 10e9, "nu": 0.25, "KIc": 1.0e6, "plane": "strain"},
            "domain": {"shape": "rectangle", "corner": [-W / 2, -W / 2], "size": [W, W]},
            "fractures": [{"points": [[-1.0, 0.0], [1.0, 0.0]], "faces": "open"}],
            "bc": [{"at": [-W / 2, -W / 2], "displacement": [0.0, 0.0]},
                   {"at": [W / 2, -W / 2], "displacement_y": 0.0}],
            "mesh": {"size": W / 10, "tip_size": tip_size},
            "propagation": {"steps": steps, "length": 1.0, "load": "injection"},
            "injection": {"fracture": 0, "rate": 1e-4, "compressibility": 0.0, "viscosity": viscosity,
                          "residual_aperture": residual_aperture, "end_time": end_time, "frames": frames}}
