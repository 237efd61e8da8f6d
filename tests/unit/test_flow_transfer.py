"""The fluid carried from one mesh of the fractures to the next
(wingcrack.flow.transfer): by arc length from each fracture's first
pre-existing point, conserving the network's fluid exactly."""
from types import SimpleNamespace

import numpy as np
import pytest

from meshing import Domain, crack_mesh
from wingcrack.flow.lubrication import Fluid, FlowState, Lubrication
from wingcrack.flow.network import FlowNetwork
from wingcrack.flow.transfer import Samples, carry, sample

DOMAIN = Domain("rectangle", corner=[-5, -5], size=[10, 10])


def network(polylines, tip):
    cm = crack_mesh(DOMAIN, [np.asarray(p, float) for p in polylines], [], size=1.0, tip_size=tip)
    net = FlowNetwork.of(cm)
    return net, Lubrication(net, Fluid(1e-3))


def test_a_linear_field_carries_exactly_and_the_fluid_is_conserved():
    """A crack meshed twice (other tip sizes, and the second with a wing
    grown at its first end, its points prepended): the fluid, linear in x,
    is interpolated exactly by arc length, and the pressure's shape
    stretched over the new extent (both linear fields: exact); the new wing
    is dry; the total fluid is the old one to round-off."""
    old = SimpleNamespace(points=np.array([[-1.0, 0.0], [1.0, 0.0]]), pre=(0, 1))
    new = SimpleNamespace(points=np.array([[-1.3, 0.3], [-1.0, 0.0], [1.0, 0.0]]), pre=(1, 2))
    net0, lub0 = network([old.points], 0.1)
    net1, lub1 = network([new.points], 0.07)
    x0 = net0.x[:, 0]
    state = FlowState(3.0, 1e6 + 2e5 * x0, 1e-4 * lub0.lengths * (2.0 + x0), injected=5e-4, leaked=1e-5,
                      exposed=np.zeros(net0.num_nodes), initial=float(np.sum(1e-4 * lub0.lengths * (2 + x0))) - 4.9e-4)
    samples = sample(net0, state, [old], lub0.lengths)
    back = Samples.from_dict(samples.to_dict())
    moved = carry(back, net1, [new], lub1.lengths)
    on_old = (net1.x[:, 1] == 0.0)
    # the pressure's shape is stretched over the new extent: the old tips' pressures at the new tips
    wing_length = float(np.hypot(0.3, 0.3))
    s_new = np.where(on_old, net1.x[:, 0] + 1.0, -np.hypot(net1.x[:, 0] + 1.0, net1.x[:, 1]))
    s_old = (s_new + wing_length) * 2.0 / (2.0 + wing_length)
    np.testing.assert_allclose(moved.pressure, 1e6 + 2e5 * (s_old - 1.0), rtol=1e-12)
    wing = net1.x[:, 1] > 1e-9
    assert wing.any() and not moved.fluid[wing].any() and (moved.exposed[wing] == 3.0).all()
    assert moved.fluid.sum() == pytest.approx(state.fluid.sum(), rel=1e-13)
    assert (moved.injected, moved.leaked, moved.initial, moved.time) == (5e-4, 1e-5, state.initial, 3.0)
    # the fluid per metre is the old one, scaled by the conservation alone (the meshes' lengths differ)
    density = moved.fluid[on_old] / lub1.lengths[on_old]
    ratio = density / (1e-4 * (2.0 + net1.x[on_old, 0]))
    assert np.ptp(ratio) < 1e-12 and ratio[0] == pytest.approx(1.0, abs=0.05)
