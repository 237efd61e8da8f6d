"""A pumped step (propagation.load = "injection"), as the loop sees it:
the loading whose load factor is the injected network's pressure
(loading.Fixed's face). The pump (injection.py) finds it on the step's
geometry: the fluid balance at the step's start, the critical pressure
at which the first growing tip reaches KIc, and the time the pump has
delivered that fluid. Where the pump stops first (end_time, shut-in) or
the pressure would pass its limit, the run stops there, the step solved
at that state and recorded.

A pumped step's record also holds its fluid (FluidState, taken at its
solution before growth): its time, the injection and the networks; the
PVD indices get the steps' times as their axis. A committed step moves
the pump on (its time and pressure, the closing pressure of the next
balance) and lets the fractures its wings joined into the network.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import progress
from . import injection
from .loading import Fixed, Found, keq, largest_keq, response_scales


class Pumped(Fixed):
    """The pump's loading: pump (injection.Pump, what the run carries from
    step to step and its checkpoint keeps); step: the step under way
    (injection.PumpedStep)."""
    unreached = None

    def __init__(self, case):
        super().__init__(case)
        self.pump = injection.Pump.of(case)
        self.lam = self.pump.pressure
        self.step = None

    @property
    def network(self):
        return self.pump.network

    def mask(self, n: int):
        return self.pump.mask(n)

    def find(self, disc, fset, grow) -> Found:
        case, m = self.case, self.case.material
        progress.doing("the fluid balance and the critical pressure")
        scales = response_scales(case, disc, fset, self.mask(len(fset.fractures)))   # before the solves
        self.step = step = injection.critical(self.pump, disc, fset.fractures, keq(case, disc, fset, grow), m.KIc,
                                              m.E, scales, pressure_scale(case))
        if step.stop is not None:
            self._solve_where_it_stops(disc, fset)
            return Found(step.pressure, step.solves, stop=lambda tips: self._stopped(tips, grow))
        self.lam = step.pressure
        return Found(self.lam, step.solves)

    def _solve_where_it_stops(self, disc, fset) -> None:
        """The state where the run stops, solved: at the pressure limit, or
        the balance at all the fluid the pump delivers (end_time, shut-in)."""
        pump, step = self.pump, self.step
        if step.stop == "limit":
            limit = pump.search_limit(self.case.material.E)
            disc.solver.solve(limit)
            step.solves += 1   # the balance's stop counts its own (injection.stopped)
            v = pump.network_volume(disc, fset.fractures)
            step.pressure, step.volume, step.time = limit, v, max(pump.time_of(v, limit), pump.time)
            step.history.append((step.time, limit, v))
        else:
            injection.stopped(pump, step, disc, fset.fractures, pressure_scale(self.case))

    def _stopped(self, tips, grow) -> str:
        """The status where the pump stops the run before a tip reaches KIc,
        or the pressure would pass its limit: how far from KIc the tips stayed."""
        step = self.step
        need = "" if step.needed is None else f"; they need {step.needed:.6g} Pa"
        below = f"the largest K_eq is {largest_keq(tips, grow, self.case.material.KIc)} KIc{need}"
        p, t = step.pressure, step.time
        if step.stop == "limit":
            return f"stopped: no tip reaches KIc below the pressure limit 0.1 E = {p:.6g} Pa (there {below})"
        if t == self.pump.schedule.end:
            return f"stopped: end_time reached: at {t:g} s the network holds {p:.6g} Pa ({below})"
        return (f"stopped: shut-in from {t:g} s: the network's fluid holds {p:.6g} Pa ({below}), and no more "
                "comes")

    def fluid(self, disc, fset) -> FluidState:
        return FluidState.of(self.pump, self.step, disc, fset)

    def critical(self, tips, grow) -> float | None:
        """The critical pressure of the step's geometry (None where the growth
        before was unstable: the tips were at KIc at the balance)."""
        return None if self.step.unstable else self.lam

    def commit(self, fluid, done, fset) -> None:
        """The step's time and pressure are the run's, and the fractures
        joined enter the network."""
        self.pump.advance(fluid.step, done)
        self.pump.join(fset, fluid.volumes, fluid.pressures)

    def state(self) -> dict:
        return self.pump.to_dict()

    def restore(self, state) -> None:
        self.pump.restore(state)


@dataclass
class FluidState:
    """A pumped step's fluid, at its solution and on its geometry (before
    growth): the step (injection.PumpedStep), each fracture's volume and
    pressure, the hydraulic groups and each fracture's length, with the
    pump whose step it is."""
    pump: injection.Pump
    step: injection.PumpedStep
    volumes: np.ndarray
    groups: list
    pressures: np.ndarray
    lengths: list

    @classmethod
    def of(cls, pump, step, disc, fset) -> FluidState:
        fractures = fset.fractures
        return cls(pump, step, pump.volumes(disc, fractures), pump.groups(fset), disc.fluid.pressures(step.pressure),
                   [float(np.linalg.norm(np.diff(f.points, axis=0), axis=1).sum()) for f in fractures])

    def record(self) -> dict:
        """The step record's "time", "injection" and "networks" (injection.step_record)."""
        return injection.step_record(self.pump, self.step, self.volumes, self.groups, self.pressures, self.lengths)


def pressure_scale(case) -> float:
    """A pressure scale of a pumped case (Pa): the largest of the in-situ
    stress, the given pressures, the initial pressure and the net pressure
    KIc / sqrt(pi tip_size) that opens a crack a rosette long: the critical
    search's first step above the balance and the balance's without a slope."""
    given = [f.pressure for f in case.fractures] + [case.injection.initial_pressure]
    net = case.material.KIc / np.sqrt(np.pi * case.mesh.tip_size)
    return float(max(np.abs(case.stress.tensor()).max(), max(given), net))
