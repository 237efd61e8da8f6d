"""A fault pumped with a closed wing at one tip: the fluid flows along the
fault (its residual aperture a conduit) and the wing, pressed shut by
57-63 MPa of normal stress against some 38 MPa of fluid at the kink, starts
closed.

Two rules of the flow's storage make this march (flow_march.apertures,
flow.lubrication.Lubrication.volumes), on faces the contact holds apart:
- their aperture is never below a least one: a wing's is the residual
  aperture (a wing the contact shuts still leaves the fluid its rough
  faces' path; without it the shut wing's nodes stored and conducted
  nothing, an equation without a derivative, and the stimulation
  network's flow failed at its second growth);
- elsewhere on them, it is the positive part: their P2 opening dips below
  zero between a node the contact holds closed and an open one (the
  kink), a volume no fluid fills.
Open faces keep the signed opening (a moving tip's suction, the viscous
KGD), their wings none more (the viscous tip's asymptote).
The march of this fault with neither rule (its faces taken as open) failed
at 4.33 s ("the flow found no state"), with the positive part alone it
reaches its end; the stimulation network's growth needs the least aperture
too (its showcase's test).

Checked: the wing's edges hold the residual aperture at least; the march reaches
its end; every node's storage volume is non-negative at every step; the
fluid balance (injected = stored, no leak-off) to 1e-8 at every step, the
flow's promise. And the storage rule against its definition.
"""
from dataclasses import replace

import numpy as np

from wingcrack.case import Case
from wingcrack.contact.constraints import pre_existing_pairs
from wingcrack.flow.lubrication import Lubrication
from wingcrack.propagation import flow_march
from wingcrack.propagation.flow_march import FlowDrive, Geometry, march
from wingcrack.propagation.fracture_set import FractureSet
from wingcrack.step import Timer, discretise

#: the fault of the stimulation network's injected fracture, the in-situ stress of that case
A, B = np.array([8.917, 9.375]), np.array([11.083, 10.625])
#: the MTS kink of a pure mode II tip (rad): the wing's direction from the tip's outward one
KINK = -1.2309594173176557
END = 6.0   # s: past the failure at 4.33 s
RESIDUAL = 1e-4


def pumped_case():
    return Case.from_dict({
        "title": "a fault with a closed wing", "material": {"E": 60e9, "nu": 0.25, "KIc": 1.5e6, "plane": "strain"},
        "domain": {"shape": "rectangle", "corner": [0, 0], "size": [20, 20]},
        "fractures": [{"points": [A.tolist(), B.tolist()], "faces": "coulomb", "friction": 0.6}],
        "bc": [{"at": [0, 0], "displacement": [0.0, 0.0]}, {"at": [20, 0], "displacement_y": 0.0}],
        "stress": {"sxx": -80e6, "syy": -50e6, "sxy": 0.0},
        "mesh": {"size": 2.0, "tip_size": 0.15, "sectors": 16, "adaptive": False},
        "propagation": {"load": "injection", "steps": 1, "length": 0.15},
        "injection": {"fracture": 0, "rate": 1e-6, "residual_aperture": RESIDUAL, "viscosity": 1e-3,
                      "end_time": END, "frames": 1}})


def winged():
    """The case, its discretisation with a wing of 0.15 m at the fault's
    first tip, and the flow's geometry on it."""
    case = pumped_case()
    fset = FractureSet.from_case(case)
    t = (B - A) / np.linalg.norm(B - A)
    c, s = np.cos(KINK), np.sin(KINK)
    fset.fractures[0].extend(0, A + 0.15 * np.array([-c * t[0] + s * t[1], -s * t[0] - c * t[1]]))
    disc = discretise(case, fset.fractures, Timer())
    drive = FlowDrive.of(case)
    return case, disc, drive, Geometry.of(drive, case, disc, fset.fractures), fset


