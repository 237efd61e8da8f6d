"""Body force (gravity) and boundary tractions: an uncracked column of
height H under its own weight, held by the reaction traction rho g H on
its base, sides free. Exact: sigma_yy = rho g (y - H), sigma_xx = sigma_xy = 0
(the displacement is quadratic, which P2 reproduces exactly): the computed
stress matches to 1e-8 of rho g H (round-off of the solve)."""
import numpy as np

from wingcrack.step import solve_initial
from wingcrack.case import Case
from wingcrack.fem.cell_stress import _POINTS, cell_stress

RHO, G, W, H = 2700.0, 9.8, 2.0, 4.0


def test_column_under_its_own_weight():
    case = Case.from_dict({
        "material": {"E": 70e9, "nu": 0.21, "KIc": 1.5e6, "plane": "stress", "density": RHO},
        "domain": {"shape": "rectangle", "corner": [0.0, 0.0], "size": [W, H]},
        "fractures": [],
        "bc": [{"on": "bottom", "traction": [0.0, RHO * G * H]},
               {"at": [0.0, 0.0], "displacement": [0.0, 0.0]},
               {"at": [W, 0.0], "displacement_y": 0.0}],
        "body": {"gravity": [0.0, -G]},
        "mesh": {"size": 0.5, "tip_size": 0.1},
        "propagation": {"length": 0.1},
    })
    sol = solve_initial(case)
    x, cells, s = cell_stress(sol.problem)
    # physical points of the evaluation points (straight cells: affine map)
    v = x[cells[:, :3]]                                          # (m, 3, 2)
    lam = np.c_[1 - _POINTS.sum(axis=1), _POINTS]                # barycentric (3 points, 3 vertices)
    p = np.einsum("qk,mkd->mqd", lam, v)
    exact = RHO * G * (p[..., 1] - H)
    scale = RHO * G * H
    assert np.abs(s[..., 1] - exact).max() < 1e-8 * scale
    assert np.abs(s[..., 0]).max() < 1e-8 * scale and np.abs(s[..., 2]).max() < 1e-8 * scale
