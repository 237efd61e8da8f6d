"""How each step's load factor is found (propagation.load), the box of
Fig. 8 between the solve and the growth:

- "fixed" (Fixed): the case's loads as given, load factor 1; a step whose
  tips do not reach KIc ends the run there;
- "scale" and "pressure" (Searched): the critical load factor, at which
  the first growing tip reaches KIc (critical_load; "pressure" scales the
  fracture pressures only: the critical injection pressure); where no
  tip reaches KIc below propagation.max_load_factor the run stops there;
- "injection" (pumped.Pumped): the network's pressure, from the pump's
  fluid balance and the critical pressure; with injection.viscosity
  (flowing.Flowing) the flow along the fractures in time, to the time a
  tip reaches KIc or a frame.

Each is an object with Fixed's face, which the loop calls without knowing
which it is: `lam` (the load factor the run holds), find (the step's load
factor, or where the loading stops the run), fluid (a pump's state of the
step), critical (the record's critical_load_factor), commit (what a
committed step leaves), mask and network (the fractures whose pressure it
sets), state and restore (the checkpoint).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

import wingcrack_kernels as K
from .. import progress, sifs
from .critical_load import critical_load_factor, scales_with_load

#: the load modes in which each step searches the critical load factor ("pressure": of the
#: fracture pressures only, the critical injection pressure)
SEARCHED = ("scale", "pressure")
#: a K_eq below this times KIc is said as 0 in a status: the round-off of SIFs that vanish
ROUND_OFF_K = 1e-9
#: added to the load-limit status of a case in which the load factor multiplies nothing
NOTHING_SCALES = (" (nothing in the case scales with it: every [[bc]] value and slip is 0, and the in-situ stress "
                  "and gravity are not scaled)")


@dataclass
class Found:
    """The load factor a step solves at and the solves finding it took.
    stop: where the loading stops the run before a tip reaches KIc (the
    step is then solved at load_factor, and recorded), the run's status
    from that step's tips (TipSIF); None where the step goes on. frame: the
    step is a state in time at which no tip reached KIc (a flowing run's):
    recorded, nothing grows, and the next step goes on from it on the same
    geometry."""
    load_factor: float
    solves: int
    stop: Callable[[list], str] | None = None
    frame: bool = False


class Fixed:
    """propagation.load = "fixed": every step at load factor 1."""
    #: the status where a step's tips do not reach KIc (None: the loading brings a tip to it)
    unreached = "stopped: no tip reaches KIc under the fixed load"
    #: the fractures whose pressure the loading sets (kept out of the connected pressures)
    network = ()
    #: does the run go on in time where no tip may grow (a flowing run's frames)?
    timed = False

    def __init__(self, case):
        self.case = case
        self.lam = 1.0

    def mask(self, n: int):
        """(n,) bool, the fractures whose pressure is the load factor (step.discretise's network), or None."""
        return None

    def find(self, disc, fset, grow) -> Found:
        """The load factor of the step on disc's geometry (grow: the tips
        that may grow); the solution it leaves is the caller's to take
        (solution_at), or, where it stops the run, the step's."""
        return Found(self.lam, 1)

    def fluid(self, disc, fset):
        """The step's fluid (pumped.FluidState) at its solution, before growth; None without a pump."""
        return None

    def critical(self, tips, grow) -> float | None:
        """The step's own critical load factor for its record (None: not known)."""
        return None

    def commit(self, fluid, done, fset) -> None:
        """The step is committed: `done` the fractures as it solved them, fset grown."""

    def state(self):
        """What the checkpoint keeps of the loading beside the load factor (None: nothing)."""
        return None

    def restore(self, state) -> None:
        """The loading as the checkpoint left it (lam is set by the caller)."""


class Searched(Fixed):
    """propagation.load = "scale" or "pressure": the critical load factor,
    searched from the one the run holds (loads only rise)."""
    unreached = None

    def __init__(self, case):
        super().__init__(case)
        self.lam = 0.0
        self.held = 0.0   # the load factor held before the step (its own critical load's reference)
        self.homogeneous = False   # the step's response scales with the load

    def find(self, disc, fset, grow) -> Found:
        case = self.case
        progress.doing("the critical-load search")
        homogeneous = response_scales(case, disc, fset)   # before the solves: they may accept a slip
        # two-sided: a secant that hits the root puts K_eq on either side of KIc by round-off (its sign may
        # differ between one process and two); one-sided, the side below crept to the root by halves and
        # ended 1e-6 above it. A root a hair below KIc grows (growth.reached: KIc (1 - 1e-3))
        crit = critical_load_factor(keq(case, disc, fset, grow), case.material.KIc, self.lam, homogeneous,
                                    case.propagation.max_load_factor, accept=disc.solver.accept, two_sided=True)
        if crit.load_factor is None:
            limit = case.propagation.max_load_factor
            progress.doing(f"the solve at the load factor limit {limit:.6g}")
            disc.solver.solve(limit)
            return Found(limit, int(crit.solves) + 1, stop=lambda tips: self._at_the_limit(tips, grow, limit))
        self.held, self.lam, self.homogeneous = self.lam, crit.load_factor, homogeneous
        return Found(self.lam, int(crit.solves))

    def _at_the_limit(self, tips, grow, limit) -> str:
        """No tip reaches KIc below the load factor limit. The step solved at
        the limit is a result too (as under a fixed load): the user sees how
        far from KIc the tips stayed, in its record and its files."""
        return f"stopped: no tip reaches KIc below the load factor limit {limit:g} (there the " \
            f"largest K_eq is {largest_keq(tips, grow, self.case.material.KIc)} KIc)" + \
            ("" if _scaled_load(self.case) else NOTHING_SCALES)

    def critical(self, tips, grow) -> float | None:
        """The load factor at which the step's first growing tip reaches KIc,
        though the run held a higher one (after the peak): where the response
        scales with the load, lam KIc / K_eq(lam) (K proportional to the load on
        the step's geometry); elsewhere the search's root where it rose above
        the held load, and None where it started above KIc (path-dependent: a
        lower critical load is not the answer of another loading)."""
        if self.homogeneous:
            k = max(tips[i].K_eq for i in grow)
            return self.lam * self.case.material.KIc / k if k > 0 else None
        return self.lam if self.lam > self.held else None


def largest_keq(tips, grow, KIc) -> str:
    """The largest K_eq of the tips `grow` in KIc, as a status says it:
    below ROUND_OFF_K the round-off of SIFs that vanish (faces stuck or
    closed), said as 0."""
    ratio = max(tips[i].K_eq for i in grow) / KIc
    return f"{ratio:.3g}" if ratio >= ROUND_OFF_K else "0"


def keq(case, disc, fset, grow):
    """keq(load): the largest K_eq of the tips `grow` after a solve at
    `load`, by the SIFs that drive growth."""
    polylines = fset.polylines()
    trials = [0]

    def keq_at(load):
        trials[0] += 1
        progress.doing(f"the critical-load search, trial {trials[0]} at load factor {load:.6g}")
        disc.solver.solution_at(load)   # a pump's balance may have solved at it
        KI, KII = sifs.driving(case, disc, polylines)
        th = K.mts_angle(KI[grow], KII[grow])
        k = float(np.max(K.equivalent_k(KI[grow], KII[grow], th)))
        sifs.require_finite("K_eq", k)
        return k

    return keq_at


def response_scales(case, disc, fset, network=None) -> bool:
    """Does the step's whole response scale with the load factor (no in-situ stress or other fixed load,
    no reference slip, no cohesion)? network: with a pump, the injected network."""
    rows = disc.contact.rows
    return scales_with_load(case, fset, network) and not np.any(disc.contact.reference) and \
        not np.any(rows.cohesion)


def _scaled_load(case) -> bool:
    """Does the load factor multiply anything (a non-zero bc value, slip or
    fracture pressure; with load = "pressure" the pressures only)?"""
    pressure = any(f.pressure for f in case.fractures)
    if case.propagation.load == "pressure":
        return pressure
    return any(any(b.value) for b in case.bcs) or any(f.slip for f in case.fractures) or pressure
