"""wingcrack.material: E' and the Kolosov constant, each defined once,
checked against the paper's eq. (14) G = (1 + nu)(1 + kappa)/(4 E) K^2 (the
energy_release_rate kernel, written with kappa, not E'), and importable
without DOLFINx (the propagation loop and the checker use it)."""
import subprocess
import sys

import numpy as np
import pytest

import wingcrack_kernels as K
from wingcrack.material import e_prime, kappa, lame


@pytest.mark.parametrize("plane", ["strain", "stress"])
@pytest.mark.parametrize("nu", [0.0, 0.21, 0.25, 0.3, 0.4999])
def test_e_prime_matches_eq_14(plane, nu):
    E, KI, KII = 17e9, 1.3e6, -0.4e6
    G = K.energy_release_rate(KI, KII, E, nu, kappa(nu, plane))
    # two algebraically equal formulas: they differ by rounding only
    assert (KI ** 2 + KII ** 2) / e_prime(E, nu, plane) == pytest.approx(G, rel=1e-14)


def test_kolosov_constant_from_the_lame_constants():
    # plane strain kappa = 3 - 4 nu = (lam + 3 mu) / (lam + mu) with the 3D
    # Lame constants; plane stress the same with the plane-stress lambda
    for nu in (0.0, 0.2, 0.3, 0.45):
        for plane in ("strain", "stress"):
            lam, mu = lame(1e10, nu, plane)
            assert kappa(nu, plane) == pytest.approx((lam + 3 * mu) / (lam + mu), rel=1e-14)


def test_bad_plane_is_refused():
    with pytest.raises(ValueError, match="plane must be"):
        e_prime(1e10, 0.25, "plane_strain")
    with pytest.raises(ValueError, match="plane must be"):
        kappa(0.25, "plane_strain")
    assert np.isclose(e_prime(1e10, 0.25, "stress"), 1e10, rtol=0)


def test_importable_without_dolfinx():
    code = ("import sys; import wingcrack.material as m; m.e_prime(1.0, 0.3, 'strain'); "
            "bad = [k for k in ('dolfinx', 'ufl', 'petsc4py', 'ffcx') if k in sys.modules]; "
            "assert not bad, bad")
    subprocess.run([sys.executable, "-c", code], check=True)
