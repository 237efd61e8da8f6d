"""Growth under a pump is quasi-static where it is stable: the two shipped
pumped cases (cases/three_fractures_injection_rate.toml, the 4.3 layout, and
cases/stimulation_network_rate.toml, the 16-fracture network), their first
steps.

A step of a pumped run is one of two kinds (propagation/injection.py):
- quasi-static: the pump brings the fluid until the first tip reaches KIc;
  the tip that decides the step sits at K_eq = KIc and no tip exceeds it
  (1e-6, the issue's: the search stops within 1e-7 of KIc, and K_eq is
  computed to ~1e-13), and time passes;
- unstable: after the growth of the step before, the tips are at or above
  KIc already at the balance of the same fluid on the longer fractures (the
  growth would run on at fixed fluid: a dynamic burst, which a quasi-static
  model takes step by step at one time): it happens at once, no time
  passes, at the balance's pressure, and says so (injection.unstable).
Both cases start quasi-statically (the 4.3 wings in mode I, the network's
first wings from the slipping fracture); the 4.3 wings turn unstable when
the T-stress turns them towards the least compression (step 4 of the
shipped case; measured, see docs/theory/fluid-pressure.md).
"""
import numpy as np
import pytest

import wingcrack
from wingcrack.case import Case

ROOT = __import__("pathlib").Path(__file__).resolve().parents[2]
#: the issue's tolerance on the deciding tip's K_eq against KIc
KEQ_TOL = 1e-6


def first_steps(name, steps):
    case = Case.from_toml(ROOT / "cases" / f"{name}.toml")
    from dataclasses import replace

    return wingcrack.run(replace(case, propagation=replace(case.propagation, steps=steps)), plots=False), case


@pytest.mark.parametrize("name, steps, stable", [("three_fractures_injection_rate", 6, 4),
                                                 ("stimulation_network_rate", 4, 4)])
def test_every_step_is_quasi_static_or_an_unstable_burst_that_says_so(name, steps, stable):
    run, case = first_steps(name, steps)
    KIc = case.material.KIc
    assert len(run.steps) == steps, run.status
    kinds = []
    for k, s in enumerate(run.steps):
        inj = s["injection"]
        free = [t["K_eq"] for t in s["tips"] if t["state"] in ("growing", "arrested")]
        if not inj["unstable"]:
            assert abs(max(free) / KIc - 1) <= KEQ_TOL, (k, max(free) / KIc)
            assert k == 0 or s["time"] > run.steps[k - 1]["time"]
            assert inj["pressure"] > inj["history"][0][1] or k == 0
        else:
            assert max(free) > KIc * (1 + KEQ_TOL), k
            assert s["time"] == run.steps[k - 1]["time"] and inj["pressure"] == inj["history"][0][1]
        kinds.append(inj["unstable"])
    assert not any(kinds[:stable]), kinds
