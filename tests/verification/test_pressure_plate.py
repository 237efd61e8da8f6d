"""Issue 15 verifications 1, 2 and 3: a straight crack 2a in the large plate
of tests/verification/test_friction_plate.py (side L = 100 a, tip_size 0.05 a, 32
sectors; far field as the in-situ stress), now with a fluid pressure p in
the crack.

The crack lies on the x axis, its direction d = +x, its pair normal n = +y.
On the crack plane of a far field (sxx, syy, sxy): sigma_n = -syy
(compressive > 0), tau = sxy. The pressure pushes both faces apart; on
frictional faces contact and the Coulomb bound act on the effective
(contact) traction, total = contact - p n (Terzaghi). A straight crack in a
uniform field is then a Griffith crack under the effective face loads:

- open faces (or frictional faces pushed open, p > sigma_n): the faces
  carry -p, the crack feels the net opening pressure p - sigma_n and the
  whole shear tau (Sneddon; Tada, Paris & Irwin, The Stress Analysis of
  Cracks Handbook, 5.1):
      KI = (p - sigma_n) sqrt(pi a), KII = tau sqrt(pi a),
      w(x) = 4 (p - sigma_n) / E' sqrt(a^2 - x^2),  s(x) = 4 tau / E' sqrt(a^2 - x^2);
- closed Coulomb faces (p < sigma_n) under the effective normal stress
  sigma_n - p: the shear stress drop tau_eff = |tau| - c - mu (sigma_n - p)
  where positive (the faces slip), 0 otherwise (they stick):
      KI = 0, KII = sign(tau) tau_eff sqrt(pi a), s(x) = sign(tau) 4 tau_eff / E' sqrt(a^2 - x^2),
  and the contact normal traction t_n = -(sigma_n - p);
E' = E / (1 - nu^2) in plane strain, E in plane stress.

One mesh and one factorisation per plane serve every load case, as in
test_friction_plate: the plate is discretised once with the crack's pressure
P_REF and propagation.load = "pressure", so that the load factor multiplies
the pressure only: a case's pressure p is the solve at p / P_REF; its far
field is swapped in through the in-situ stress constant and its face law
through fresh contact rows. test_shared_plate_is_sif checks this route
against wingcrack.sif of the case written with its own pressure.

Verification 3 runs the loop (wingcrack.run, one step) on the same plate.

Measured (both planes): Sneddon's KI 0.033 % (plane strain; 0.030 % plane
stress) high by correlation, 0.041 % by the interaction integral, KII 5e-6
of KI, the opening within 0.034 % over the middle half; the frictional
crack's SIFs within 1.0e-3 of K_SCALE (the largest: correlation's KII of
the open cases, |tau| = 0.5 sigma), the slip and opening within 0.04 %,
the stuck crack's SIFs 7e-12 of K_SCALE, the friction law and
non-penetration to 8e-16; the critical injection pressure 0.076 % high (7
solves), KI 2e-9 of KII at it, the kink 70.5288 deg.
"""
import numpy as np
import pytest

import wingcrack
from builders import square_plate_with_cracks
from wingcrack import sifs
from wingcrack.case import Case
from wingcrack.contact.constraints import constraint_rows
from wingcrack.contact.friction import OPEN, SLIP, STICK
from wingcrack.fem.contact_problem import ContactProblem
from wingcrack.face_values import contact_record, face_values
from wingcrack.io.faces import face_state
from wingcrack.solver import Solver
from wingcrack.step import Discretisation, Timer, discretise

A, L, SIGMA, E, NU = 1.0, 100.0, 1.0e6, 10e9, 0.25
SIZE, TIP_SIZE = 10 * A, 0.05 * A
PLANES = ("strain", "stress")
#: the crack's pressure at load factor 1 on the shared plates (Pa)
P_REF = SIGMA
#: the load scale of every SIF tolerance
K_SCALE = SIGMA * np.sqrt(np.pi * A)
#: the issue's 0.5 % of K_SCALE on KI and KII: on this plate and mesh the
#: discretisation error of both methods is below 0.2 % of the load
#: (test_friction_plate: correlation's KII 0.20 % low, the interaction
#: integral's 0.02 %; the plate's finite size 0.03 %)
K_TOL = 5e-3
#: the issue's pointwise 1 % on the opening and slip over the middle half
#: (measured on the frictionless slip of this mesh: 0.015 %); near the tips
#: the P2 jump cannot follow sqrt(a - |x|)
PROFILE_TOL = 1e-2
#: relative residuals of the friction law and non-penetration (issue 14)
LAW_TOL = 1e-8


