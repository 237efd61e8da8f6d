"""The field files hold only finite numbers, and a crack-tip node's stress is
the documented convention (fem/nodal_fields.py): the mean over the cells
that have the tip as a vertex of each cell's stress at its 3-point Gauss
point nearest the tip (barycentric 2/3 at the tip vertex, 1/6 at the
others). The stress is singular at the tip (1/sqrt(r); the quarter-point
map's Jacobian vanishes there: the stress interpolated at the node is NaN).

The reference is computed here from the file alone, without DOLFINx: the
P2 isoparametric map of each tip cell from the file's node coordinates,
the file's displacements, Hooke's law of the case's material and its
in-situ stress. The same evaluator is first checked against the file at
the rosette's quarter-point nodes, where the written value is that of the
node's one cell (a quarter-point node on a crack face belongs to one cell)
or one of its two (inside the rosette)."""
from __future__ import annotations

import meshio
import numpy as np
import pytest

from builders import square_plate_with_cracks
from wingcrack.api import sif
from wingcrack.case import Case

E, NU = 10e9, 0.25
#: (sxx, syy, sxy) of each face kind: open faces under tension (mixed mode at
#: both tips), frictionless ones under compression (closed, in contact, sliding)
SIGMA0 = {"open": (2.0e5, 1.0e6, 3.0e5), "frictionless": (-2.0e5, -1.0e6, 3.0e5)}
T = np.array([np.sin(np.radians(60)), np.cos(np.radians(60))])
TIPS = (-T, T)


def plate(faces):
    d = square_plate_with_cracks(40.0, [[-T, T]], SIGMA0[faces], size=4.0, tip_size=0.1, nu=NU, sectors=16)
    d["fractures"][0]["faces"] = faces
    return Case.from_dict(d)


@pytest.fixture(scope="module", params=["open", "frictionless"])
def written(request, tmp_path_factory):
    """step_0000.vtu, faces_0000.vtu and the in-situ stress of a `sif` of
    the plate: open faces, and closed ones with contact tractions."""
    out = tmp_path_factory.mktemp(f"plate_{request.param}")
    sif(plate(request.param), out=out)
    return meshio.read(out / "step_0000.vtu"), meshio.read(out / "faces_0000.vtu"), SIGMA0[request.param]


def p2_stress(xc, uc, bary, sigma0):
    """(sxx, syy, sxy) of the P2 cell with nodes xc (6, 2), displacements
    uc (6, 2) (gmsh/VTK order: v0, v1, v2, m01, m12, m20) at the point of
    barycentric coordinates `bary` (L0, L1, L2): plane strain, the total
    stress with the in-situ stress sigma0 (sxx, syy, sxy)."""
    L0, L1, L2 = bary
    dxi = np.array([1 - 4 * L0, 4 * L1 - 1, 0, 4 * (L0 - L1), 4 * L2, -4 * L2])     # d/dL1 at L0 = 1 - L1 - L2
    deta = np.array([1 - 4 * L0, 0, 4 * L2 - 1, -4 * L1, 4 * L1, 4 * (L0 - L2)])    # d/dL2
    dref = np.vstack([dxi, deta])
    J = dref @ xc                             # J[a, b] = d x_b / d xi_a
    grad = np.linalg.solve(J, dref)           # (2, 6): d N / d x_b
    gu = uc.T @ grad.T                        # du_i / dx_j
    eps = 0.5 * (gu + gu.T)
    lam, mu = E * NU / ((1 + NU) * (1 - 2 * NU)), E / (2 * (1 + NU))
    s = lam * np.trace(eps) * np.eye(2) + 2 * mu * eps
    return np.array([s[0, 0] + sigma0[0], s[1, 1] + sigma0[1], s[0, 1] + sigma0[2]])


def in_plane(stress9):
    """(n, 3) (sxx, syy, sxy) of the file's 3 x 3 tensors (row-major)."""
    return stress9[:, [0, 4, 1]]


def tip_cells(m, tip):
    """The tip's node and its cells [(cell nodes (6,), which vertex is the tip)]."""
    node = int(np.argmin(np.linalg.norm(m.points[:, :2] - tip, axis=1)))
    assert np.linalg.norm(m.points[node, :2] - tip) < 1e-12
    cells = m.cells_dict["triangle6"]
    rows, corner = np.nonzero(cells[:, :3] == node)
    return node, [(cells[r], c) for r, c in zip(rows, corner)]


def test_every_value_of_both_files_is_finite(written):
    fields, faces, sigma0 = written
    # the compressed crack's faces are in contact: the face file holds their tractions
    assert (faces.point_data["normal_traction"] < 0).any() == (sigma0[1] < 0)
    for m in (fields, faces):
        assert np.isfinite(m.points).all()
        for name, v in m.point_data.items():
            assert np.isfinite(v).all(), name
        for name, blocks in m.cell_data.items():
            assert all(np.isfinite(b).all() for b in blocks), name
        for name, v in m.field_data.items():
            assert np.isfinite(v).all(), name


def test_tip_stress_is_the_mean_at_the_gauss_points_nearest_the_tip(written):
    m, _, sigma0 = written
    x, u, s = m.points[:, :2], m.point_data["displacement"][:, :2], in_plane(m.point_data["stress"])
    for tip in TIPS:
        node, cells = tip_cells(m, tip)
        assert len(cells) == 16                       # the rosette's sectors
        # the evaluator against the file where the field is defined: the quarter-point nodes,
        # the mid nodes of the cell's two edges at the tip vertex k
        edges = {0: ((3, 1), (5, 2)), 1: ((3, 0), (4, 2)), 2: ((4, 1), (5, 0))}   # (mid node, far vertex)
        ends = {3: (0, 1), 4: (1, 2), 5: (2, 0)}
        candidates = {}
        for c, k in cells:
            for j, far in edges[k]:
                # a quarter point: a quarter of the edge from the tip
                assert np.isclose(np.linalg.norm(x[c[j]] - tip), 0.25 * np.linalg.norm(x[c[far]] - tip), rtol=1e-9)
                bary = np.zeros(3)
                bary[list(ends[j])] = 0.5
                candidates.setdefault(int(c[j]), []).append(p2_stress(x[c], u[c], bary, sigma0))
        scale = max(np.abs(s[q]).max() for q in candidates)
        for q, values in candidates.items():
            off = min(np.abs(v - s[q]).max() for v in values)
            # the same formula in double precision (FFCx's kernel, numpy here): rounding only
            assert off < 1e-9 * scale, (q, off / scale)
        # the tip node: the convention, computed here
        gauss = []
        for c, k in cells:
            bary = np.full(3, 1 / 6)
            bary[k] = 2 / 3
            gauss.append(p2_stress(x[c], u[c], bary, sigma0))
        want = np.mean(gauss, axis=0)
        assert np.abs(s[node] - want).max() < 1e-9 * np.abs(want).max(), (s[node], want)
        vm = np.sqrt(want[0] ** 2 - want[0] * want[1] + want[1] ** 2 + 3 * want[2] ** 2)
        assert abs(m.point_data["von_mises"][node] - vm) < 1e-9 * vm
        # finite and of the near-tip field's size, not a value of its own
        assert 0.1 * scale < np.abs(want).max() < 10 * scale, (want, scale)
