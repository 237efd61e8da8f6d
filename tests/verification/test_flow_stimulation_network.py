"""The showcase's stimulation network with the flow along the fractures
(cases/stimulation_network_flow.toml), its first three steps: the first
growth (the wings at both tips of fracture 0 at the isolated crack's
breakdown, 36.9 MPa: the flow's pressure at the injection point where the
pump's uniform one reached it, 4.19 s), a frame, and the second growth,
where the run failed before a shut wing held a least aperture ("the flow
found no state after 10.3 s" and earlier ones; contact.constraints.
least_apertures).

Checked: the run goes on past its second growth; the fluid balance
(injected = stored, no leak-off) to 1e-8 at every step, the flow's
promise; the injected volume the pump's rate times the time (1e-12: the
schedule's sum); the breakdown pressure within 0.1 % of the pumped case's
36.93 MPa (docs/user-guide/showcase.md): by then the pressure has evened
out along the 2.5 m fault (alpha = w_r^2 / (12 eta c_f) = 1.9e3 m^2/s,
alpha t / L^2 about 1,200) and the fault stores what the pump's does."""
from dataclasses import replace
from pathlib import Path

import pytest

import wingcrack
from wingcrack.case import Case

CASE = Path(__file__).resolve().parents[2] / "cases" / "stimulation_network_flow.toml"


@pytest.fixture(scope="module")
def run():
    case = Case.from_toml(CASE)
    case = replace(case, propagation=replace(case.propagation, steps=3))
    return wingcrack.run(case, plots=False)


def test_the_flowing_network_grows_past_its_second_growth(run):
    assert run.status == "finished" and len(run.steps) == 3, run.status
    grew = [any(t["state"] == "growing" for t in s["tips"]) for s in run.steps]
    assert grew[0] and grew[2], grew
    assert run.steps[0]["injection"]["pressure"] == pytest.approx(36.93e6, rel=1e-3)


def test_the_fluid_balance_holds_at_every_step(run):
    for s in run.steps:
        inj = s["injection"]
        assert abs(inj["injected"] - inj["stored"] - inj["leaked"]) <= 1e-8 * (inj["held"] + inj["injected"])
        assert inj["injected"] == pytest.approx(1e-6 * s["time"], rel=1e-12)
