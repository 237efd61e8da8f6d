"""fem.compiled: forms, elements and expressions compiled once per run give
the numbers dolfinx.fem.form / fem.Expression / fem.FunctionSpace give on
the same mesh, to the last bit (the same generated kernels), and a form that
differs (quadrature degree, boundary tags, a material number in the
expression) gets its own compiled form. The reference is dolfinx's own
compile path, swapped in for the cache on the same mesh."""
from dataclasses import replace

import numpy as np
import pytest
import ufl
from dolfinx import fem

from builders import square_plate_with_cracks
from wingcrack.case import Case
from wingcrack.fem import compiled
from wingcrack.fem.cell_stress import cell_stress
from wingcrack.fem.elasticity import ElasticProblem
from wingcrack.fem.interaction_integral import InteractionIntegral
from wingcrack.fem.mesh import to_dolfinx
from wingcrack.fem.nodal_fields import local_nodal_fields
from wingcrack.loads import case_loads
from wingcrack.step import Timer, discretise
from wingcrack.tip_sifs import tip_sifs


def plate(nu=0.25, plane="strain"):
    t = np.array([np.sin(np.radians(60)), np.cos(np.radians(60))])
    return Case.from_dict(square_plate_with_cracks(40.0, [[-t, t]], (2.0e5, 1.0e6, 3.0e5), size=4.0,
                                                   tip_size=0.1, nu=nu, plane=plane))


@pytest.fixture(scope="module")
def crack_mesh():
    case = plate()
    return case, discretise(case, case.fractures, Timer()).cm


@pytest.fixture
def uncached(monkeypatch):
    """dolfinx's own compilation at every call, as before the cache."""
    monkeypatch.setattr(compiled, "form", lambda f, recipe: fem.form(f))
    monkeypatch.setattr(compiled, "expression", lambda e, X, recipe: fem.Expression(e, X))
    monkeypatch.setattr(compiled, "function_space", lambda mesh, element: fem.FunctionSpace(mesh, element))


@pytest.fixture
def checked(monkeypatch):
    monkeypatch.setattr(compiled, "CHECK", True)


def everything(case, cm):
    """Every number the fem layer computes on `cm`, through whichever
    compile path is in place."""
    m = case.material
    fm = to_dolfinx(cm)
    p = ElasticProblem(fm, m.E, m.nu, m.plane, case_loads(case, cm, case.fractures))
    p.solve(1.0)
    polylines = [np.asarray(f.points, float) for f in case.fractures]
    tips = tip_sifs(p, cm, polylines, case.domain, m.E, m.nu, m.plane, case.stress.tensor())
    out = {"u": p.u.x.array.copy(), "b": p.b.getArray().copy(), "energy": np.array([p.strain_energy()]),
           "KM": np.array([[t.KI_M, t.KII_M] for t in tips], float),
           "cell_stress": cell_stress(p)[2], **local_nodal_fields(p)}
    p.destroy()
    return out


def _cached_run(case, cm):
    everything(case, cm)             # compiles, if nothing did yet
    before = compiled.count()
    out = everything(case, cm)       # a new DOLFINx mesh: every form from the cache
    assert compiled.count() == before
    return out


def test_same_numbers_to_the_last_bit(crack_mesh, request):
    case, cm = crack_mesh
    cached = _cached_run(case, cm)
    request.getfixturevalue("uncached")
    reference = everything(case, cm)
    assert set(cached) == set(reference)
    for name in reference:
        # equal_nan: the nodal stress is singular (NaN) at the tip nodes, both ways
        assert np.array_equal(cached[name], reference[name], equal_nan=True), name
    assert np.all(np.isfinite(reference["KM"])) and np.abs(reference["KM"]).max() > 0


def test_checked_cache_on_two_materials(crack_mesh, checked):
    """Two materials in one process: the interaction integral has kappa
    (a number in its expression) in its recipe, so each gets its own
    compiled form; CHECK compares every cached form's UFL signature with
    its compiled one's."""
    case, cm = crack_mesh
    other = replace(case, material=replace(case.material, nu=0.3, plane="stress"))
    a, b = _cached_run(case, cm), _cached_run(other, cm)
    assert not np.array_equal(a["KM"], b["KM"])


def test_quadrature_degree_and_boundary_tags_get_their_own_form(crack_mesh, checked):
    case, cm = crack_mesh
    fm = to_dolfinx(cm)
    msh = fm.mesh
    x = ufl.SpatialCoordinate(msh)
    ds = ufl.Measure("ds", domain=msh, subdomain_data=fm.facet_tags)
    tags = sorted({int(t) for t in fm.facet_tags.values})
    assert len(tags) >= 2
    integrand = ufl.sin(x[0]) * ufl.exp(x[1] / 20.0)

    def forms():
        out = []
        for degree in (1, 2, 6):
            out.append(ufl.inner(integrand, 1.0) * ufl.dx(domain=msh, metadata={"quadrature_degree": degree}))
        out.append(integrand * ds(tags[0]))
        out.append(integrand * ds(tuple(tags)))
        return out

    before = compiled.count()
    cached = [fem.assemble_scalar(compiled.form(f, ("test.unit",))) for f in forms()]
    assert compiled.count() == before + 5
    again = [fem.assemble_scalar(compiled.form(f, ("test.unit",))) for f in forms()]
    assert compiled.count() == before + 5
    reference = [fem.assemble_scalar(fem.form(f)) for f in forms()]
    assert cached == reference == again
    # the forms are different, and so are their values
    assert len(set(reference)) == 5


