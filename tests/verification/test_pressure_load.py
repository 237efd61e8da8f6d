"""Issue 15 verification 4: a fracture's pressure is the face traction -p n.

The pressure's load (loads.face_pressure_forces: the consistent P2 nodal
forces summed edge by edge, quarter-point edges included) against the same
traction written by hand as a UFL boundary integral over the crack faces,
int -p n_out . v ds, which DOLFINx integrates on its own facets (the split
crack faces are exterior facets of the mesh; n_out is their outward normal).
The displacements from the one factorisation must agree to round-off: 1e-10
of the largest displacement (both are the same discrete load, assembled two
ways; measured 1e-15)."""
import numpy as np
import pytest
import ufl
from dolfinx import fem, mesh as dmesh
from dolfinx.fem import petsc as fpetsc

from builders import square_plate_with_cracks
from wingcrack.case import Case
from wingcrack.step import Timer, discretise

A, P = 1.0, 2.0e6


@pytest.mark.parametrize("crack", [[[-A, 0.0], [A, 0.0]], [[-A, -0.3], [0.0, 0.2], [0.8, 0.1]]],
                         ids=["straight", "kinked"])
def test_open_faces_with_pressure_equal_the_traction_written_by_hand(crack):
    d = square_plate_with_cracks(20.0, [crack], (0.0, 0.0, 0.0), size=2.0, tip_size=0.05)
    d["fractures"][0].update(faces="open", pressure=P)
    case = Case.from_dict(d)
    disc = discretise(case, case.fractures, Timer())
    u_pressure = disc.problem.solve(1.0).x.array.copy()

    # by hand: the exterior facets on the crack polyline, -p n_out on them
    p = disc.problem
    msh, V = p.fm.mesh, p.fm.V
    pts = np.asarray(crack, float)

    def on_crack(x):
        xy = x[:2].T
        dist = np.full(len(xy), np.inf)
        for a, b in zip(pts[:-1], pts[1:]):
            t = np.clip((xy - a) @ (b - a) / np.dot(b - a, b - a), 0.0, 1.0)
            dist = np.minimum(dist, np.linalg.norm(xy - (a + t[:, None] * (b - a)), axis=1))
        return dist < 1e-9

    msh.topology.create_connectivity(msh.topology.dim - 1, msh.topology.dim)
    facets = dmesh.locate_entities_boundary(msh, msh.topology.dim - 1, on_crack)
    tags = dmesh.meshtags(msh, msh.topology.dim - 1, facets, np.full(len(facets), 1, dtype=np.int32))
    ds = ufl.Measure("ds", domain=msh, subdomain_data=tags)
    v = ufl.TestFunction(V)
    n = ufl.FacetNormal(msh)
    b = fpetsc.assemble_vector(fem.form(ufl.inner(-P * n, v) * ds(1)))
    fpetsc.apply_lifting(b, [p.a], bcs=[p.bcs])
    from petsc4py import PETSc
    b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
    fpetsc.set_bc(b, p.bcs)
    u = fem.Function(V)
    p.solver.solve(b, u.vector)
    u.x.scatter_forward()
    scale = np.abs(u_pressure).max()
    assert scale > 0
    np.testing.assert_allclose(u.x.array, u_pressure, atol=1e-10 * scale)
    disc.solver.release()