def test_a_pumped_fault_with_a_closed_wing_marches_dry_wing_and_all(monkeypatch):
    case, disc, drive, geo, fset = winged()
    wing = ~pre_existing_pairs(disc.cm, fset.fractures)[geo.net.pair[:, 2]]   # the wing's edges
    assert wing.any() and not wing.all()
    np.testing.assert_array_equal(geo.lub.constant[wing], 0.0)          # a wing's faces mate where open,
    np.testing.assert_array_equal(geo.lub._least[wing], RESIDUAL)       # and leave their roughness where shut
    np.testing.assert_array_equal(geo.lub._least[~wing], 0.0)
    seen = []
    commit = flow_march._commit

    def checked(drive, geo, new, dt, out):
        assert geo.lub.volumes(geo.faces.w).min() >= 0.0
        assert abs(new.imbalance()) < 1e-8
        seen.append(new.time)
        commit(drive, geo, new, dt, out)

    monkeypatch.setattr(flow_march, "_commit", checked)
    out = march(drive, geo, None, case.material.KIc)
    disc.solver.release()
    assert out.kind == "end" and seen[-1] == END and len(seen) > 10


def test_the_storage_of_faces_held_apart_is_no_less_than_their_least_aperture():
    """Lubrication.volumes against its definition on this network, with
    fields of one sign along each edge (where the floored field is the
    field or the floor, exactly, whatever the edge's parametrisation: its
    quarter points): positive everywhere, both kinds of faces store it
    whole; negative on every other edge, faces held apart store the
    positive edges' volume alone (the field with the negative edges
    zeroed, on open faces), open faces the signed field; negative
    everywhere, held faces store nothing, and with a least aperture r
    everywhere, the volume of r (its hydraulic aperture r too: the
    conductance of a uniform r, no derivative)."""
    case, disc, drive, geo, fset = winged()
    disc.solver.release()
    net = geo.net
    k = net.num_edges
    held = Lubrication(net, geo.lub.fluid, held=np.ones(k, bool))
    open_ = Lubrication(net, geo.lub.fluid)
    rng = np.random.default_rng(7)
    w = rng.uniform(1e-4, 1e-3, (k, 3))
    np.testing.assert_allclose(held.volumes(w), open_.volumes(w), rtol=1e-13)
    negative = np.arange(k) % 2 == 1
    signed = np.where(negative[:, None], -w, w)
    np.testing.assert_allclose(held.volumes(signed), open_.volumes(np.where(negative[:, None], 0.0, w)),
                               rtol=1e-13, atol=1e-13 * open_.volumes(w).max())
    assert open_.volumes(signed).sum() < held.volumes(signed).sum()   # open faces keep the overlap
    assert np.all(held.volumes(-w) == 0.0) and np.all(open_.volumes(-w) < 0.0)
    r = np.full((k, 3), RESIDUAL)
    rough = Lubrication(net, geo.lub.fluid, held=np.ones(k, bool), least=np.full(k, RESIDUAL))
    np.testing.assert_allclose(rough.volumes(-w), open_.volumes(r), rtol=1e-13)
    np.testing.assert_allclose(rough.conductances(-w), open_.conductances(r), rtol=1e-13)
    assert rough.conductance_derivative(-w).count_nonzero() == 0 and rough.volume_derivative(-w).count_nonzero() == 0
    np.testing.assert_allclose(rough.volumes(w + RESIDUAL), open_.volumes(w + RESIDUAL), rtol=1e-13)


def test_a_time_step_the_time_cannot_resolve_fails_the_step_saying_so():
    """A step whose length is at the round-off of the time (SHORTEST of
    it) is no step: the march fails there with its message, not with
    Lubrication.step's refusal of a step that does not go forward (which
    a run of ever shorter retries reached)."""
    import pytest

    from wingcrack.errors import ComputationError

    case, disc, drive, geo, fset = winged()
    t = geo.state.time + 10.0
    start = replace(geo.state, time=t)
    out = flow_march.Outcome("end", t)
    with pytest.raises(ComputationError, match="the flow found no state after 10 s"):
        flow_march._step(drive, geo, start, t * (1 + 0.5 * flow_march.SHORTEST), out)
    disc.solver.release()
