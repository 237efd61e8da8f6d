"""The flow along the fractures alone (wingcrack.flow), against closed
forms of pressure diffusion in a conduit of fixed hydraulic aperture w_h:
the storage c_f w_h dp/dt and the cubic law's flux -w_h^3 / (12 eta) dp/ds
make it the heat equation with the diffusivity alpha = w_h^2 / (12 eta c_f)
(tests/references.py). The networks are the faces of real crack meshes
(gmsh, quarter-point tips), their openings held at zero: the faces do not
move (the coupling with the mechanics is tested elsewhere).

Time steps: backward Euler, geometric from t1 / 200 by a factor 1.02
(dt / t -> 2 %); the error measured over two decades of time [t1, 100 t1],
t1 the time at which the diffusion length sqrt(4 alpha t) spans ten flow
segments. Tolerance 1 % (the issue's); measured (max over nodes and times,
relative to the pressure step or rise):
    pressure step dp at the fault's centre     2.1e-3
    a rate at a T-junction (three branches)    4.4e-3 (at the junction, early: 10 segments)
the first mostly backward Euler's (1.05 per step: 6.1e-3; 1.02: 2.2e-3),
the conduits long enough that their ends change nothing (erfc(4) ~ 1e-8).
Carter's leak-off and a conduit drained below the floor (0) against
closed forms to the Newton residual (1e-12).
"""
import numpy as np
import pytest

from meshing import Domain, crack_mesh
from references import diffusion_flux, diffusion_step
from wingcrack.flow.lubrication import Fluid, Lubrication, Source
from wingcrack.flow.network import FlowNetwork

WH, ETA, CF = 1e-4, 1e-3, 1e-8           # m, Pa s, 1/Pa
ALPHA = WH ** 2 / (12 * ETA * CF)        # m^2/s
K = WH ** 3 / (12 * ETA)                 # m^3 / (Pa s): the conduit's conductivity
P0 = 1.0e6
TIP = 0.25                               # m: edges of 2 TIP along the fractures, flow segments of TIP
#: the issue's tolerance
TOL = 0.01
#: the balance injected = stored + leaked, relative to the fluid there was (issue 28's measure)
BALANCE = 1e-8


def conduit(cm):
    """The flow on every face of cm, a conduit of aperture WH (rigid faces)."""
    net = FlowNetwork.of(cm)
    k = net.num_edges
    return net, Lubrication(net, Fluid(ETA, CF, P0), constant=np.full((k, 3), WH), hydraulic=np.full(k, WH))


def march(lub, state, source_at, t1):
    """Backward Euler from t = 0 to 100 t1 (module doc); yields each state."""
    t, dt = 0.0, t1 / 200
    while t < 100 * t1 * (1 - 1e-12):
        t_next = min(t + dt, 100 * t1)
        state, _ = lub.step(state, t_next, source_at(t, t_next))
        t, dt = t_next, 1.02 * dt
        assert abs(state.imbalance()) < BALANCE
        yield state


def test_a_pressure_step_diffuses_along_a_fault_as_erfc():
    L = 100.0
    cm = crack_mesh(Domain("rectangle", corner=[-3 * L, -3 * L], size=[6 * L, 6 * L]),
                    [np.array([[-L, 0.0], [L, 0.0]])], [], size=0.6 * L, tip_size=TIP)
    net, lub = conduit(cm)
    dp = 1.0e5   # c_f dp = 1e-3: the density's change is no part of the closed form
    source = Source(net.point_weights([0.0, 0.0], 0), pressure=P0 + dp)
    t1 = (10 * TIP) ** 2 / (4 * ALPHA)    # sqrt(4 alpha t1) = 10 TIP
    assert np.sqrt(4 * ALPHA * 100 * t1) * 4 <= L
    errors = []
    for s in march(lub, lub.initial_state(P0, np.zeros((net.num_edges, 3))), lambda a, b: source, t1):
        if s.time >= t1 * (1 - 1e-9):
            ref = P0 + diffusion_step(net.x[:, 0], s.time, ALPHA, dp)
            errors.append(np.abs(s.pressure - ref).max() / dp)
    assert len(errors) > 200 and max(errors) < TOL, max(errors)


def test_a_rate_at_a_t_junction_splits_in_three():
    """Three branches of one aperture meet at the injection point: each takes
    a third of the rate, and the pressure there rises as at the end of a
    half-infinite conduit fed Q/3: the junction conserves the flux."""
    L = 60.0
    cm = crack_mesh(Domain("rectangle", corner=[-4 * L, -4 * L], size=[8 * L, 8 * L]),
                    [np.array([[-L, 0.0], [L, 0.0]]), np.array([[0.0, L], [0.0, 0.0]])], [], size=0.6 * L,
                    tip_size=TIP)
    net, lub = conduit(cm)
    weights = net.point_weights([0.0, 0.0])
    j = int(np.argmax(weights))
    assert weights[j] == 1.0 and np.count_nonzero(net.segments == j) == 3   # one node, three segments
    Q = 1e-7
    t1 = (10 * TIP) ** 2 / (4 * ALPHA)
    assert np.sqrt(4 * ALPHA * 100 * t1) * 2 < L
    errors = []
    for s in march(lub, lub.initial_state(P0, np.zeros((net.num_edges, 3))),
                   lambda a, b: Source(weights, volume=Q * (b - a)), t1):
        assert s.injected == pytest.approx(Q * s.time, rel=1e-12)
        if s.time >= t1 * (1 - 1e-9):
            rise = diffusion_flux(s.time, ALPHA, K, Q / 3)
            errors.append(abs(s.pressure[j] - P0 - rise) / rise)
    assert max(errors) < TOL, max(errors)


