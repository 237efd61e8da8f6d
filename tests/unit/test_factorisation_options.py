"""The MUMPS ordering of fem.elasticity.factorize: approximate minimum fill
(ICNTL(7) = 2) below AMF_BELOW DOFs, and what it changes.

PETSc 3.18 overwrites an ICNTL(7) given by MatMumpsSetIcntl before the
analysis, so the ordering goes through the options database: the test
reads the ordering MUMPS used (INFOG(7)) back, and checks that the
displacement equals the one of MUMPS's own ordering (PORD in this build
above about 10k DOFs), a second elimination of the same K in another
order: they differ by round-off, ~1e-14 of max |u| measured on the disc;
1e-12 leaves a factor 100 for the plate's conditioning."""
import numpy as np
import pytest
from petsc4py import PETSc

from builders import square_plate_with_cracks
from wingcrack.case import Case
from wingcrack.fem import elasticity
from wingcrack.fem.elasticity import ElasticProblem
from wingcrack.fem.mesh import to_dolfinx
from wingcrack.fem.pair_operator import PairOperator
from wingcrack.contact.constraints import constraint_rows
from wingcrack.loads import case_loads
from wingcrack.step import Timer, discretise

AMF, PORD, AMD = 2, 4, 0


def plate(faces="open"):
    t = np.array([np.sin(np.radians(60)), np.cos(np.radians(60))])
    d = square_plate_with_cracks(40.0, [[-t, t]], (2.0e5, -1.0e6, 3.0e5), size=0.9, tip_size=0.1)
    for f in d["fractures"]:
        f["faces"] = faces
    return Case.from_dict(d)


@pytest.fixture(scope="module")
def meshes():
    out = {}
    for faces in ("open", "frictionless"):
        case = plate(faces)
        out[faces] = case, discretise(case, case.fractures, Timer()).cm
    return out


def solve(case, cm, schur=False):
    m = case.material
    fm = to_dolfinx(cm)
    p = ElasticProblem(fm, m.E, m.nu, m.plane, case_loads(case, cm, case.fractures))
    rows = constraint_rows(cm, case.fractures)
    p.factorize(schur_dofs=PairOperator.pair_dofs(fm, rows) if schur else None)
    p.solve(1.0)
    ordering = p.solver.getPC().getFactorMatrix().getMumpsInfog(7)
    u = p.u.x.array.copy()
    p.destroy()
    return fm.num_dofs, ordering, u


def test_amf_below_the_threshold_same_displacement(meshes, monkeypatch):
    case, cm = meshes["open"]
    dofs, ordering, u = solve(case, cm)
    assert 10_000 < dofs < elasticity.AMF_BELOW
    assert ordering == AMF
    assert not PETSc.Options().getAll()        # the option was for that factorisation only
    monkeypatch.setattr(elasticity, "AMF_BELOW", 0)
    _, own, u_own = solve(case, cm)
    assert own == PORD                          # MUMPS's own choice at this size
    assert np.abs(u - u_own).max() <= 1e-12 * np.abs(u_own).max()


def test_schur_complement_orders_by_amd(meshes):
    """With the Schur complement on the pair dofs MUMPS orders by AMD
    whatever ICNTL(7) says: no option is set there, the ordering is AMD."""
    case, cm = meshes["frictionless"]
    _, ordering, _ = solve(case, cm, schur=True)
    assert ordering == AMD
    assert not PETSc.Options().getAll()


def test_the_lame_constants_by_their_names(meshes):
    """ElasticProblem's constants are lame_lambda and lame_mu (the shear
    modulus E / (2 (1 + nu)) in both planes); the former lam and mu still
    read them, with a DeprecationWarning."""
    from wingcrack.material import lame

    case, cm = meshes["open"]
    m = case.material
    p = ElasticProblem(to_dolfinx(cm), m.E, m.nu, m.plane, case_loads(case, cm, case.fractures))
    assert (float(p.lame_lambda.value), float(p.lame_mu.value)) == lame(m.E, m.nu, m.plane)
    assert float(p.lame_mu.value) == m.E / (2.0 * (1.0 + m.nu))
    with pytest.warns(DeprecationWarning, match="lame_mu"):
        assert p.mu is p.lame_mu
    with pytest.warns(DeprecationWarning, match="lame_lambda"):
        assert p.lam is p.lame_lambda
    p.destroy()
