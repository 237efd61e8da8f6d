"""Paper Appendix B / issue 3 test 5: two equal collinear cracks.

Two cracks of length a, inner tips 2b apart, remote tension normal to them
(in a square plate of side 100 c). K at an inner tip over K of the isolated
crack against the exact two-crack solution (complete elliptic integrals, see
references.collinear_cracks), not the paper's approximate column. The plate
and mesh effects cancel largely in the ratio; tolerance 0.5% (measured
differences are ~1e-4).
"""
import numpy as np
import pytest

from builders import square_plate_with_cracks
from references import collinear_cracks
from wingcrack.api import sif
from wingcrack.case import Case


def _inner_tips(result, b):
    return [t for t in result.tips if abs(abs(t.x) - b) < 1e-9]


@pytest.mark.parametrize("b_over_a", [0.1, 0.2, 0.5, 1.0])
def test_inner_tip_amplification(b_over_a):
    a = 1.0
    b, c = b_over_a * a, (b_over_a + 1.0) * a
    cracks = [[[b, 0.0], [c, 0.0]], [[-c, 0.0], [-b, 0.0]]]
    tip = min(0.05, 0.25 * b)   # the rosettes must stay clear of each other
    kw = dict(size=10.0, tip_size=tip, nu=0.25)
    pair = sif(Case.from_dict(square_plate_with_cracks(100 * c, cracks, (0.0, 1.0, 0.0), **kw)))
    alone = sif(Case.from_dict(square_plate_with_cracks(100 * c, cracks[:1], (0.0, 1.0, 0.0), **kw)))
    k_inner, _ = collinear_cracks(b, c)
    exact = k_inner / np.sqrt(np.pi * a / 2)
    (iso,) = _inner_tips(alone, b)
    for t in _inner_tips(pair, b):
        assert abs(t.KI / iso.KI / exact - 1) < 5e-3, (t.KI / iso.KI, exact)
        assert abs(t.KI_M / iso.KI_M / exact - 1) < 5e-3, (t.KI_M / iso.KI_M, exact)
