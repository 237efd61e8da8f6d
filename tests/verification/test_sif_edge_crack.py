"""Paper section 4.1 / issue 3 test 3: single edge crack under tension.

Strip of width b, height 8b, edge crack of depth a at mid-height, uniform
tension sigma on its ends. Reference: KI = sigma sqrt(pi a) F(a/b) with
Tada's F (accurate to 0.5% for a/b <= 0.6); tolerance 1%: Tada's 0.5% plus
our ~0.1% and the (small) finite-height effect of a strip of height 8b.
"""
import numpy as np
import pytest
from scipy.integrate import quad

from builders import edge_crack_strip
from references import tada_edge_crack_F
from wingcrack.api import sif
from wingcrack.case import Case

SIGMA, E, NU = 1.0e6, 10e9, 0.25


@pytest.mark.parametrize("s", [0.3, 0.5])
def test_edge_crack_against_tada(s):
    r = sif(Case.from_dict(edge_crack_strip(s, sigma=SIGMA, size=0.1, tip_size=0.01)))
    (tip,) = r.tips
    K = SIGMA * np.sqrt(np.pi * s) * tada_edge_crack_F(s)
    assert abs(tip.KI / K - 1) < 0.01, tip.KI / K
    assert abs(tip.KI_M / K - 1) < 0.01, tip.KI_M / K
    # symmetric about the crack line: no mode II (1e-4 of K: round-off and
    # the unstructured mesh's asymmetry only)
    assert abs(tip.KII) < 1e-4 * K and abs(tip.KII_M) < 1e-4 * K


def test_strain_energy_converges_linearly():
    """Fig. 11 of the paper: with uniform refinement (element size h, rosette
    h/2) the strain-energy error falls like h: the crack-tip singularity
    (alpha = 1/2) bounds the rate at h^(2 alpha) = h (Pin & Pian 1973), eq. 39.

    The rate is fitted from successive differences U(h/2) - U(h), which need
    no reference; the extrapolated energy is then checked against the energy
    of Tada's F: U = U0 + int_0^a G(a') da' (load control), with
    U0 = sigma^2 b H / (2 E'), G = K^2 / E'. F's 0.5% accuracy moves that
    reference by up to 0.3% of U here, hence that tolerance.
    """
    b, H, s = 1.0, 8.0, 0.5
    Ep = E / (1 - NU ** 2)
    n = np.array([8, 16, 32, 64])
    U = []
    for k in n:
        h = b / k
        d = edge_crack_strip(s, sigma=SIGMA, size=h, tip_size=0.5 * h, height=H)
        # the paper's 16-sector rosette: with 32 sectors the tip region is
        # resolved so much better that the asymptotic rate only shows below
        # h = b/64 (measured rates 1.67, 1.42 on these meshes)
        d["mesh"]["sectors"] = 16
        r = sif(Case.from_dict(d))
        U.append(r.problem.strain_energy())
    U = np.array(U)
    dU = np.diff(U)
    assert np.all(dU > 0), "traction loading: the FE energy converges from below"
    rates = np.log2(dU[:-1] / dU[1:])
    # pre-asymptotic on the coarsest meshes (smooth-part error ~ h^4 still
    # visible), then the singular rate 1 is approached
    assert 0.85 < rates[-1] < 1.25, rates
    assert np.all(rates > 0.85), rates
    p = rates[-1]
    U_inf = U[-1] + dU[-1] / (2 ** p - 1)
    U_ref = SIGMA ** 2 * b * H / (2 * Ep) + SIGMA ** 2 * np.pi / Ep * quad(
        lambda x: x * tada_edge_crack_F(x / b) ** 2, 0, s * b)[0]
    assert abs(U_inf / U_ref - 1) < 3e-3, (U_inf, U_ref)
