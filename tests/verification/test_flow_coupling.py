"""The flow coupled to the faces' contact and friction (fem.coupled_faces,
fem.face_response): solved on the faces alone, it must be the whole
problem's solution, and a viscous fluid left alone must settle at the one
pressure of the toughness-dominated model (issue 28's balance), the second
method here.

- The pair system: the compliance of the faces' jump space gives the pair
  operator's own S (round-off), and the face-level solve at a pressure field
  gives the openings and contact forces of the whole solve with that field's
  nodal load (round-off: 1e-12 of the largest).
- A uniform field's nodal load is the pumped network's uniform pressure
  load: the same solution (round-off).
- dw/dp of a state set (closed, stuck and slipping pairs next to open ones)
  against finite differences that keep the set: 1e-6 (the differences'
  own truncation, the response being linear within a set).
- A crack under 10 MPa of confinement, water (viscous, compressible) pumped
  for 0.5 s into its closed faces and then shut in: the fluid opens it,
  flows and spreads; once its pressure has evened out it equals the
  pressure at which the crack holds the same fluid
  (propagation.fluid.balance_pressure on the same discretisation, solved to
  1e-10 of the fluid): 1e-9. The balance at every step: 1e-8.
"""
import numpy as np
import pytest

from wingcrack.case import Case
from wingcrack.flow.lubrication import Fluid, Lubrication, Source
from wingcrack.flow.network import FlowNetwork
from wingcrack.io.faces import SLIP, STICK
from wingcrack.propagation import fluid
from wingcrack.step import Timer, discretise

L, W = 1.0, 100.0
S0, P0 = 10e6, 5e6
C, ETA, WR, Q = 4.5e-10, 1e-3, 1e-5, 1e-5


def crack_case(faces="frictionless", sxy=0.0, **more):
    table = {"points": [[-L, 0.0], [L, 0.0]], "faces": faces}
    table.update(more)
    return Case.from_dict({
        "title": "crack", "material": {"E": 10e9, "nu": 0.25, "KIc": 1e9, "plane": "strain"},
        "domain": {"shape": "rectangle", "corner": [-W / 2, -W / 2], "size": [W, W]},
        "fractures": [table],
        "bc": [{"at": [-W / 2, -W / 2], "displacement": [0.0, 0.0]}, {"at": [W / 2, -W / 2], "displacement_y": 0.0}],
        "stress": {"sxx": -S0, "syy": -S0, "sxy": sxy},
        "mesh": {"size": W / 10, "tip_size": 0.05},
        "propagation": {"load": "injection", "steps": 1},
        "injection": {"fracture": 0, "rate": Q, "initial_pressure": P0, "compressibility": C,
                      "residual_aperture": WR}})


@pytest.fixture(scope="module")
def coulomb():
    """A Coulomb crack under shear, and a pressure field that opens its
    middle: open, stuck and slipping pairs at once."""
    case = crack_case("coulomb", sxy=1e6, friction=0.6)
    disc = discretise(case, case.fractures, Timer())
    net = FlowNetwork.of(disc.cm)
    faces = disc.coupled_faces(net)
    x = net.x[:, 0]
    p = P0 + 8e6 * np.exp(-(x / (0.4 * L)) ** 2)
    yield disc, net, faces, p
    disc.solver.release()


def test_the_face_level_solve_is_the_whole_solve(coulomb):
    disc, net, faces, p = coulomb
    S = disc.contact.op.S
    np.testing.assert_allclose(faces.response.S, S, atol=1e-12 * np.abs(S).max())
    w = faces.openings(p).ravel().copy()
    res = faces.result
    states = res.state[disc.contact.rows.coulomb]
    assert (w > 1e-9).any() and (states == STICK).any() and (states == SLIP).any()
    faces.complete(p)   # the whole displacement with the field's nodal load, through the ordinary solve
    whole = faces.response.openings_of_solution()
    np.testing.assert_allclose(whole, w, atol=1e-12 * np.abs(w).max())
    np.testing.assert_allclose(disc.contact.result.forces, res.forces, atol=1e-12 * np.abs(res.forces).max())


