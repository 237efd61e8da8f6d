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
displacements by 1e-6 to 4e-5 (checked below), the fracture pressure left out
by 0.5 on the pressurised crack below.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from builders import brazilian_disc, square_plate_with_cracks
from wingcrack import cli
from wingcrack import crosscheck as xc
from wingcrack.case import Case

ROOT = Path(__file__).resolve().parents[2]
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
    assert "\nleft out: fracture 0 (frictionless) solved as open: its contact\n" in out
    assert "\nloads at load factor 1: 1 displacement condition x 1; 1 traction x 1\n" in out
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


# -- fluid pressure in the fractures ------------------------------------------

A, SIGMA_N, P = 1.0, 3.0e6, 1.0e6


def pressurised_griffith(faces: str, load: str = "scale") -> dict:
    """A Griffith crack 2a along x in a plate 20a (the mesh of
    tests/verification/test_pressure_load.py) under the in-situ compression sigma_n across
    it and a fluid pressure P < sigma_n in it, on `faces`."""
    d = square_plate_with_cracks(20 * A, [[[-A, 0.0], [A, 0.0]]], (0.0, -SIGMA_N, 0.0), size=2.0 * A,
                                 tip_size=0.05 * A)
    d["fractures"][0].update(faces=faces, pressure=P)
    if faces == "coulomb":
        d["fractures"][0]["friction"] = 0.6
    d["propagation"]["load"] = load
    return d


@pytest.mark.parametrize("faces", ["open", "frictionless", "coulomb"])
def test_pressurised_crack_agrees_and_is_solved_open(faces):
    """Both solves apply the pressure on every kind of face, and contact
    faces are solved open as the report says: the crack then feels the net
    pressure P - sigma_n < 0 on open faces, so its faces overlap and
    Sneddon's KI = (P - sigma_n) sqrt(pi a) is negative (contact would give
    KI = 0; the pressure dropped, -sigma_n sqrt(pi a), 50 % more). 3 % on
    KI: measured 1.37 % high, the square plate's finite size (the same
    crack and tip mesh in plates 40a and 80a: 0.33 %, 0.065 %, falling as
    (a/L)^2), the rest discretisation (0.03 % at 100a,
    tests/verification/test_pressure_plate.py)."""
    r = xc.crosscheck(Case.from_dict(pressurised_griffith(faces)))
    assert r.u_rel < U_TOL, r.u_rel
    assert r.sif_rel < SIF_TOL, r.sif_rel
    assert r.agrees()
    sneddon = (P - SIGMA_N) * np.sqrt(np.pi * A)
    for t in r.tips:
        assert t["KI"] == pytest.approx(sneddon, rel=3e-2)
        assert abs(t["KII"]) < 1e-3 * abs(sneddon)
    assert r.loads == ["in-situ stress", "2 displacement conditions x 1", "fluid pressure 1e+06 Pa on fracture 0 x 1"]
    if faces == "open":
        assert r.opened == [] and r.left_out == "left out: nothing (every face is open in the case)"
    else:
        assert r.opened == [{"fracture": 0, "faces": faces}]
        what = "contact and friction" if faces == "coulomb" else "contact"
        assert r.left_out == (f"left out: fracture 0 ({faces}) solved as open: its {what}; "
                              "the fluid pressure on it is applied")


def test_dropped_pressure_is_seen(monkeypatch):
    """The check is not vacuous: the scikit-fem side without the pressure
    term (no crack faces found) loads the crack by -sigma_n instead of
    P - sigma_n: displacement and SIFs P / (sigma_n - P) = 0.5 off (measured
    0.5 to 1e-12)."""
    monkeypatch.setattr(xc.SkfemProblem, "crack_faces", lambda self: [])
    r = xc.crosscheck(Case.from_dict(pressurised_griffith("open")))
    assert r.u_rel == pytest.approx(P / (SIGMA_N - P), rel=1e-6)
    assert r.sif_rel == pytest.approx(P / (SIGMA_N - P), rel=1e-6)
    assert not r.agrees()


