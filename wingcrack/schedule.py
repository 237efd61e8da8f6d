"""The pump's schedule: piecewise constant rates in time, the volume it has
injected by a time, and its exact inverse, the time by which it has
injected a volume.

Rates are m^3/s per metre of thickness, volumes m^3 per metre, at the
fluid's reference density (that of the initial pressure). Before the first
time nothing is injected; the last rate holds to the end (0: shut-in for
good). Q(t) is continuous, piecewise linear and non-decreasing: its
inverse `time_of(v)` is the earliest t with Q(t) >= v, exact up to one
rounding (the interval's start plus the rest over its rate), and inf where
the pump never gets there.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Schedule:
    """times (n,) the start of each interval, increasing; rates (n,) >= 0;
    end: the run's end time (inf: none)."""
    times: np.ndarray
    rates: np.ndarray
    end: float = math.inf

    @classmethod
    def of(cls, injection) -> "Schedule":
        """The schedule of a case's Injection (a constant `rate` from t = 0, or
        `times` with `rates`)."""
        if injection.rate is not None:
            times, rates = (0.0,), (float(injection.rate),)
        else:
            times, rates = injection.times, injection.rates
        end = math.inf if injection.end_time is None else float(injection.end_time)
        return cls(np.asarray(times, float), np.asarray(rates, float), end)

    @classmethod
    def from_dict(cls, d: dict) -> "Schedule":
        """The schedule of to_dict (summary.json's propagation.schedule)."""
        end = d.get("end_time")
        return cls(np.asarray(d["times"], float), np.asarray(d["rates"], float), math.inf if end is None else float(end))

    def to_dict(self) -> dict:
        """times and rates (s, m^3/s per m) and end_time (s, None: none), as summary.json keeps them."""
        return {"times": self.times.tolist(), "rates": self.rates.tolist(),
                "end_time": None if math.isinf(self.end) else float(self.end)}

    @property
    def _volumes(self) -> np.ndarray:
        """(n,) Q at the start of each interval."""
        return np.r_[0.0, np.cumsum(np.diff(self.times) * self.rates[:-1])]

    def injected(self, t: float) -> float:
        """Q(t): the volume injected by time t (m^3/m)."""
        t = float(t)
        k = int(np.searchsorted(self.times, t, side="right")) - 1
        if k < 0:
            return 0.0
        return float(self._volumes[k] + (t - self.times[k]) * self.rates[k])

    def time_of(self, volume: float) -> float:
        """The earliest t >= 0 at which Q(t) >= volume (0 for volume <= 0;
        inf where the pump never injects that much: the last rate is 0)."""
        v = float(volume)
        if v <= 0.0:
            return 0.0
        q = self._volumes
        # the first interval whose end volume reaches v (the last one runs for ever)
        for k in range(len(self.times)):
            ends = q[k + 1] if k + 1 < len(q) else math.inf if self.rates[k] > 0 else q[k]
            if ends >= v and self.rates[k] > 0:
                return float(self.times[k] + (v - q[k]) / self.rates[k])
        return math.inf

    def shut_in_from(self) -> float | None:
        """The time from which nothing more is injected (the last rate is
        0), or None where the pump runs to the end."""
        if self.rates[-1] > 0:
            return None
        k = len(self.rates) - 1
        while k > 0 and self.rates[k - 1] == 0:
            k -= 1
        return float(self.times[k])

    def describe(self) -> str:
        """The schedule in words: "1e-4 m^3/s per m from 0 s" or its intervals."""
        parts = []
        for k, (t, r) in enumerate(zip(self.times, self.rates)):
            stop = f" to {self.times[k + 1]:g} s" if k + 1 < len(self.times) else ""
            what = "shut-in" if r == 0 else f"{r:g} m^3/s per m"
            parts.append(f"{what} from {t:g} s{stop}")
        end = "" if math.isinf(self.end) else f"; the run ends at {self.end:g} s"
        return ", ".join(parts) + end
