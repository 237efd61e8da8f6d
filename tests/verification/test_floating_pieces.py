"""Pieces of the body that only contact holds (wingcrack.floating), against
the uncut body's solution and the statics of a sliding block.

(a) A square block cut out of a plate by four fractures meeting end to end
    at its corners, under hydrostatic compression: the uncut plate's
    displacement is linear, which P2 elements hold exactly, and it meets
    every contact condition with all faces closed and no shear on them; so
    the discrete solution of the cut plate is the uncut one to round-off.
(b) A strip cut across by one Coulomb fracture whose normal makes the angle
    beta with the strip's axis; the far piece carries a compressive end
    traction p and is held by nothing but the fracture. Uncut, the strip is
    in uniaxial stress: on the fracture sigma_n = -p cos^2 beta, tau = p sin
    beta cos beta, |tau| / |sigma_n| = tan beta. The piece is held (all pairs
    stuck, the uncut solution) exactly when tan beta <= friction, and slides
    along the fracture above.
Both are written as case files are (fractures meeting end to end, a fracture
from boundary to boundary) and go through the case check; the last tests run
them through the command line as a user does.
"""
import json

import numpy as np
import pytest

from networks import to_toml
from wingcrack import cli
from wingcrack.case import Case
from wingcrack.errors import ComputationError
from wingcrack.face_values import pair_states
from wingcrack.io.faces import SLIP, STICK
from wingcrack.step import Timer, discretise

E, NU = 1e10, 0.25
#: two direct solves (MUMPS on K, a dense one on the pair system) of a system of condition ~1e8 between
#: them: round-off of the displacement scale is ~1e-13 (measured 7e-14 to 3e-13); a sliding block or a
#: wrong rigid amplitude is off by the displacement scale itself
ROUND_OFF = 1e-10


def _case_dict(fractures, bc, plane="strain", body=None, size=(2.0, 2.0)):
    d = {"title": "floating", "material": {"E": E, "nu": NU, "KIc": 1e6, "plane": plane, "density": 2700.0},
         "domain": {"shape": "rectangle", "corner": [0.0, 0.0], "size": list(size)},
         "fractures": fractures,
         "bc": bc, "mesh": {"size": 0.2, "tip_size": 0.02}}
    if body:
        d["body"] = body
    return d


def _case(*args, **kw):
    return Case.from_dict(_case_dict(*args, **kw))


def _solve(case):
    d = discretise(case, case.fractures, Timer())
    d.solver.solve(1.0)
    x = np.asarray(d.cm.x)
    return d, x, d.problem.nodal_displacements(np.arange(len(x)))


def _block_dict(faces, p=1e6, shear=0.0):
    fr = {"faces": faces, **({"friction": 0.6} if faces == "coulomb" else {})}
    bc = [{"on": "top", "traction": [shear, -p]}, {"on": "bottom", "traction": [-shear, p]},
          {"on": "left", "traction": [p, -shear]}, {"on": "right", "traction": [-p, shear]},
          {"at": [0.0, 0.0], "displacement": [0.0, 0.0]}, {"at": [2.0, 0.0], "displacement_y": 0.0}]
    c = [[0.7, 0.7], [1.3, 0.7], [1.3, 1.3], [0.7, 1.3]]
    return [{"points": [c[i], c[(i + 1) % 4]], **fr} for i in range(4)], bc


def _block(faces, p=1e6, shear=0.0, body=None):
    return _solve(_case(*_block_dict(faces, p, shear), body=body))


@pytest.mark.parametrize("faces", ["coulomb", "frictionless"])
def test_a_block_under_hydrostatic_compression_is_the_uncut_plate(faces):
    d, x, u = _block(faces)
    assert not d.cm.tips
    # plane strain, sigma = -p I: eps = -p (1 + nu) (1 - 2 nu) / E in both directions, u = eps x
    exact = -1e6 * (1 + NU) * (1 - 2 * NU) / E * x
    assert np.abs(u - exact).max() <= ROUND_OFF * np.abs(exact).max()
    state, closed = pair_states(d)
    assert closed.all()
    if faces == "coulomb":
        assert np.all(state == STICK)   # no shear on any face: every pair stuck
    assert d.contact.result.alpha.shape == (3,)   # the block floats: three rigid modes, all fixed


