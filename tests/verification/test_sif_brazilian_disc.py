"""Paper section 4.2, Table 2 / issue 3 test 4: the cracked Brazilian disc.

R = 42 mm, a = 5 mm, plane stress, E = 15 GPa, nu = 0.21, line loads f0 at the
poles, faces open (traction-free), phi = 0..90 deg. N = K sqrt(pi) R/(f0 sqrt a).
- displacement correlation (DC) and interaction integral (M) agree within
  0.3% of max(|KI|, |KII|): M is mesh-independent to 1e-4 here, DC's KII is
  0.1-0.25% low on a 32-sector rosette of radius a/20 (it falls with more
  sectors and smaller rosettes, see test_sif_rosette_convergence);
- the two tips agree within 0.1% (the problem is point-symmetric; only the
  unstructured mesh away from the rosettes differs);
- N lies within 3% of the paper's "present model" column (their mesh is
  coarser and their table shows ~2-5% scatter against Atkinson's series).
"""
import numpy as np
import pytest

from builders import brazilian_disc
from references import PAPER_TABLE2
from wingcrack.api import sif
from wingcrack.case import Case

R, A, F0 = 0.042, 0.005, 1.0e6
NORM = np.sqrt(np.pi) * R / (F0 * np.sqrt(A))
PHIS = [0, 15, 30, 45, 60, 75, 90]


@pytest.fixture(scope="module")
def results():
    # rosette h = a/20 with 32 sectors: the displacement-correlation KII error
    # is 0.32% at h = a/10 and 0.22% at a/20 (measured at phi = 15 deg)
    return {phi: sif(Case.from_dict(brazilian_disc(phi, tip_size=0.00025))) for phi in PHIS}


@pytest.mark.parametrize("phi", PHIS)
def test_dc_agrees_with_interaction_integral(results, phi):
    for t in results[phi].tips:
        scale = max(abs(t.KI), abs(t.KII))
        assert abs(t.KI - t.KI_M) < 3e-3 * scale, (t.KI, t.KI_M)
        assert abs(t.KII - t.KII_M) < 3e-3 * scale, (t.KII, t.KII_M)


@pytest.mark.parametrize("phi", PHIS)
def test_both_tips_agree(results, phi):
    t0, t1 = results[phi].tips
    scale = max(abs(t0.KI), abs(t0.KII))
    assert abs(t0.KI - t1.KI) < 1e-3 * scale
    assert abs(t0.KII - t1.KII) < 1e-3 * scale


@pytest.mark.parametrize("phi", PHIS)
def test_close_to_paper_table2(results, phi):
    NI_paper, NII_paper = PAPER_TABLE2[phi]
    scale = max(abs(NI_paper), abs(NII_paper))
    for t in results[phi].tips:
        assert abs(t.KI * NORM - NI_paper) < 0.03 * scale, (t.KI * NORM, NI_paper)
        # the crack is turned counter-clockwise from the load axis: KII >= 0
        # in the contract's tip frame at both tips, as in the paper
        assert abs(t.KII * NORM - NII_paper) < 0.03 * scale, (t.KII * NORM, NII_paper)
