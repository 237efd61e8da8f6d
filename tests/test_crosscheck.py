"""Cross-check of the assembly (wingcrack/crosscheck.py): the same open-face
problem assembled by scikit-fem (MeshTri2 isoparametric P2, its own forms,
node map and boundary conditions, SciPy's SuperLU) on wingcrack's mesh.

Tolerances: both are direct solves of the same discrete system (same mesh,
same P2 geometry, same quadrature rules), so they differ by round-off of
quadrature sums and of two different factorisations, amplified by the
condition number of K (quarter-point cells next to cells 100x larger):
measured 1e-14 to 1e-12. Displacements must agree to 1e-8 relative, SIFs to
1e-6 (displacement correlation takes differences of face displacements, which
are a small part of max |u| on the disc). A real discrepancy is far larger:
a cell quadrature of order 6 instead of DOLFINx's 4 alone moves the
displacements by 1e-6 to 4e-5 (checked below), a wrong load more.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from builders import brazilian_disc, square_plate_with_cracks
from wingcrack import cli
from wingcrack import crosscheck as xc
from wingcrack.case import Case

ROOT = Path(__file__).resolve().parents[1]
U_TOL, SIF_TOL = 1e-8, 1e-6


def every_load_rectangle() -> dict:
    """Square plate with an inclined interior crack under every kind of load:
    in-situ stress (initial stress, sigma0.n on the boundary, -sigma0.n felt
    by the faces), gravity, a traction, a point force, and displacements on a
    whole named boundary and of one component on another."""
    d = square_plate_with_cracks(1.0, [[[-0.15, -0.1], [0.15, 0.12]]], (2e6, -5e6, 1e6), 0.1, 0.02)
    d["material"]["density"] = 2500.0
    d["body"] = {"gravity": [0.3, -9.81]}
    # (bottom held in y only: with x held too it would conflict with the
    # right side's x at their shared corner, which the case checker refuses)
    d["bc"] = [{"on": "bottom", "displacement_y": 0.0},
               {"at": [-0.5, -0.5], "displacement_x": 0.0},
               {"on": "top", "traction": [1e6, -3e6]},
               {"on": "right", "displacement_x": 1e-5},
               {"at": [-0.5, 0.2], "force": [2e5, 1e5]}]
    return d


def disc_on_curved_rim() -> dict:
    """Disc (curved P2 rim cells and facets) with in-situ stress and a
    traction on the rim besides the two line loads."""
    d = brazilian_disc(30, size=0.006, tip_size=0.001)
    d["stress"] = {"sxx": -2e6, "syy": 1e6, "sxy": 0.5e6}
    d["bc"].append({"on": "rim", "traction": [3e6, -1e6]})
    return d


CASES = {
    # the paper's disc as shipped: frictionless faces, solved as open
    "disc45": lambda: Case.from_toml(ROOT / "cases" / "brazilian_disc_45.toml"),
    "rectangle_inclined": lambda: Case.from_dict(every_load_rectangle()),
    "disc_rim_traction": lambda: Case.from_dict(disc_on_curved_rim()),
}


@pytest.mark.parametrize("name", sorted(CASES))
def test_skfem_agrees(name):
    case = CASES[name]()
    r = xc.crosscheck(case)
    assert r.dofs > 1000 and len(r.tips) == 2
    assert r.u_rel < U_TOL, r.u_rel
    assert r.sif_rel < SIF_TOL, r.sif_rel
    assert r.agrees()
    expect_opened = [{"fracture": 0, "faces": "frictionless"}] if name == "disc45" else []
    assert r.opened == expect_opened
    # the SIFs compared are the real ones (not, say, two zeros)
    assert max(abs(t["KII"]) for t in r.tips) > 1e5


def test_wrong_quadrature_is_seen(monkeypatch):
    """The check is not vacuous: scikit-fem with a cell rule of order 6
    (exact on affine cells as well) differs from DOLFINx's order 4 on the
    quarter-point cells, far above the tolerances."""
    monkeypatch.setattr(xc, "CELL_ORDER", 6)
    r = xc.crosscheck(Case.from_dict(every_load_rectangle()))
    assert r.u_rel > 100 * U_TOL
    assert not r.agrees()


def test_lame_plane_stress_and_strain():
    E, nu = 10e9, 0.25
    lam, mu = xc.lame(E, nu, "stress")
    # plane stress: sigma_xx = E/(1-nu^2) (eps_xx + nu eps_yy)
    assert lam + 2 * mu == pytest.approx(E / (1 - nu**2), rel=1e-15)
    lam, mu = xc.lame(E, nu, "strain")
    assert lam + 2 * mu == pytest.approx(E * (1 - nu) / ((1 + nu) * (1 - 2 * nu)), rel=1e-15)


RECTANGLE_TOML = """
title = "crosscheck CLI plate"
[material]
E = 10e9
nu = 0.25
KIc = 1e6
plane = "strain"
[domain]
shape = "rectangle"
corner = [-0.5, -0.5]
size = [1.0, 1.0]
[[fractures]]
points = [[-0.15, -0.1], [0.15, 0.12]]
faces = "frictionless"
[[bc]]
on = "bottom"
displacement = [0.0, 0.0]
[[bc]]
on = "top"
traction = [1e6, -3e6]
[mesh]
size = 0.1
tip_size = 0.02
[propagation]
length = 0.02
"""


def test_cli_report(tmp_path, capsys):
    case = tmp_path / "plate.toml"
    case.write_text(RECTANGLE_TOML)
    code = cli.main(["crosscheck", str(case), "-o", str(tmp_path / "out")])
    out = capsys.readouterr().out
    assert code == cli.EXIT_OK, out
    assert "fracture 0 (frictionless) solved as open" in out
    assert "agree within 1e-06" in out
    import json

    report = json.loads((tmp_path / "out" / "crosscheck.json").read_text())
    assert report["agree"] is True and report["tolerance"] == 1e-6
    assert report["u_rel"] < U_TOL and report["sif_rel"] < SIF_TOL
    assert {"KI", "KII", "KI_skfem", "KII_skfem"} <= set(report["tips"][0])
    assert np.isfinite(report["seconds"]["total"])


def test_cli_missing_file(tmp_path, capsys):
    missing = tmp_path / "nowhere.toml"
    assert cli.main(["crosscheck", str(missing)]) == cli.EXIT_INVALID
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [f"wingcrack: error: {missing}: cannot read: No such file or directory"]


def test_cli_bad_tolerance(capsys):
    with pytest.raises(SystemExit) as exc:
        cli.main(["crosscheck", str(ROOT / "cases" / "brazilian_disc_45.toml"), "--tol", "0"])
    assert exc.value.code == cli.EXIT_INVALID
    assert "--tol: must be a positive number" in capsys.readouterr().err
