"""The pump's keys ([injection], propagation.load = "injection") and its
schedule (wingcrack/schedule.py): the keys read with their
defaults, the refusals the bad-case corpus does not hold, and the injected
volume Q(t) of piecewise constant rates with its exact inverse."""
import math

import numpy as np
import pytest

from test_case import BASE, patched
from wingcrack.case import Case, CaseError
from wingcrack.schedule import Schedule

PUMPED = patched(("propagation", {"load": "injection"}), ("injection", {"fracture": 1, "rate": 1.0e-4}))


def test_the_pump_reads_with_its_defaults():
    """Every key of [injection] given at its default reads as the table
    that leaves them out (the defaults are those of the Keys: water's
    compressibility, no residual aperture, p0 = 0, no end)."""
    given = patched(("injection.compressibility", 4.5e-10), ("injection.residual_aperture", 0.0),
                    ("injection.initial_pressure", 0.0), base=PUMPED)
    a, b = Case.from_dict(given), Case.from_dict(PUMPED)
    assert a.injection == b.injection
    inj = b.injection
    assert (inj.fracture, inj.rate, inj.times, inj.rates, inj.point, inj.end_time) == (1, 1.0e-4, None, None, None,
                                                                                     None)
    assert Case.from_dict(BASE).injection is None


def test_a_schedule_reads_as_tuples():
    d = patched(("injection", {"fracture": 1, "times": [0.0, 60, 120.0], "rates": [1e-4, 0, 2e-4],
                               "end_time": 600}), base=PUMPED)
    inj = Case.from_dict(d).injection
    assert inj.times == (0.0, 60.0, 120.0) and inj.rates == (1e-4, 0.0, 2e-4) and inj.end_time == 600.0


@pytest.mark.parametrize("change, key, reason", [
    # the fracture injected into meets fracture 0 (a T): the network's pressure is the balance's
    ((("fractures.2", {"points": [[1.0, 1.0], [1.0, 1.8]], "pressure": 1e6}), ("injection.fracture", 2)),
     "fractures[2].pressure", "is injected"),
    ((("fractures.2", {"points": [[1.0, 1.0], [1.0, 1.8]]}), ("fractures.0.pressure", 1e6),
      ("injection.fracture", 2)), "fractures[0].pressure", "meets the injected fractures[2]"),
    ((("injection.end_time", 1e13),), "injection.end_time", "at most 1e+12"),
    ((("injection.rate", 1e3),), "injection.rate", "must be at most L^2"),
    ((("injection", {}),), "injection.fracture", "missing"),
    ((("injection.leak_off", 0.0),), "injection.leak_off", "not yet supported"),
])
def test_the_pump_is_refused_naming_the_key(change, key, reason):
    with pytest.raises(CaseError) as info:
        Case.from_dict(patched(*change, base=PUMPED))
    assert info.value.key == key and reason in info.value.reason, (info.value.key, info.value.reason)


def test_a_dry_fracture_with_a_pressure_beside_the_network_is_accepted():
    """A fracture the injected one does not meet keeps its own given pressure."""
    case = Case.from_dict(patched(("fractures.0.pressure", 1e6), base=PUMPED))
    assert case.fractures[0].pressure == 1e6


def test_the_midpoint_is_halfway_along_the_polyline():
    f = Case.from_dict(BASE).fractures[0]   # (1, 1) - (1.5, 1.2) - (2, 1): two equal segments
    np.testing.assert_allclose(f.midpoint, [1.5, 1.2], atol=1e-15)


# ---------------------------------------------------------------- the schedule


def schedule(times, rates, end=math.inf):
    return Schedule(np.asarray(times, float), np.asarray(rates, float), end)


def test_the_injected_volume_is_the_rates_integrated():
    s = schedule([10.0, 20.0, 30.0], [2.0, 0.0, 3.0])
    for t, q in ((0.0, 0.0), (10.0, 0.0), (15.0, 10.0), (20.0, 20.0), (25.0, 20.0), (30.0, 20.0), (40.0, 50.0)):
        assert s.injected(t) == q, t


def test_the_inverse_is_exact_and_the_earliest_time():
    """time_of(Q(t)) = t where Q rises (exact in binary fractions); at a
    shut-in plateau the earliest time it was reached; inf where the pump
    never injects that much."""
    s = schedule([10.0, 20.0, 30.0], [2.0, 0.0, 3.0])
    for t in (10.5, 12.25, 20.0, 30.0, 31.5, 1e6):
        assert s.time_of(s.injected(t)) == (20.0 if t == 30.0 else t), t
    assert s.time_of(0.0) == 0.0 and s.time_of(-1.0) == 0.0
    shut = schedule([0.0, 5.0], [1.0, 0.0])
    assert shut.time_of(5.0) == 5.0 and shut.time_of(5.0 + 1e-9) == math.inf
    assert shut.shut_in_from() == 5.0 and s.shut_in_from() is None


def test_the_inverse_round_trips_random_volumes():
    """Q(time_of(v)) = v to round-off over random schedules: the time a step
    takes is exactly the fluid it needs."""
    rng = np.random.default_rng(7)
    for _ in range(50):
        n = int(rng.integers(1, 6))
        times = np.cumsum(rng.uniform(0.1, 100.0, n)) - 0.1
        rates = rng.uniform(0.0, 1e-3, n) * (rng.uniform(size=n) > 0.3)
        rates[-1] = max(rates[-1], 1e-5)
        s = schedule(times, rates)
        for v in rng.uniform(0.0, 2 * s.injected(times[-1] + 50.0), 10):
            t = s.time_of(v)
            # the time's own rounding, eps t, moves Q by eps t r: the bound is a few roundings of both terms
            r = rates[np.searchsorted(times, t, side="right") - 1] if t > 0 else 0.0
            assert abs(s.injected(t) - v) <= 4 * np.finfo(float).eps * (v + t * r), (v, t)


def test_the_schedule_of_a_case():
    case = Case.from_dict(patched(("injection", {"fracture": 1, "times": [0.0, 60.0], "rates": [1e-4, 0.0],
                                                 "end_time": 600.0}), base=PUMPED))
    s = Schedule.of(case.injection)
    assert s.end == 600.0 and s.injected(100.0) == pytest.approx(6e-3, rel=1e-15)
    assert s.describe() == ("0.0001 m^3/s per m from 0 s to 60 s, shut-in from 60 s; the run ends at 600 s")
    assert Schedule.of(Case.from_dict(PUMPED).injection).describe() == "0.0001 m^3/s per m from 0 s"
