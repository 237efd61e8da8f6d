"""The crack-face term of the interaction integral for loaded faces.

When the faces carry a traction t (contact), the domain form of the
interaction integral needs

    I = I_domain - int_{faces} t . du^a/dx1 q ds,

t being the force per length on each face's own body, in the tip frame.
On the faces (theta = +-pi) du^a/dx1 = -du^a/dr, with (K^a = 1)
    mode I:  du^a/dx1 = (0, -+ c / sqrt r),   mode II: (-+ c / sqrt r, 0),
    c = (kappa + 1) / (4 G sqrt(2 pi)),  G the shear modulus, upper sign on the upper face.
The traction comes from the pair forces (nodal forces) through the face's
consistent P2 mass matrix, t = M^-1 F; the integrals use the isoparametric
map of each face edge, so on the quarter-point edges next to the tip
(r ~ xi^2) the 1/sqrt(r) integrand is smooth in xi and Gauss-Legendre is
accurate.
"""
from __future__ import annotations

import numpy as np

_XG, _WG = np.polynomial.legendre.leggauss(8)
_S = (_XG + 1) / 2
_W = _WG / 2
_N = np.stack([(1 - _S) * (1 - 2 * _S), _S * (2 * _S - 1), 4 * _S * (1 - _S)])   # a, b, mid
_DN = np.stack([4 * _S - 3, 4 * _S - 1, 4 - 8 * _S])


def face_term(x, edges, forces, tip, ex, ey, r_in, r_out, shear_modulus, kappa) -> tuple[float, float]:
    """int t . du^a/dx1 q ds over the face edges `edges` (k, 3) [a, b, mid]
    of one face, for the mode I and mode II auxiliary fields.

    x: (n, 2) node coordinates; forces: (n, 2) nodal forces on the nodes
    (global frame; zero where none); tip, ex, ey: tip position and frame;
    q = 1 for r <= r_in, linear to 0 at r_out (interpolated linearly along
    each edge from its vertex values, as the P1 q of the domain term)."""
    edges = np.asarray(edges, dtype=np.int64)
    if len(edges) == 0:
        return 0.0, 0.0
    nodes, local = np.unique(edges, return_inverse=True)
    local = local.reshape(edges.shape)
    nn = len(nodes)
    X = x[edges]                                        # (k, 3, 2)
    xq = np.einsum("iq,kid->kqd", _N, X)                # (k, q, 2)
    jac = np.linalg.norm(np.einsum("iq,kid->kqd", _DN, X), axis=2)  # (k, q)
    M = np.zeros((nn, nn))
    for a in range(3):
        for b in range(3):
            np.add.at(M, (local[:, a], local[:, b]), np.einsum("q,kq,q->k", _N[a] * _N[b], jac, _W))
    R = np.array([ex, ey], float)
    t_nodes = np.linalg.solve(M, forces[nodes] @ R.T)   # traction, tip frame (nn, 2)
    rel = xq - np.asarray(tip, float)
    Xl = rel @ R.T                                      # local coordinates
    r = np.linalg.norm(Xl, axis=2)
    # which face: upper (x2 > 0 side) or lower; on the face x2 ~ 0, so use
    # the side of the edge's opposite material: decided by the caller's sign
    dv = np.hypot(*(x[edges[:, :2]] - np.asarray(tip, float)).transpose(2, 0, 1))   # (k, 2)
    qv = np.clip((r_out - dv) / (r_out - r_in), 0.0, 1.0)
    q = qv[:, :1] * (1 - _S) + qv[:, 1:] * _S          # (k, q) P1 along the edge
    c = (kappa + 1) / (4 * shear_modulus * np.sqrt(2 * np.pi))
    g = c / np.sqrt(np.maximum(r, 1e-300))              # magnitude of du^a/dx1
    tq = np.einsum("iq,kid->kqd", _N, t_nodes[local])   # (k, q, 2)
    w = jac * _W * q * g
    return float(np.sum(tq[..., 1] * w)), float(np.sum(tq[..., 0] * w))
