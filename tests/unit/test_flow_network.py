"""The flow's network on a crack mesh's faces (wingcrack.flow.network):
one node per point of the faces, and functionals consistent with the
mechanics' own (loads.opening_functionals, the consistent P2 load of a
uniform pressure, verified against a UFL facet integral and Clapeyron in
tests/verification/test_pressure_load.py and test_injection_prebreakdown.py)."""
import numpy as np
import pytest

from meshing import Domain, crack_mesh
from wingcrack.flow.network import FlowNetwork
from wingcrack.loads import opening_functionals

HOST = np.array([[-1.0, 0.0], [1.0, 0.0]])
WING = np.array([[0.2, 0.8], [0.2, 0.0]])          # ends on the host: a T-junction
APART = np.array([[-1.0, -1.0], [0.5, -1.6]])       # meets nothing


@pytest.fixture(scope="module")
def mesh():
    return crack_mesh(Domain("rectangle", corner=[-5, -5], size=[10, 10]), [HOST, WING, APART], [], size=1.0,
                      tip_size=0.1)


def test_every_copy_of_a_face_node_is_one_flow_node(mesh):
    net = FlowNetwork.of(mesh)
    x = np.asarray(mesh.x)
    faces = np.unique(np.r_[mesh.crack_edges.ravel(), mesh.crack_edges_minus.ravel()])
    assert net.num_nodes == len(np.unique(x[faces], axis=0))
    junction = np.flatnonzero(np.linalg.norm(net.x - WING[-1], axis=1) < 1e-12)
    assert len(junction) == 1 and np.count_nonzero(net.segments == junction[0]) == 3
    for t in mesh.tips:   # a tip is a node at the end of one segment (zero flux: a dry tip)
        j = np.flatnonzero(np.linalg.norm(net.x - x[t.node], axis=1) == 0)
        assert len(j) == 1 and np.count_nonzero(net.segments == j[0]) == 1
    groups = net.components()
    assert len(np.unique(groups)) == 2   # the T, and the fracture apart


def test_lengths_and_volumes_of_a_unit_aperture(mesh):
    net = FlowNetwork.of(mesh)
    total = sum(np.linalg.norm(np.diff(p, axis=0), axis=1).sum() for p in (HOST, WING, APART))
    assert net.tributary().sum() == pytest.approx(total, rel=1e-14)
    V = net.volume_matrix() @ np.ones(3 * net.num_edges)
    np.testing.assert_allclose(V, net.tributary(), rtol=1e-13)


def test_the_load_of_a_uniform_pressure_is_the_mechanics_own(mesh):
    """The nodal pressure field p_i = 1 loads the faces exactly as the
    uniform unit pressure of loads.opening_functionals (to round-off), and
    the volume functional is its transpose: for any displacement, the sum
    of the nodal volumes is the opening integral."""
    n = len(mesh.x)
    net = FlowNetwork.of(mesh)
    F = net.load_matrix(n)
    uniform = opening_functionals(mesh, 3)
    scale = np.abs(uniform).max()
    np.testing.assert_allclose(F @ np.ones(net.num_nodes), uniform @ np.ones(3), atol=1e-14 * scale)
    u = np.random.default_rng(1).normal(size=2 * n)
    V = net.volume_matrix() @ (net.jump_matrix(n) @ u)
    assert V.sum() == pytest.approx((uniform.T @ u).sum(), rel=1e-12)
    np.testing.assert_allclose(F.T @ u, V, rtol=1e-12, atol=1e-14 * np.abs(V).max())
    # one fracture's network: its load is that fracture's column
    one = FlowNetwork.of(mesh, [2])
    np.testing.assert_allclose(one.load_matrix(n) @ np.ones(one.num_nodes), uniform[:, 2].toarray().ravel(),
                               atol=1e-14 * scale)


def test_a_point_source_between_nodes_is_split_by_the_hats(mesh):
    net = FlowNetwork.of(mesh, [0])
    a, b = net.segments[5]
    w = net.point_weights(0.3 * net.x[a] + 0.7 * net.x[b])
    assert w[a] == pytest.approx(0.3) and w[b] == pytest.approx(0.7) and w.sum() == pytest.approx(1.0)