def test_injection_load_factor_scales_the_pressure_only(monkeypatch):
    """load = "pressure" at a load factor 2.5: the pressure is 2.5 P, the
    traction and displacement conditions and the in-situ stress stay; with
    load = "scale" every bc value is scaled too. scikit-fem applies its own
    reading of that rule; swapping the rules shows as a disagreement."""
    def case(load):
        d = pressurised_griffith("open", load=load)
        d["bc"] += [{"on": "top", "traction": [1e6, 2e6]}, {"at": [10 * A, 10 * A], "displacement_x": 1e-5}]
        return Case.from_dict(d)

    r = xc.crosscheck(case("pressure"), load_factor=2.5)
    assert r.agrees(), (r.u_rel, r.sif_rel)
    assert r.u_rel < U_TOL and r.sif_rel < SIF_TOL
    assert r.load_factor == 2.5 and r.loads[-1] == "fluid pressure 1e+06 Pa on fracture 0 x 2.5"
    assert "1 traction x 1" in r.loads
    scaled = xc.crosscheck(case("scale"), load_factor=2.5)
    assert scaled.agrees() and "1 traction x 2.5" in scaled.loads
    monkeypatch.setattr(xc, "factors", lambda case, lam: (float(lam), float(lam)))
    assert not xc.crosscheck(case("pressure"), load_factor=2.5).agrees()


def test_pressure_on_wings_and_joined_fractures():
    """The faces of a network as growth leaves it: a kinked fracture (a
    pre-existing part and its wing, one polyline), a fracture joined to it
    as a T, a third linked to that one tip to tip, and an edge crack from
    the boundary, each with its own pressure (mesh order), solved by both
    assemblies at a load factor 1.7 on one mesh. Each face edge carries the
    pressure of its fracture, junction nodes included."""
    host = [[-1.0, 0.0], [0.4, 0.0], [0.9, 0.35]]           # pre-existing part and a wing
    branch = [[0.2 + 0.8 * np.cos(1.1), 0.8 * np.sin(1.1)], [0.2, 0.0]]   # ends on host: a T
    linked = [[-0.6, 1.3], branch[0]]                         # ends on branch's free end: tip to tip
    edge = [[-2.5, -1.0], [-1.5, -1.2]]                       # from the left side: a mouth
    d = square_plate_with_cracks(5.0, [host], (-1e6, -2e6, 0.5e6), size=0.5, tip_size=0.03)
    case = Case.from_dict(d)
    pressures = [3e6, 1e6, 2e6, 4e6]
    from dataclasses import replace

    from wingcrack.fem.nodal import nodal_displacements
    from wingcrack.step import Timer, discretise

    fractures = [replace(case.fractures[0], points=np.asarray(p, float), pressure=q)
                 for p, q in zip((host, branch, linked, edge), pressures)]
    disc = discretise(case, fractures, Timer())
    cm = disc.cm
    assert len(cm.tips) == 4   # both ends of host, end 0 of linked, end 1 of edge: the T and the link are no tips
    copies = [int(np.sum(np.linalg.norm(cm.x - np.asarray(q), axis=1) < 1e-12)) for q in (branch[1], branch[0])]
    assert copies == [3, 2]   # the T's node in three copies, the link's in two
    u_wc = nodal_displacements(disc.problem.fm, disc.problem.solve(1.7), np.arange(len(cm.x)))
    sk = xc.SkfemProblem(case, cm, pressures, load_factor=1.7)
    assert {f for f, _ in sk.crack_faces()} == {0, 1, 2, 3}
    u_sk = sk.solve()
    scale = np.abs(u_wc).max()
    assert scale > 0
    np.testing.assert_allclose(u_sk, u_wc, rtol=0, atol=U_TOL * scale)   # measured 1.1e-12
    # and each fracture's pressure matters: the branch's and the link's swapped is seen
    swapped = xc.SkfemProblem(case, cm, [3e6, 2e6, 1e6, 4e6], load_factor=1.7).solve()
    assert np.abs(swapped - u_wc).max() > 1e-3 * scale
    disc.solver.release()


def test_cli_injection_case_agrees(capsys):
    """The shipped injection case (Coulomb faces everywhere, 1 MPa in the
    middle fracture, load = "pressure"): both solves with the pressure, the
    report says what is left out."""
    code = cli.main(["crosscheck", str(ROOT / "cases" / "three_fractures_injection.toml")])
    out = capsys.readouterr().out
    assert code == cli.EXIT_OK, out
    assert "\nloads at load factor 1: in-situ stress; 2 displacement conditions x 1; " \
           "fluid pressure 1e+06 Pa on fracture 1 x 1\n" in out
    assert "\nleft out: fracture 0 (coulomb), fracture 1 (coulomb), fracture 2 (coulomb) solved as open: " \
           "their contact and friction; the fluid pressure on fracture 1 is applied\n" in out
    assert "agree within 1e-06" in out and "DISAGREE" not in out