def test_a_block_is_held_by_friction_against_its_weight_and_by_interlock_against_shear():
    d, _, u = _block("coulomb", body={"gravity": [0.0, -9.8]})
    assert np.all(pair_states(d)[0] == STICK) and np.all(np.isfinite(u))
    # frictionless faces on four sides hold a square block against a shear of the plate too
    d, _, u = _block("frictionless", shear=3e5)
    assert np.any(pair_states(d)[1]) and np.abs(u).max() < 1e-3


def test_a_block_whose_faces_all_open_is_loose_and_put_in_the_middle():
    """Biaxial tension: the cavity opens round the block, which carries no load; its place is not
    determined by the equations (any place with open faces is a solution): it is put where the least
    opening of its faces is the largest (the middle of its opening), by a rigid motion."""
    d, x, u = _block("coulomb", p=-1e5)
    res = d.contact.result
    assert res.loose == 3 and not np.any(pair_states(d)[1])
    inside = np.linalg.norm(x - 1.0, axis=1, ord=np.inf) < 0.3 - 1e-9
    # the block's displacement is a rigid motion (no load on it, all faces open): a least-squares fit
    # of a translation and a rotation leaves round-off
    xi = x[inside] - 1.0
    A = np.block([[np.ones((len(xi), 1)), np.zeros((len(xi), 1)), -xi[:, 1:2]],
                  [np.zeros((len(xi), 1)), np.ones((len(xi), 1)), xi[:, 0:1]]])
    b = np.r_[u[inside, 0], u[inside, 1]]
    fit = np.linalg.lstsq(A, b, rcond=None)[0]
    assert np.abs(A @ fit - b).max() <= ROUND_OFF * np.abs(u).max()
    rows = d.contact.rows
    w = (res.jump - res.reference)[rows.normal]
    assert np.all(w > 0)
    G = d.contact.G[rows.normal]
    for k in range(3):   # no rigid motion of the block widens its narrowest opening
        for step in (-0.01, 0.01):
            moved = w + step * np.mean(w) * G[:, k] / np.abs(G[:, k]).max()
            assert np.min(moved) <= np.min(w) * (1 + 1e-9)


def _strip_dict(beta_deg, friction, p=1e6):
    bc = [{"on": "left", "displacement_x": 0.0}, {"at": [0.0, 0.0], "displacement_y": 0.0},
          {"on": "right", "traction": [-p, 0.0]}]
    t = 0.25 * np.tan(np.radians(beta_deg))
    return [{"points": [[1.0 + t, 0.0], [1.0 - t, 0.5]], "faces": "coulomb", "friction": friction}], bc


def _strip(beta_deg, friction, p=1e6):
    return _solve(_case(*_strip_dict(beta_deg, friction, p), plane="stress", size=(2.0, 0.5)))


@pytest.mark.parametrize("offset", [-1.0, -0.1])
def test_a_strip_cut_across_is_held_below_the_friction_angle(offset):
    friction = 0.6
    beta = np.degrees(np.arctan(friction)) + offset
    d, x, u = _strip(beta, friction)
    exact = np.c_[-1e6 / E * x[:, 0], NU * 1e6 / E * x[:, 1]]   # plane stress, sigma_xx = -p
    assert np.abs(u - exact).max() <= ROUND_OFF * np.abs(exact).max()
    assert np.all(pair_states(d)[0] == STICK)