def test_a_uniform_field_loads_as_the_pumped_network(coulomb):
    disc, net, faces, _ = coulomb
    p = 12e6
    w = faces.openings(np.full(net.num_nodes, p)).ravel().copy()
    forces = faces.result.forces.copy()
    # the pumped network's load: its unit-pressure forces times the load factor
    disc.problem.set_face_forces(np.asarray(faces.load @ np.ones(net.num_nodes)).reshape(-1, 2))
    unit = disc.problem.loads.face_forces.copy()
    from wingcrack.loads import face_pressure_forces
    np.testing.assert_allclose(unit, face_pressure_forces(disc.cm, [1.0]), atol=1e-14 * np.abs(unit).max())
    disc.solver.solve(p)
    np.testing.assert_allclose(faces.response.openings_of_solution(), w, atol=1e-12 * np.abs(w).max())
    np.testing.assert_allclose(disc.contact.result.forces, forces, atol=1e-12 * np.abs(forces).max())


def test_the_derivative_of_a_state_set(coulomb):
    disc, net, faces, p = coulomb
    w0 = faces.openings(p).ravel().copy()
    set0 = (faces.result.active.copy(), faces.result.state.copy())
    W = faces.derivative()
    rng = np.random.default_rng(3)
    for _ in range(3):
        d = rng.normal(size=net.num_nodes) * 1e3   # 1 kPa: no state changes (checked)
        w1 = faces.openings(p + d).ravel()
        assert (faces.result.active == set0[0]).all() and (faces.result.state == set0[1]).all()
        np.testing.assert_allclose(w1 - w0, W @ d, atol=1e-6 * np.abs(W @ d).max())


def test_a_viscous_fluid_shut_in_settles_at_the_one_pressure_balance():
    case = crack_case()
    disc = discretise(case, case.fractures, Timer())
    net = FlowNetwork.of(disc.cm)
    faces = disc.coupled_faces(net)
    k = net.num_edges
    lub = Lubrication(net, Fluid(ETA, C, P0), constant=np.full((k, 3), WR))
    state = lub.initial_state(P0, faces.openings(np.full(net.num_nodes, P0)))
    disc.contact.accept()
    weights = net.point_weights([0.0, 0.0], 0)
    t, dt = 0.0, 1e-3
    while t < 0.5 - 1e-12:   # pumped
        t_next = min(t + dt, 0.5)
        state, _ = lub.step(state, t_next, Source(weights, volume=Q * (t_next - t)), faces)
        disc.contact.accept()
        t, dt = t_next, 1.2 * dt
        assert abs(state.imbalance()) < 1e-8
    assert state.pressure.max() > S0 and state.pressure.max() - state.pressure.min() > 1e5   # open, flowing
    for _ in range(30):   # shut in
        state, _ = lub.step(state, t + dt, Source(weights, volume=0.0), faces)
        disc.contact.accept()
        t, dt = t + dt, 1.5 * dt
        assert abs(state.imbalance()) < 1e-8
    p = state.pressure
    assert p.max() - p.min() < 1e-9 * p.mean()
    assert state.injected == pytest.approx(Q * 0.5, rel=1e-12)

    def volume_at(pressure):   # the crack's volume at one pressure: issue 28's, through the pumped load
        disc.problem.set_face_forces(np.asarray(faces.load @ np.ones(net.num_nodes)).reshape(-1, 2))
        disc.solver.solve(pressure)
        return float(disc.fluid.openings()[0]) + WR * 2 * L

    b = fluid.balance_pressure(volume_at, float(state.fluid.sum()), C, P0, S0, 1e5)
    assert p.mean() == pytest.approx(b.pressure, rel=1e-9)
    disc.solver.release()