def e_prime(plane):
    return E / (1 - NU ** 2) if plane == "strain" else E


def ellipse(x):
    return np.sqrt(np.clip(A * A - x * x, 0.0, None))


def uniaxial(beta_deg, sigma=SIGMA):
    """(sxx, syy, sxy) of uniaxial compression sigma along (cos b, sin b)."""
    b = np.radians(beta_deg)
    m = np.array([np.cos(b), np.sin(b)])
    s = -sigma * np.outer(m, m)
    return float(s[0, 0]), float(s[1, 1]), float(s[0, 1])


def plate_dict(plane, stress=(0.0, 0.0, 0.0), faces="open", pressure=P_REF, load="pressure", **law):
    d = square_plate_with_cracks(L, [[[-A, 0.0], [A, 0.0]]], stress, size=SIZE, tip_size=TIP_SIZE, nu=NU,
                                 plane=plane)
    d["material"]["E"] = E
    d["fractures"][0].update(faces=faces, pressure=pressure, **law)
    d["propagation"]["load"] = load
    return d


def plate_case(*args, **kw):
    return Case.from_dict(plate_dict(*args, **kw))


@pytest.fixture(scope="module")
def plates():
    """plates(plane): the discretised plate of that plane (crack pressure
    P_REF, load = "pressure", frictionless faces: the contact pair dofs in
    the Schur complement), made once."""
    made = {}

    def get(plane):
        if plane not in made:
            case = plate_case(plane, faces="frictionless")
            made[plane] = discretise(case, case.fractures, Timer())
        return made[plane]

    yield get
    for d in made.values():
        d.solver.release()


def solve(plates, case, p):
    """`case` (plate_case) solved on the shared plate of its plane at the
    crack pressure p (the load factor p / P_REF): its far field, fresh
    contact rows of its face law; the Discretisation, its tips' SIFs (both
    methods) and its faces (io.faces.face_state)."""
    shared = plates(case.material.plane)
    assert list(shared.fluid.given) == [P_REF]
    problem = shared.problem
    problem.sigma0.value[:] = case.stress.tensor()
    contact = ContactProblem(problem, constraint_rows(shared.cm, case.fractures))
    disc = Discretisation(shared.cm, Solver(problem, contact), shared.fluid)
    disc.solver.solve(p / P_REF)
    tips = sifs.at_tips(case, disc, [f.points for f in case.fractures])
    return disc, tips, face_state(disc.cm, face_values(disc))


def check_sifs(tips, KI, KII):
    assert len(tips) == 2
    for t in tips:
        assert abs(t.KI - KI) < K_TOL * K_SCALE, (t.end, t.KI, KI)
        assert abs(t.KII - KII) < K_TOL * K_SCALE, (t.end, t.KII, KII)
        assert abs(t.KI_M - KI) < K_TOL * K_SCALE, (t.end, t.KI_M, KI)
        assert abs(t.KII_M - KII) < K_TOL * K_SCALE, (t.end, t.KII_M, KII)


def check_profile(st, name, amplitude):
    """st[name] (opening or slip) = amplitude sqrt(a^2 - x^2) pointwise
    within PROFILE_TOL over the middle half."""
    x = st["position"][:, 0]
    middle = np.abs(x) <= A / 2
    assert middle.sum() >= 10, "the middle half holds enough pairs to see the profile"
    ref = amplitude * ellipse(x[middle])
    err = np.abs(st[name][middle] - ref) / np.abs(ref)
    assert err.max() <= PROFILE_TOL, (name, err.max())


def test_shared_plate_is_sif():
    """The shared route (pressure P_REF, solved at the factor p / P_REF with
    load = "pressure", far field swapped) gives what wingcrack.sif computes
    from scratch for the case written with its own pressure p at factor 1
    (load = "scale"): the right-hand side is linear in the pressure, so the
    two are the same linear algebra up to round-off (1e-10 of K_SCALE)."""
    p = 0.3 * SIGMA
    case = plate_case("strain", uniaxial(45), "coulomb", pressure=p, load="scale", friction=0.5)
    base = plate_case("strain", faces="frictionless")
    made = discretise(base, base.fractures, Timer())
    try:
        _, shared, _ = solve(lambda plane: made, case, p)
    finally:
        made.solver.release()
    direct = wingcrack.sif(case).tips
    assert len(shared) == len(direct) == 2
    for a, b in zip(shared, direct):
        for k in ("KI", "KII", "KI_M", "KII_M"):
            assert abs(getattr(a, k) - getattr(b, k)) < 1e-10 * K_SCALE, (k, getattr(a, k), getattr(b, k))


