"""ElasticProblem.solve takes u from its last solutions where the right-hand
side lies in their span (b = b0 + lambda b1 is affine in the load factor):
against a solve of a fresh factorisation of the same K at that factor (the
reference: a second elimination of the same system, so they differ by
round-off, ~1e-15 of max |u|; 1e-12 leaves room for the plate's
conditioning, as tests/unit/test_factorisation_options.py argues)."""
import numpy as np
import pytest

from builders import square_plate_with_cracks
from wingcrack.case import Case
from wingcrack.fem.elasticity import ElasticProblem
from wingcrack.fem.mesh import to_dolfinx
from wingcrack.loads import case_loads
from wingcrack.step import Timer, discretise


def plate(sigma0):
    t = np.array([np.sin(np.radians(60)), np.cos(np.radians(60))])
    d = square_plate_with_cracks(40.0, [[-t, t]], sigma0, size=1.5, tip_size=0.2)
    d["bc"] += [{"on": "top", "traction": [0.0, 1e5]}, {"on": "bottom", "traction": [0.0, -1e5]}]
    return Case.from_dict(d)


def problem(case, cm):
    m = case.material
    p = ElasticProblem(to_dolfinx(cm), m.E, m.nu, m.plane, case_loads(case, cm, case.fractures))
    p.factorize()
    return p


def fresh(case, cm, load_factor):
    p = problem(case, cm)
    p.solve(load_factor)
    assert p.span_solves == 0
    u = p.u.x.array.copy()
    p.destroy()
    return u


@pytest.mark.parametrize("sigma0, solves_before_span", [((0.0, 0.0, 0.0), 1), ((2.0e5, -1.0e6, 3.0e5), 2)],
                         ids=["homogeneous", "in-situ stress"])
def test_a_solve_in_the_span_of_the_last_two_is_their_combination(sigma0, solves_before_span):
    case = plate(sigma0)
    cm = discretise(case, case.fractures, Timer()).cm
    p = problem(case, cm)
    factors = [1.0, 2.5, 0.37, 4.0]
    spanned = []
    for k, lam in enumerate(factors):
        p.solve(lam)
        spanned.append(p.span_solves)
        u_ref = fresh(case, cm, lam)
        assert np.abs(p.u.x.array - u_ref).max() <= 1e-12 * np.abs(u_ref).max(), lam
    # no fixed load: b(lambda) = lambda b(1) from the second solve on; with the in-situ stress
    # from the third (b0 + lambda b1 needs two)
    assert spanned == [max(0, k - solves_before_span + 1) for k in range(len(factors))]
    p.factorize()   # another factorisation forgets the solutions of the last
    p.solve(0.37)
    assert p.span_solves == 0
    p.destroy()


def closed_plate(sigma0):
    """The plate's crack pressed shut by a vertical compression on the top
    and bottom edges (frictionless faces in contact, no gap): the pair forces
    are linear in the load factor (proportional without in-situ stress)."""
    t = np.array([np.sin(np.radians(60)), np.cos(np.radians(60))])
    d = square_plate_with_cracks(40.0, [[-t, t]], sigma0, size=1.5, tip_size=0.2)
    d["fractures"][0]["faces"] = "frictionless"
    d["bc"] += [{"on": "top", "traction": [0.0, -1e5]}, {"on": "bottom", "traction": [0.0, 1e5]}]
    return Case.from_dict(d)


@pytest.mark.parametrize("sigma0, solves_before_span", [((0.0, 0.0, 0.0), 1), ((-2.0e5, -1.0e5, 3.0e4), 2)],
                         ids=["homogeneous", "in-situ stress"])
def test_pair_force_responses_in_the_span_of_the_last_two_are_their_combination(sigma0, solves_before_span):
    """PairOperator.add_forces takes K^-1 B mu from the last two responses
    where mu lies in their span: the contact solution at each load factor
    against a fresh discretisation's (the same mesh, its own factorisation
    and active set: round-off apart, the tolerance of the elastic span's
    test above)."""
    case = closed_plate(sigma0)
    disc = discretise(case, case.fractures, Timer())
    assert disc.contact.op is not None and disc.contact.op.m > 0
    factors = [1.0, 2.5, 0.37, 4.0]
    spanned = []
    for lam in factors:
        res = disc.contact.solve(lam)
        assert res.active.any()   # the faces are in contact: there are pair forces to respond to
        spanned.append(disc.contact.op.span_solves)
        ref = discretise(case, case.fractures, Timer())
        ref.contact.solve(lam)
        assert ref.contact.op.span_solves == 0
        u, u_ref = disc.problem.u.x.array, ref.problem.u.x.array
        assert np.abs(u - u_ref).max() <= 1e-12 * np.abs(u_ref).max(), lam
        ref.solver.release()
    assert spanned == [max(0, k - solves_before_span + 1) for k in range(len(factors))]
