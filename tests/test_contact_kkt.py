"""Issue 4 test 5: KKT conditions on every case in cases/ with contact, and
the active set does not depend on where the iteration starts."""
from pathlib import Path

import numpy as np
import pytest

from wingcrack.api import solve_initial
from wingcrack.case import Case
from wingcrack.contact.active_set import solve_active_set

CASES = sorted(p for p in (Path(__file__).parents[1] / "cases").glob("*.toml")
               if any(f.faces != "open" for f in Case.from_toml(p).fractures))


@pytest.mark.parametrize("path", CASES, ids=lambda p: p.stem)
def test_kkt_and_initial_guess(path):
    sol = solve_initial(Case.from_toml(path))
    res, rows, op = sol.contact.result, sol.contact.rows, sol.contact.op
    # feasibility (w + g >= 0), sign (mu >= 0) and complementarity (mu (w+g)
    # = 0) to 1e-8 of the load scale: the active set is exact, so only the
    # round-off of the small dense solve remains
    for name, value in res.kkt_residuals(rows.gap, rows.normal).items():
        assert value < 1e-8, (name, value)
    target = np.where(rows.normal, -rows.gap, rows.slip)
    for start in (np.ones(len(rows), bool), np.zeros(len(rows), bool)):
        other = solve_active_set(op.S, res.jump0, target, rows.normal, active=start)
        assert np.array_equal(other.active, res.active)
        assert np.allclose(other.mu, res.mu, rtol=1e-9, atol=1e-12 * np.abs(res.mu).max())