# -- verification 1: Sneddon's pressurised crack ------------------------------

@pytest.mark.parametrize("plane", PLANES)
@pytest.mark.parametrize("p", (P_REF, 2.5 * P_REF))
def test_sneddon_pressurised_crack(plates, plane, p):
    """Open faces, the pressure p the only load: KI = p sqrt(pi a), KII = 0
    (both methods, 0.5 % of p sqrt(pi a)), the opening
    4 p / E' sqrt(a^2 - x^2) over the middle half (1 %), no slip; the faces
    are open and report the pressure p."""
    case = plate_case(plane)
    disc, tips, st = solve(plates, case, p)
    k = p * np.sqrt(np.pi * A)
    assert len(tips) == 2
    for t in tips:
        assert abs(t.KI - k) < K_TOL * k and abs(t.KI_M - k) < K_TOL * k, (t.end, t.KI, t.KI_M, k)
        assert abs(t.KII) < K_TOL * k and abs(t.KII_M) < K_TOL * k, (t.end, t.KII, t.KII_M)
    assert (st["state"] == OPEN).all() and not st["closed"].any()
    check_profile(st, "opening", 4 * p / e_prime(plane))
    assert np.abs(st["slip"]).max() < 1e-3 * 4 * p / e_prime(plane) * A
    assert np.allclose(face_values(disc)["pressure"], p, rtol=1e-12)


# -- verification 2: a closed frictional crack with pressure -----------------

#: per beta: (mu, c) of faces that stick at p = 0 (c + mu sigma_n > |tau|:
#: 30 deg, sigma_n = 0.25, |tau| = 0.433 sigma; 45 deg, 0.5 and 0.5 sigma),
#: so that the pressure is what makes them slip
STUCK_AT_ZERO = {30: (2.0, 0.0), 45: (1.2, 0.0)}
#: (beta, mu, c, p / sigma_n) of verification 2: stuck with a little
#: pressure (the bound c + mu (sigma_n - p) still above |tau|: 0.45 > 0.433,
#: 0.54 > 0.5 sigma), slipping (with and without cohesion) at 0.75 sigma_n,
#: pushed open at 1.5 and 3 sigma_n
PRESSURE_CASES = [(beta, mu, c, q) for beta, (mu, _) in STUCK_AT_ZERO.items()
                  for c, q in ((0.0, 0.1), (0.0, 0.75), (0.05 * SIGMA, 0.75), (0.0, 1.5), (0.0, 3.0))]


def frictional_reference(beta, mu, c, p):
    """(state, KI, KII, opening amplitude, slip amplitude) of the crack at
    pressure p (see the module doc); state "open", "slip" or "stick"."""
    _, syy, tau = uniaxial(beta)
    sigma_n = -syy
    if p > sigma_n:
        return "open", (p - sigma_n) * np.sqrt(np.pi * A), tau * np.sqrt(np.pi * A), 4 * (p - sigma_n), 4 * tau
    tau_eff = max(abs(tau) - c - mu * (sigma_n - p), 0.0)
    return ("slip" if tau_eff > 0 else "stick"), 0.0, np.sign(tau) * tau_eff * np.sqrt(np.pi * A), 0.0, \
        np.sign(tau) * 4 * tau_eff


def test_the_cases_cover_the_three_regimes():
    """The parameters of verification 2 do what their comments say: every
    crack sticks at p = 0, and the pressures give stick, slip and open at
    each beta (on the formulas alone; the solves are below)."""
    for beta, (mu, c) in STUCK_AT_ZERO.items():
        assert frictional_reference(beta, mu, c, 0.0)[0] == "stick"
        sigma_n = -uniaxial(beta)[1]
        states = [frictional_reference(beta, m, cc, q * sigma_n)[0] for b, m, cc, q in PRESSURE_CASES if b == beta]
        assert states == ["stick", "slip", "slip", "open", "open"], (beta, states)