def test_check_catches_a_recipe_two_expressions_share(crack_mesh, checked):
    case, cm = crack_mesh
    msh = to_dolfinx(cm).mesh
    x = ufl.SpatialCoordinate(msh)
    compiled.form(ufl.sin(x[0]) * ufl.dx(domain=msh), ("test.shared",))
    with pytest.raises(compiled.SignatureMismatch):
        compiled.form(ufl.cos(x[0]) * ufl.dx(domain=msh), ("test.shared",))


def test_quadrature_degree_of_the_interaction_integral(crack_mesh, checked, monkeypatch):
    """Another quadrature degree of the M-integral: its own compiled form,
    the values dolfinx.fem.form gives at that degree."""
    case, cm = crack_mesh
    m = case.material
    fm = to_dolfinx(cm)
    p = ElasticProblem(fm, m.E, m.nu, m.plane, case_loads(case, cm, case.fractures))
    p.solve(1.0)
    tip = cm.tips[0]

    def sifs(degree):
        M = InteractionIntegral(p, m.E, m.nu, m.plane, case.stress.tensor(), quadrature_degree=degree)
        return M.sifs(tip.x, tip.ex, tip.ey, 1.000001 * tip.h, 3 * tip.h), M._form_near(tip.x, 3 * tip.h)[0].ufcx_form

    (k6, u6), (k3, u3) = sifs(6), sifs(3)
    assert u6 is not u3 and sifs(6)[1] is u6
    cached = {6: k6, 3: k3}
    monkeypatch.setattr(compiled, "form", lambda f, recipe: fem.form(f))
    reference = {degree: sifs(degree)[0] for degree in (6, 3)}
    assert cached == reference
    assert cached[3] != cached[6]
    p.destroy()


def test_load_form_on_other_boundary_tags(crack_mesh, checked, monkeypatch):
    """The elastic load form with the in-situ traction on fewer outer tags,
    and with a traction on one tag: each its own compiled form, each the
    right-hand side dolfinx.fem.form gives."""
    case, cm = crack_mesh
    m = case.material
    loads = case_loads(case, cm, case.fractures)
    assert len(loads.outer_tags) >= 2
    variants = [loads, replace(loads, outer_tags=tuple(loads.outer_tags[:1])),
                replace(loads, tractions=[(int(loads.outer_tags[0]), 1.0e5, -2.0e5)])]

    def rhs(variant):
        p = ElasticProblem(to_dolfinx(cm), m.E, m.nu, m.plane, variant)
        b = p.assemble_rhs(1.0).getArray().copy()
        ufcx = p.L.ufcx_form
        p.destroy()
        return b, ufcx

    cached, ufcx = zip(*[rhs(v) for v in variants])
    assert len({id(u) for u in ufcx}) == 3                  # three compiled forms
    assert all(rhs(v)[1] is u for v, u in zip(variants, ufcx))   # found again on a new mesh
    monkeypatch.setattr(compiled, "form", lambda f, recipe: fem.form(f))
    reference = [rhs(v)[0] for v in variants]
    for c, r in zip(cached, reference):
        assert np.array_equal(c, r)
    assert not np.array_equal(reference[0], reference[1]) and not np.array_equal(reference[0], reference[2])


def test_load_form_with_tractions_on_the_same_tags_in_another_order(crack_mesh, checked, monkeypatch):
    """Tractions on two edges, given in either order: the same integrals by
    tag, but the first constant on another edge. They shared one compiled form,
    and the second case took the first's values on the swapped edges (a
    block case then a shear case in one process: a critical load of 0.647
    instead of 1.061)."""
    case, cm = crack_mesh
    m = case.material
    loads = case_loads(case, cm, case.fractures)
    a, b = (int(t) for t in loads.outer_tags[:2])
    first = replace(loads, tractions=[(a, 1.0e5, 0.0), (b, 0.0, -3.0e5)])
    second = replace(loads, tractions=[(b, 0.0, -3.0e5), (a, 1.0e5, 0.0)])   # the same loads

    def rhs(variant):
        p = ElasticProblem(to_dolfinx(cm), m.E, m.nu, m.plane, variant)
        out = p.assemble_rhs(1.0).getArray().copy()
        p.destroy()
        return out

    cached = [rhs(first), rhs(second)]
    monkeypatch.setattr(compiled, "form", lambda f, recipe: fem.form(f))
    reference = rhs(first)
    assert np.array_equal(cached[0], reference)
    np.testing.assert_allclose(cached[1], reference, rtol=0, atol=1e-12 * np.abs(reference).max())