def test_carter_leak_off_of_a_fault_held_at_its_pressure():
    """A conduit held at its initial pressure at its centre (an
    incompressible fluid, rigid faces; a conduit of 1 cm, whose pressure
    drop to feed the leak-off is a few Pa of its 1 MPa: the pressure stays
    above the floor, no node drains): what leaks is replaced by what is
    injected, and Carter's law gives both, 2 C_L sqrt(t) per metre of both
    faces along the fracture's length (exact: the leak-off is integrated in
    time exactly at each node)."""
    L, CL, WH = 10.0, 1e-5, 1e-2
    cm = crack_mesh(Domain("rectangle", corner=[-3 * L, -3 * L], size=[6 * L, 6 * L]),
                    [np.array([[-L, 0.0], [L, 0.0]])], [], size=0.6 * L, tip_size=0.5)
    net = FlowNetwork.of(cm)
    k = net.num_edges
    lub = Lubrication(net, Fluid(ETA, 0.0, P0, leak_off=CL), constant=np.full((k, 3), WH),
                      hydraulic=np.full(k, WH))
    state = lub.initial_state(P0, np.zeros((k, 3)))
    source = Source(net.point_weights([0.0, 0.0], 0), pressure=P0)
    for t in (1.0, 2.0, 10.0, 100.0):
        state, _ = lub.step(state, t, source)
        ref = 2 * CL * np.sqrt(t) * 2 * L
        assert state.leaked == pytest.approx(ref, rel=1e-12)
        # the injected to the balance's round-off, of all the fluid there was (the conduit's fluxes, of
        # 1 MPa over a long step, carry the pressure's round-off: 1e-11 of fluid here)
        assert state.injected == pytest.approx(ref, abs=1e-9 * (state.initial + ref))
        assert abs(state.imbalance()) < BALANCE
        assert np.ptp(state.pressure) < 1e-4 * P0


@pytest.mark.parametrize("share", [0.5, 2.0])
def test_a_conduit_drained_below_its_fluid_holds_the_floor_and_the_balance(share):
    """A pump withdraws a share of the fluid a conduit can give by
    decompressing to 0 (rigid faces: sum V (1 - rho(0)/rho(P0))), then
    shuts in. In equilibrium the pressure is uniform: the one at which the
    conduit holds what is left, P0 + ln(1 - W / sum V) / c_f, where that
    is above 0; else 0 (a fluid under tension cavitates: the floor), the
    conduit partly filled by the fluid missing. The pressure never falls
    below 0 on the way, and the balance holds at every step, drained or
    not."""
    L = 10.0
    cm = crack_mesh(Domain("rectangle", corner=[-3 * L, -3 * L], size=[6 * L, 6 * L]),
                    [np.array([[-L, 0.0], [L, 0.0]])], [], size=0.6 * L, tip_size=0.5)
    net, lub = conduit(cm)
    state = lub.initial_state(P0, np.zeros((net.num_edges, 3)))
    total = float(np.sum(lub.volumes(np.zeros((net.num_edges, 3)))))   # the conduit's volume (rho = 1 at P0)
    decompression = total * (1 - lub.fluid.density(0.0))
    W = share * decompression
    weights = net.point_weights([0.0, 0.0], 0)
    t, dt = 0.0, 0.01
    while t < 1000.0:   # withdrawn over the first second (a diffusion time L^2 / alpha = 1.2 s), then shut in
        t_next = min(t + dt, 1000.0) if t >= 1.0 else min(t + 0.01, 1.0)
        state, _ = lub.step(state, t_next, Source(weights, volume=-W * (min(t_next, 1.0) - min(t, 1.0))))
        t, dt = t_next, 1.5 * dt if t_next >= 1.0 else dt
        assert np.min(state.pressure) >= 0.0
        assert abs(state.imbalance()) < BALANCE
    assert state.injected == pytest.approx(-W, rel=1e-12)
    if share < 1:   # the fluid left fills the conduit at a pressure above 0
        p = P0 + np.log(1 - W / total) / CF
        # the equilibrium to the Newton residual (RTOL of the fluid moved) over the storage c_f V: 1e-9 of the drop
        assert np.abs(state.pressure - p).max() < 1e-9 * (P0 - p), np.abs(state.pressure - p).max() / (P0 - p)
    else:   # the floor, the fluid missing (W beyond what decompression gives) where the pump drew it
        # at the floor (where the pump drew the fluid) or above it by what the diffusion has not yet evened
        # out (e^(-alpha t / L^2) of it: nothing at t = 1000 s; 3e-47 Pa measured)
        assert np.min(state.pressure[weights > 0]) == 0.0 and np.max(state.pressure) < 1e-12 * P0
        held = lub.fluid.density(0.0) * lub.volumes(np.zeros((net.num_edges, 3)))
        missing = held - state.fluid
        assert np.sum(missing) == pytest.approx(W - decompression, rel=1e-9)
        assert np.all(state.fluid >= 0.0) and np.all(missing >= -1e-9 * total)