@pytest.mark.parametrize("plane", PLANES)
@pytest.mark.parametrize("beta, mu, c, q", PRESSURE_CASES)
def test_frictional_crack_with_pressure(plates, plane, beta, mu, c, q):
    """Coulomb faces under uniaxial compression sigma at beta, pressure
    p = q sigma_n, one increment from zero slip: KI and KII of the reference
    (both methods, 0.5 % of K_SCALE); open: every pair open, the opening and
    slip ellipses of the net pressure and of tau (1 % over the middle half);
    slipping: every pair closed and slipping, the slip ellipse of tau_eff,
    and the contact (effective) tractions t_n = -(sigma_n - p) and
    t_t = sign(tau) (c + mu (sigma_n - p)) (1 % away from the tips, as in
    test_friction_plate); stuck: every pair sticks, no slip (1e-8 of the
    frictionless slip) and KI = KII = 0 (1e-8 of K_SCALE: a stuck closed
    crack transmits the uniform field, which P2 holds exactly); the friction
    law and non-penetration hold to LAW_TOL."""
    _, syy, tau = uniaxial(beta)
    sigma_n = -syy
    p = q * sigma_n
    case = plate_case(plane, uniaxial(beta), "coulomb", friction=mu, cohesion=c)
    disc, tips, st = solve(plates, case, p)
    state, KI, KII, w_amp, s_amp = frictional_reference(beta, mu, c, p)
    ep = e_prime(plane)
    free_slip = 4 * abs(tau) / ep * A   # the frictionless crack's slip at its centre
    if state == "open":
        assert (st["state"] == OPEN).all() and not st["closed"].any()
        check_sifs(tips, KI, KII)
        check_profile(st, "opening", w_amp / ep)
        check_profile(st, "slip", s_amp / ep)
    elif state == "slip":
        assert st["closed"].all() and (st["state"] == SLIP).all()
        check_sifs(tips, KI, KII)
        check_profile(st, "slip", s_amp / ep)
        away = np.abs(st["position"][:, 0]) < 0.8 * A
        assert np.allclose(st["normal_traction"][away], -(sigma_n - p), rtol=1e-2)
        assert np.allclose(st["tangential_traction"][away], np.sign(tau) * (c + mu * (sigma_n - p)), rtol=1e-2)
    else:
        assert st["closed"].all() and (st["state"] == STICK).all()
        assert np.abs(st["slip"]).max() < 1e-8 * free_slip
        for t in tips:
            for v in (t.KI, t.KII, t.KI_M, t.KII_M):
                assert abs(v) < 1e-8 * K_SCALE, (t.KI, t.KII, t.KI_M, t.KII_M)
        away = np.abs(st["position"][:, 0]) < 0.8 * A
        assert np.allclose(st["normal_traction"][away], -(sigma_n - p), rtol=1e-2)
    if state != "open":
        assert np.abs(st["opening"]).max() <= 1e-8 * free_slip
    rec = contact_record(disc)
    for name, value in {**(rec.friction or {}), **(rec.kkt or {})}.items():
        assert value < LAW_TOL, (name, value)


# -- verification 3: the critical injection pressure -------------------------

#: the in-situ stress: principal compressions S1 along (cos b, sin b), b = 30
#: deg from the crack, and S3 across: sigma_n = S1 sin^2 b + S3 cos^2 b =
#: 1.875 MPa, |tau| = (S1 - S3) sin b cos b = 0.6495 MPa
INJ_BETA, S1, S3 = 30.0, 3.0e6, 1.5e6
#: mu = 0.6 (Byerlee), c = 0: mu sigma_n = 1.125 MPa > |tau|, the crack
#: sticks at p = 0 and starts slipping at p_s = sigma_n - |tau| / mu =
#: 0.7925 MPa; KIc = 0.6 MPa m^0.5, (sqrt(3)/2) KIc / sqrt(pi a) =
#: 0.2932 MPa < |tau|, so the slipping crack reaches KIc before it opens:
#: p_c = sigma_n - (|tau| - (sqrt(3)/2) KIc / sqrt(pi a)) / mu = 1.2811 MPa,
#: between p_s and sigma_n
INJ_MU, INJ_KIC = 0.6, 0.6e6
#: the given pressure: the critical load factor is p_c / P_INJ = 0.64
P_INJ = 2.0e6
#: the issue's 0.5 % on p_c: KII grows as mu sqrt(pi a) dp once the crack
#: slips, so the SIF error (correlation's KII 0.2 % low, of a KII of 0.29
#: MPa sqrt(pi a) at p_c) moves p_c by 0.2 % 0.29 / 0.6 MPa, under 0.1 % of
#: p_c; the search's own tolerance is 1e-6
PC_TOL = 5e-3
#: the MTS kink of a tip with KI = 0: 2 atan(-sqrt(2) / 2) = -70.53 deg for
#: KII > 0 (tip frame), where K_eq = (2 / sqrt(3)) |KII|
KINK = np.degrees(2 * np.arctan(-np.sqrt(2) / 2))


