"""A run driven by a pump (propagation.load = "injection"), toughness
dominated: one pressure per connected network, no viscous loss.

The injected network (the injected fracture and the fractures it meets;
with propagation.connect_pressure, those its wings join too) holds its
fluid: exp(c (p - p0)) V(p) = held + Q(t) (fluid.py), V the network's
volume at pressure p (`Pump.volumes`: the opening integral of its faces,
the gap of its contact faces, the residual aperture over its length),
Q(t) the pumped volume (schedule.py), `held` what the network held
without the pump (at t = 0, and the fluid of fractures it joined). The
network's pressure is the load factor of the step's solves (loads: its
faces carry a unit pressure times the factor); every other load is fixed.

A step on the geometry the last one grew:
1. the balance: the pressure p_b at the fluid the network holds now (the
   time of the last step), solved from the last pressure, and accepted as
   the state the friction starts from (the pressure falls after growth:
   the same fluid in longer fractures). At the first step: the network's
   volume at p0, which is then what it holds (`held`).
2. the critical pressure p* >= p_b at which the first growing tip reaches
   KIc (critical_load, the load factor acting on the network's pressure
   only), to K_eq = KIc (1 + KEQ_TOL); where the tips already reach KIc at
   p_b, the growth the step before was unstable and p* = p_b.
3. the time: V(p*) holds exp(c (p* - p0)) V(p*) of fluid, which the pump
   has delivered at t* = Q^-1(that - held) (the schedule's exact inverse).
   Past end_time, or where the pump has stopped (shut-in) before, the run
   stops: the state at that time is the balance at the fluid pumped by
   then, recorded with how far from KIc its tips stayed.

Every solve between p_b and p* that the search kept as its lower end is a
state of the run (the time its fluid arrives, the pressure, the volume):
with the balance and p* they are the step's points of the pressure
history (`history`), which history.png draws against time.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from ..case.bounds import MAX_STRAIN
from . import fluid
from .critical_load import critical_load_factor
from ..schedule import Schedule

#: the deciding tip's K_eq at the critical pressure: within KIc (1 +- KEQ_TOL) (the search stops
#: there; K_eq is computed to ~1e-13; the issue asks 1e-6, growth takes a tip within 1e-3 of KIc)
KEQ_TOL = 1e-7


@dataclass
class Pump:
    """What a pumped run carries from step to step (and its checkpoint).
    network: the injected network's fractures; held: the fluid (m^3/m at
    the initial pressure's density) it holds without the pump (None before
    the first step); time: the time of the last step (s); pressure: the
    network's pressure there (Pa); closing: where the last step's network
    opening, extrapolated down from its critical pressure, vanishes (Pa;
    the balance's first step on the next geometry), or None."""
    schedule: Schedule
    compressibility: float
    initial_pressure: float
    residual_aperture: float
    fracture: int
    connect: bool
    network: list
    held: float | None = None
    time: float = 0.0
    pressure: float = 0.0
    closing: float | None = None

    @classmethod
    def of(cls, case) -> "Pump":
        inj = case.injection
        return cls(Schedule.of(inj), float(inj.compressibility), float(inj.initial_pressure),
                   float(inj.residual_aperture), int(inj.fracture), bool(case.propagation.connect_pressure),
                   [int(i) for i in np.flatnonzero(case.network_at_start())], pressure=float(inj.initial_pressure))

    # ---- the state

    def mask(self, n: int) -> np.ndarray:
        out = np.zeros(n, bool)
        out[self.network] = True
        return out

    def fluid_at(self, t: float) -> float:
        """The fluid the network holds at time t (m^3/m at rho0)."""
        return self.held + self.schedule.injected(t)

    def fluid_of(self, volume: float, p: float) -> float:
        return fluid.fluid_of(volume, p, self.compressibility, self.initial_pressure)

    def time_of(self, volume: float, p: float) -> float:
        """The time at which the network at pressure p with volume `volume`
        holds the fluid the pump has delivered (inf: never)."""
        return max(self.schedule.time_of(self.fluid_of(volume, p) - self.held), 0.0)

    @property
    def delivered(self) -> float:
        """The most the pump injects before the run ends (end_time or shut-in; inf: no end)."""
        s = self.schedule
        if math.isfinite(s.end):
            return s.injected(s.end)
        return math.inf if s.shut_in_from() is None else s.injected(s.shut_in_from())

    # ---- volumes

    def volumes(self, disc, fractures) -> np.ndarray:
        """(n_fractures,) each fracture's volume at disc's current solution
        (m^2 per metre): the integral of the normal opening of its faces
        and wings, plus the volume it holds whatever the opening (constant)."""
        return np.asarray(disc.openings(), float) + self.constant(fractures)

    def constant(self, fractures) -> np.ndarray:
        """(n_fractures,) the part of each fracture's volume that no opening
        changes, along its pre-existing part: the gap of contact faces (the
        faces start that far apart) and the residual aperture (the
        roughness of a natural fracture; a wing, a fresh crack whose faces
        mate, holds none), m^2 per metre."""
        out = np.zeros(len(fractures))
        for i, f in enumerate(fractures):
            pre = _length(getattr(f, "pre_points", f.points))   # a case Fracture is all pre-existing
            law = f.law
            out[i] = (law.gap if law.faces != "open" else 0.0) * pre + self.residual_aperture * pre
        return out

    def network_volume(self, disc, fractures) -> float:
        return float(self.volumes(disc, fractures)[self.network].sum())

    # ---- a step

    def balance(self, disc, fractures, fluid_held: float, start: float, scale: float) -> fluid.Balance:
        """The pressure at which the network holds `fluid_held` on disc's
        geometry, from `start` (solves from the accepted state; the root's
        solution is left); its first step from the last closing pressure,
        or `scale`."""
        def volume_at(p):
            disc.solve(p)
            return self.network_volume(disc, fractures)

        return fluid.balance_pressure(volume_at, fluid_held, self.compressibility, self.initial_pressure, start,
                                      scale, closing=self.closing,
                                      constant=float(self.constant(fractures)[self.network].sum()))

    def start(self, disc, fractures, scale: float) -> fluid.Balance:
        """The step's first state, solved and accepted: at the first step the
        network at p0 (what it then holds is `held`); later the balance at
        the fluid held at the last step's time. scale: a pressure scale of
        the case (Pa), the balance's first step without a slope."""
        if self.held is None:
            p0 = self.initial_pressure
            disc.solve(p0)
            v = self.network_volume(disc, fractures)
            self.held = self.fluid_of(v, p0)
            b = fluid.Balance(p0, v, self.held, [(p0, v)])
        else:
            b = self.balance(disc, fractures, self.fluid_at(self.time), self.pressure, scale)
        disc.accept()
        return b

    def search_limit(self, E: float) -> float:
        """The highest pressure the critical search tries: 0.1 E (the case's
        bound on any stress)."""
        return MAX_STRAIN * E

    def past_the_pump(self, volume: float, p: float) -> bool:
        """Does the network at pressure p hold more than the pump delivers
        before the run ends?"""
        return self.fluid_of(volume, p) - self.held > self.delivered * (1 + 1e-12)


    # ---- what a committed step leaves

    def advance(self, step: "PumpedStep", fractures) -> None:
        """The step is done: its time and pressure are the run's, and the
        closing pressure of its network (the volume's last two states, on
        `fractures` as the step solved them, extrapolated to no opening) the
        next balance's first step (the last one's kept where the step has
        no two states to tell it: unstable growth)."""
        (_, p1, v1), (_, p2, v2) = ([(0.0, 0.0, 0.0)] + step.history)[-2:]
        opening = v2 - float(self.constant(fractures)[self.network].sum())
        if len(step.history) > 1 and p2 > p1 and v2 > v1 and opening > 0:
            self.closing = p2 - opening * (p2 - p1) / (v2 - v1)
        self.time, self.pressure = step.time, step.pressure

    def join(self, fset, volumes, pressures) -> list:
        """After growth: the fractures now connected to the network enter it
        (propagation.connect_pressure) with the fluid they held: none where
        dry (no given pressure), exp(c (p_f - p0)) V_f at their given
        pressure p_f otherwise (volumes, pressures (n,): at the step's
        solution, before growth). Returns the fractures that entered."""
        if not self.connect:
            return []
        group = next(g for g in fset.connected_groups() if self.fracture in g)
        new = sorted(set(group) - set(self.network))
        self.held += sum(self.fluid_of(volumes[j], pressures[j]) for j in new if pressures[j] > 0)
        self.network = sorted(set(self.network) | set(new))
        for j in self.network:   # what the checkpoint and the summary show for them: the network's
            f = fset.fractures[j]
            f.law = dataclasses.replace(f.law, pressure=float(self.pressure))
        return new

    def groups(self, fset) -> list:
        """The hydraulic groups of the fractures: the network, and the
        connected groups of the others (each fracture on its own without
        propagation.connect_pressure)."""
        if self.connect:
            return fset.connected_groups()
        rest = [[i] for i in range(len(fset.fractures)) if i not in self.network]
        return sorted([list(self.network)] + rest)

    def to_dict(self) -> dict:
        """The state the checkpoint keeps (the schedule and fluid are the case's)."""
        return {"network": list(self.network), "held": self.held, "time": self.time, "pressure": self.pressure,
                "closing": self.closing}

    def restore(self, d: dict) -> None:
        """The state of a checkpoint's to_dict (checked by checkpoint.load)."""
        self.network, self.held = [int(i) for i in d["network"]], float(d["held"])
        self.time, self.pressure = float(d["time"]), float(d["pressure"])
        self.closing = None if d.get("closing") is None else float(d["closing"])


@dataclass
class PumpedStep:
    """How a pumped step went: start (the balance at its start), the
    critical pressure and its volume (None where the run stops before a
    tip reaches KIc: `stop` says why, "pump" (end_time or shut-in) or
    "limit" (the pressure limit)), its time, whether the growth before was
    unstable (the tips at KIc at the balance), the history [(t, p, V)] of
    the step, and its solves."""
    start: fluid.Balance
    pressure: float | None = None
    volume: float | None = None
    time: float = 0.0
    unstable: bool = False
    history: list = field(default_factory=list)
    solves: int = 0
    stop: str | None = None
    needed: float | None = None   # the critical pressure where the pump stops before it


def critical(pump: Pump, disc, fractures, keq, KIc: float, E: float, homogeneous: bool, scale: float) -> PumpedStep:
    """Steps 1-3 of the module doc on disc's geometry: the balance at the
    step's start, the critical pressure (keq(p): the largest K_eq of the
    growing tips after a solve at p) and its time; the solution left is the
    critical pressure's (or the last trial's where the run stops)."""
    start = pump.start(disc, fractures, scale)
    out = PumpedStep(start, solves=start.solves, history=[(pump.time, start.pressure, start.volume)])
    if start.partly_filled:   # the pressure holds until the pump has filled the network
        out.history.append((pump.time_of(start.volume, start.pressure), start.pressure, start.volume))
    last = {}

    def keq_v(p):
        k = keq(p)
        last["p"], last["v"] = p, pump.network_volume(disc, fractures)
        return k

    def accept():
        disc.accept()
        p, v = last["p"], last["v"]
        t = pump.time_of(v, p)
        # a state the pump never reaches before the run ends (past end_time, or after shut-in: inf) is
        # none of the run's: the search stops on it (beyond), and the history keeps to the run's times
        if p > out.history[-1][1] and t <= pump.schedule.end and math.isfinite(t):
            out.history.append((t, p, v))

    def beyond(p):
        return pump.past_the_pump(last["v"], p)

    # the first trial above the start: the last step's critical pressure (the next one is near it on a
    # geometry one growth apart), else a pressure scale above
    first = pump.pressure if pump.pressure > start.pressure else start.pressure + scale
    crit = critical_load_factor(keq_v, KIc, start.pressure, homogeneous, pump.search_limit(E), rtol=1e-12,
                                accept=accept, first=first, beyond=beyond, at_root=KEQ_TOL, two_sided=True,
                                secant_above=True)
    out.solves += crit.solves
    if crit.load_factor is None:
        out.stop = "pump" if last and beyond(last["p"]) else "limit"
        return out
    p = float(crit.load_factor)
    out.unstable = p == start.pressure   # the tips at KIc at the balance (the search's root is above its start)
    disc.solution_at(p)   # the search's last trial, mostly
    v = pump.network_volume(disc, fractures)
    # unstable: the balance's state (its fluid is the held one to 1e-10: no time passes)
    t = pump.time if out.unstable else max(pump.time_of(v, p), pump.time)
    if t > pump.schedule.end or not math.isfinite(t):
        out.stop, out.needed = "pump", p
        return out
    out.pressure, out.volume, out.time = p, v, t
    if p > out.history[-1][1]:
        out.history.append((t, p, v))
    return out


def stopped(pump: Pump, out: PumpedStep, disc, fractures, scale: float) -> PumpedStep:
    """The state where the pump stops the run (out.stop == "pump"): the
    balance at all the fluid it delivers, at end_time or (shut-in) the time
    its last fluid arrived; out completed with it."""
    s = pump.schedule
    shut = s.shut_in_from()
    t = s.end if shut is None or s.end < shut else shut
    b = pump.balance(disc, fractures, pump.held + pump.delivered, out.start.pressure, scale)
    out.solves += b.solves
    out.pressure, out.volume, out.time = b.pressure, b.volume, t
    out.history.append((t, b.pressure, b.volume))
    return out


def _length(points) -> float:
    return float(np.linalg.norm(np.diff(np.asarray(points, float), axis=0), axis=1).sum())


def step_record(pump: Pump, step: PumpedStep, volumes: np.ndarray, groups: list, pressures, lengths) -> dict:
    """The step's "time", "injection" and "networks" for its record:
    volumes, pressures and lengths (n_fractures,) at the step's pressure;
    groups: the connected groups of fractures. injection.partly_filled:
    the network was not full at the step's start (its first history point
    holds less fluid than its volume, at the pressure floor)."""
    p, v = step.pressure, step.volume
    injected = pump.schedule.injected(step.time)
    # the fluid the volume holds at p, but all there is where the network is not full (p at the floor)
    stored = min(pump.fluid_of(v, p), pump.held + injected) - pump.held
    nets = [{"fractures": [int(i) for i in g], "pressure": float(max(pressures[i] for i in g)),
             "volume": float(sum(volumes[i] for i in g)), "length": float(sum(lengths[i] for i in g))}
            for g in groups]
    return {"time": float(step.time),
            "injection": {"injected": float(injected), "stored": float(stored), "leaked": 0.0, "pressure": float(p),
                          "volume": float(v), "held": float(pump.held), "unstable": bool(step.unstable),
                          "partly_filled": bool(step.start.partly_filled),
                          # the state where the pump or the pressure limit ended the run: no tip at KIc
                          "stopped": step.stop is not None,
                          "history": [[float(t), float(q), float(w)] for t, q, w in step.history]},
            "networks": nets}