@pytest.mark.parametrize("offset", [0.1, 1.0])
def test_a_strip_cut_across_slides_above_the_friction_angle(offset):
    friction = 0.6
    with pytest.raises(ComputationError, match=r"the piece around \(1\.4\d*, 0\.25\) slides along fracture 0"):
        _strip(np.degrees(np.arctan(friction)) + offset, friction)


def test_a_strip_pulled_at_its_end_is_pulled_away_from_the_fracture():
    with pytest.raises(ComputationError, match=r"the piece around \(1\.4\d*, 0\.25\) is pulled away from its faces"):
        _strip(20.0, 0.6, p=-1e6)


def test_the_block_and_the_strip_as_a_user_runs_them(tmp_path, capsys):
    """`check` accepts both networks; `sif` holds the block (every pair stuck) and a strip below the
    friction angle, and fails at 1 degree above it with the mechanism named, in summary.json too."""
    friction = 0.6
    cases = {"block": _case_dict(*_block_dict("coulomb")),
             "held": _case_dict(*_strip_dict(np.degrees(np.arctan(friction)) - 1.0, friction),
                                plane="stress", size=(2.0, 0.5)),
             "slides": _case_dict(*_strip_dict(np.degrees(np.arctan(friction)) + 1.0, friction),
                                  plane="stress", size=(2.0, 0.5))}
    for name, d in cases.items():
        path = tmp_path / f"{name}.toml"
        path.write_text(to_toml(d))
        assert cli.main(["check", str(path), "--quiet"]) == 0
        out = tmp_path / name
        status = cli.main(["sif", str(path), "-o", str(out), "--quiet"])
        summary = json.loads((out / "summary.json").read_text())
        if name == "slides":
            assert status == 1 and summary["status"].startswith("failed: step 0: the piece around (1.4")
            assert "slides along fracture 0" in summary["status"]
            assert "slides along fracture 0" in capsys.readouterr().err
        else:
            assert status == 0 and summary["status"] == "finished"
            contact = summary["steps"][0]["contact"]
            assert contact["stick"] == contact["pairs"] > 0 and contact["slip"] == 0


def test_a_run_that_cuts_a_piece_off_stops_there_with_the_mechanism(tmp_path):
    """A fracture from the top edge grows straight down (mode I under the right edge's tension) and
    reaches the bottom at step 2; a second fracture, parallel to the tension, keeps a tip in the
    run. Step 3's geometry leaves the right piece held by nothing (its faces are frictionless and
    the load pulls it away): the run stops there, the end of the loading path, every step before it
    kept, exit 0."""
    d = {"title": "cut through", "material": {"E": E, "nu": NU, "KIc": 1e5, "plane": "strain"},
         "domain": {"shape": "rectangle", "corner": [0.0, 0.0], "size": [1.0, 1.0]},
         "fractures": [{"points": [[0.6, 1.0], [0.6, 0.1]], "faces": "frictionless"},
                       {"points": [[0.15, 0.5], [0.35, 0.5]], "faces": "frictionless"}],
         "bc": [{"on": "right", "traction": [1e6, 0.0]}, {"on": "left", "displacement_x": 0.0},
                {"at": [0.0, 0.0], "displacement_y": 0.0}],
         "mesh": {"size": 0.1, "tip_size": 0.01}, "propagation": {"steps": 20, "length": 0.03}}
    path = tmp_path / "cut.toml"
    path.write_text(to_toml(d))
    out = tmp_path / "out"
    assert cli.main(["run", str(path), "-o", str(out), "--quiet", "--no-plots"]) == 0
    summary = json.loads((out / "summary.json").read_text())
    k = len(summary["steps"])
    assert k >= 2 and summary["status"] == (f"stopped: step {k}: the body cannot carry the load: the piece "
                                            "around (0.8, 0.5) is pulled away from its faces: contact cannot hold it")
    assert any(t["state"] == "boundary" for t in summary["steps"][-1]["tips"])   # the cut closed in the step before
    assert all((out / f"step_{i:04d}.vtu").exists() for i in range(k))