def injection_stress():
    b = np.radians(INJ_BETA)
    m, m3 = np.array([np.cos(b), np.sin(b)]), np.array([-np.sin(b), np.cos(b)])
    s = -S1 * np.outer(m, m) - S3 * np.outer(m3, m3)
    return float(s[0, 0]), float(s[1, 1]), float(s[0, 1])


def injection_reference():
    """(sigma_n, |tau|, p_s, p_c) of the injection case (Pa)."""
    _, syy, tau = injection_stress()
    sigma_n = -syy
    p_s = sigma_n - abs(tau) / INJ_MU
    p_c = sigma_n - (abs(tau) - np.sqrt(3) / 2 * INJ_KIC / np.sqrt(np.pi * A)) / INJ_MU
    return sigma_n, abs(tau), p_s, p_c


def test_the_injection_case_crosses_stick_to_slip():
    """The numbers of verification 3 (formulas alone): the crack sticks at
    p = 0, and the critical pressure lies past the onset of slip and below
    the opening pressure, so the search crosses the change from stick to
    slip and the crack is closed at p_c (KI = 0)."""
    sigma_n, tau, p_s, p_c = injection_reference()
    assert sigma_n == pytest.approx(1.875e6) and tau == pytest.approx(0.649519e6, rel=1e-6)
    assert INJ_MU * sigma_n > tau
    assert 0 < p_s < p_c < sigma_n
    assert p_s == pytest.approx(0.792468e6, rel=1e-6) and p_c == pytest.approx(1.281071e6, rel=1e-6)
    assert p_c < P_INJ


def test_critical_injection_pressure(tmp_path):
    """One step of wingcrack.run with load = "pressure" on the stuck crack:
    step 0's load factor times the given pressure is p_c (0.5 %); at it the
    crack is closed and slips along its whole length, KI = 0 (1e-6 of KII,
    the round-off of the contact), K_eq = KIc = (2 / sqrt(3)) |KII|, and
    both wings kink at -sign(KII) 70.53 deg in their tip frames (the
    recorded theta and the grown segment)."""
    d = plate_dict("strain", injection_stress(), "coulomb", pressure=P_INJ, load="pressure", friction=INJ_MU)
    d["material"]["KIc"] = INJ_KIC
    d["propagation"]["steps"] = 1
    case = Case.from_dict(d)
    result = wingcrack.run(case, out=tmp_path / "out", plots=False)
    assert len(result.steps) == 1, result.status
    s0 = result.steps[0]
    _, _, _, p_c = injection_reference()
    assert s0["load_factor"] * P_INJ == pytest.approx(p_c, rel=PC_TOL)
    c = s0["contact"]
    assert c["closed"] == c["slip"] == c["pairs"] > 0, c
    assert len(s0["tips"]) == 2
    grown = result.fractures.fractures[0].points
    for t in s0["tips"]:
        assert abs(t["KI"]) <= 1e-6 * abs(t["KII"]), (t["KI"], t["KII"])
        assert t["K_eq"] == pytest.approx(INJ_KIC, rel=1e-5)
        assert t["K_eq"] == pytest.approx(2 / np.sqrt(3) * abs(t["KII"]), rel=1e-6)
        assert np.degrees(t["theta"]) == pytest.approx(np.sign(t["KII"]) * KINK, abs=1e-3)
        # the wing the step grew from this tip, in the tip's frame (end 1: x' = +x; end 0: x' = -x)
        ex = np.array([1.0, 0.0]) if t["end"] == 1 else np.array([-1.0, 0.0])
        ey = np.array([-ex[1], ex[0]])
        tip, new = (grown[-2], grown[-1]) if t["end"] == 1 else (grown[1], grown[0])
        assert np.allclose(tip, [A if t["end"] == 1 else -A, 0.0], atol=1e-12)
        seg = new - tip
        assert np.degrees(np.arctan2(seg @ ey, seg @ ex)) == pytest.approx(np.degrees(t["theta"]), abs=1e-6)
