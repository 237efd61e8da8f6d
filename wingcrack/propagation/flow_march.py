"""A run whose fluid flows along the fractures (injection.viscosity): time
steps on each geometry until a growing tip arrives (the growth event,
found in time as the critical load is today: K_eq reaches KIc, or for a
moving tip the apparent toughness of the viscous tip asymptote,
viscous_tip.py), a frame time, or the end.

On a geometry (a discretisation of the current fractures) the injected
network's faces carry the flow (flow.lubrication on flow.network), coupled
to the contact and friction on the faces alone (fem.coupled_faces): each
time step is one backward-Euler step of the coupled problem, one increment
of friction from the last accepted state. After each step the whole
displacement gives the tips' K_eq; where a growing tip passes KIc the time
of the event is found between the step's ends (Illinois on K_eq(t) - KIc,
each trial the step from its start to the trial time) to K_eq within
KEQ_TOL of KIc, on either side (a tip a hair below KIc grows: growth's
KEQ_RTOL). The fluid then goes on to the next geometry by arc length
(flow.transfer), the new crack empty: the flow fills it.

Time steps are chosen by the run: each the last times a factor of at most
GROWTH, held where the pressure changed by more than CHANGE of its
disturbance at a node other than the source's (dt / t of a diffusion then
settles near CHANGE), halved where the coupled iteration fails; they land
on the frame times, the schedule's changes and the end.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from ..contact.constraints import least_apertures, pre_existing_pairs
from ..contact.friction_problem import SLIP
from ..errors import ComputationError
from ..flow.lubrication import FLOOR, Fluid, FlowState, Lubrication, Source
from ..flow.network import FlowNetwork
from ..flow.transfer import Samples, carry, sample
from ..schedule import Schedule
from .viscous_tip import TipMotion

#: the largest ratio of one time step to the last
GROWTH = 1.5
#: the pressure change of a step, relative to the disturbance p - p0, that the time steps aim at
CHANGE = 0.05
#: the first time step, as a fraction of the interval between frames
FIRST = 1e-4
#: a growth event: the deciding tip's K_eq within KIc (1 +- KEQ_TOL), on either side as the pump's
#: search (injection.KEQ_TOL): where K_eq is linear in time (a stationary crack filling) the secant's
#: trial is the root to round-off, whose sign may differ between one process and two; one-sided, a
#: trial a hair below KIc was refused and the search ended elsewhere in the band (1.8e-6 later in time)
KEQ_TOL = 1e-4
#: halvings of a time step whose coupled iteration fails before the run fails
MAX_RETRIES = 20
#: the shortest time step, relative to the time: below it the time's own round-off is near (a step
#: from t to t + dt with dt under t's spacing would be no step)
SHORTEST = 1e-12
#: a growth event within this fraction of the time from the step's start took no time (unstable)
UNSTABLE = 1e-9
#: the fluid the nodes may hold below none, relative to all the fluid there was (its round-off; the
#: balance's own bound is 1e-8)
OVERDRAWN = 1e-9


@dataclass
class FlowDrive:
    """What a flowing run carries from step to step (and its checkpoint):
    the fluid and the source (a rate schedule, or a pressure held at the
    point), the network's fractures, the frame times, the end, the fluid
    along the fractures (flow.transfer.Samples; None before the first
    step), the last time step and its time."""
    fluid: Fluid
    fracture: int
    point: np.ndarray
    schedule: Schedule | None
    pressure: float | None
    end: float
    frames: np.ndarray
    network: list
    connect: bool
    initial_pressure: float
    samples: Samples | None = None
    dt: float | None = None
    motion: TipMotion = field(default_factory=TipMotion)
    time: float = 0.0

    @classmethod
    def of(cls, case) -> "FlowDrive":
        inj = case.injection
        fr = case.fractures[inj.fracture]
        point = np.asarray(inj.point if inj.point is not None else fr.midpoint, float)
        schedule = None if inj.pressure is not None else Schedule.of(inj)
        end = float(inj.end_time)
        frames = end * np.arange(1, int(inj.frames) + 1) / int(inj.frames)
        fluid = Fluid(float(inj.viscosity), float(inj.compressibility), float(inj.initial_pressure),
                      float(inj.leak_off))
        return cls(fluid, int(inj.fracture), point, schedule, None if inj.pressure is None else float(inj.pressure),
                   end, frames, [int(i) for i in np.flatnonzero(case.network_at_start())],
                   bool(case.propagation.connect_pressure), float(inj.initial_pressure))

    def stops(self) -> np.ndarray:
        """The times a step must land on: the frames, the schedule's changes, the end."""
        out = list(self.frames) + [self.end]
        if self.schedule is not None:
            out += [float(t) for t in self.schedule.times]
        return np.unique([t for t in out if t > 0])

    def source(self, weights, t0: float, t1: float) -> Source:
        if self.pressure is not None:
            return Source(weights, pressure=self.pressure)
        return Source(weights, volume=self.schedule.injected(t1) - self.schedule.injected(t0))


def apertures(case, cm, net: FlowNetwork, fractures):
    """(constant (k, 3), hydraulic (k,), held (k,), least (k,)) of the
    network's edges: on the pre-existing part of a fracture its contact
    faces' gap and the residual aperture, or its fixed hydraulic aperture
    (then its edges' conductance too); none on the wings (fresh cracks
    whose faces mate where they are open); held: the faces' law holds them
    apart (every law but "open": a wing's is its fracture's); least: their
    least aperture (contact.constraints.least_apertures: the residual
    aperture on a held wing, 0 elsewhere, the positive part)."""
    mid_pair = net.pair[:, 2]   # a mid node is never a tip
    pre = pre_existing_pairs(cm, fractures)[mid_pair]
    residual = float(case.injection.residual_aperture)
    least = least_apertures(cm, fractures, residual)[mid_pair]
    k = net.num_edges
    constant = np.zeros(k)
    hydraulic = np.full(k, np.nan)
    held = np.zeros(k, bool)
    for f in np.unique(net.fracture):
        rows = np.flatnonzero((net.fracture == f) & pre)
        law = fractures[int(f)].law
        held[net.fracture == f] = law.faces != "open"
        gap = law.gap if law.faces != "open" else 0.0
        fixed = case.fractures[int(f)].hydraulic_aperture if int(f) < len(case.fractures) else None
        constant[rows] = gap + (fixed if fixed is not None else residual)
        if fixed is not None:
            hydraulic[rows] = fixed
    return np.repeat(constant[:, None], 3, axis=1), hydraulic, held, least


def balanced(lub: Lubrication, faces, carried: FlowState) -> FlowState:
    """The carried fluid on a grown geometry, spread at once: the carried
    pressure's shape shifted by the one constant at which the network,
    solved there, holds the fluid it held (a safeguarded Newton on the
    shift, the fluid held rising with it; below the floor partly filled,
    as in the flow's step), each node's fluid the mechanics' there: as the
    pump without viscosity spreads it. Its pressure is where the first time
    step on the grown geometry starts (Geometry.of): one the faces agree
    with. The fluid itself is not spread so: a new crack filled at once
    holds no moving tip's viscous suction, and its tips run ahead of the
    viscosity-dominated solution (by 20 % on l(t) at six times the initial
    length, no less on a finer mesh)."""
    fl = lub.fluid
    total = float(np.sum(carried.fluid))

    def excess(shift):   # the fluid the shifted field holds (partly filled below the floor), and its slope
        q = carried.pressure + shift
        p = np.maximum(q, FLOOR)
        above = q > FLOOR
        w = faces.openings(p)
        rho = fl.density(p)
        V = lub.volumes(w)
        held = rho * V + lub.kappa * np.minimum(q - FLOOR, 0.0)
        slope = float(np.sum((fl.compressibility * rho * V + rho * (lub.volume_derivative(w) @ faces.derivative()).sum(axis=1))[above])
                      + np.sum(lub.kappa[~above]))
        return float(np.sum(held)) - total, slope, held, p

    scale = max(float(np.max(np.abs(carried.pressure))), 1.0)
    lo = hi = None
    x, (f, slope, m, p) = 0.0, excess(0.0)
    for _ in range(200):
        if abs(f) <= 1e-12 * max(total, 1e-300):
            break
        if f > 0:
            hi = x
        else:
            lo = x
        step = -f / slope if slope > 0 else (-scale if f > 0 else scale)
        nxt = x + step
        if lo is not None and hi is not None and not lo < nxt < hi:
            nxt = 0.5 * (lo + hi)
        elif lo is None and nxt >= x or hi is None and nxt <= x:
            nxt = x + step
        x, (f, slope, m, p) = nxt, excess(nxt)
    else:
        raise ComputationError("the fluid carried to the grown fractures found no pressure that holds it")
    return FlowState(carried.time, p, m, carried.injected, carried.leaked, carried.exposed, carried.initial)


@dataclass
class Geometry:
    """The flow on one discretisation: the network, the coupled faces, the
    discrete flow, the source's weights and the fluid's state."""
    disc: object
    net: FlowNetwork
    faces: object
    lub: Lubrication
    weights: np.ndarray
    state: FlowState

    @classmethod
    def of(cls, drive: FlowDrive, case, disc, fractures) -> "Geometry":
        net = FlowNetwork.of(disc.cm, drive.network)
        faces = disc.coupled_faces(net)
        constant, hydraulic, held, least = apertures(case, disc.cm, net, fractures)
        lub = Lubrication(net, drive.fluid, constant, hydraulic, held, least)
        weights = net.point_weights(drive.point, drive.fracture)
        if drive.samples is None:   # the start: every node at p0, the faces solved there
            w = faces.openings(np.full(net.num_nodes, drive.initial_pressure))
            state = lub.initial_state(drive.initial_pressure, w, drive.time)
        else:
            # the fluid stays where the flow left it (the new crack empty: the flow fills it, through the
            # viscous resistance that makes a moving tip's suction); the balance's pressure is the first
            # step's start, one that the faces' mechanics agrees with
            carried = carry(drive.samples, net, fractures, lub.lengths)
            state = replace(carried, pressure=balanced(lub, faces, carried).pressure)
        return cls(disc, net, faces, lub, weights, state)

    def samples(self, fractures) -> Samples:
        return sample(self.net, self.state, fractures, self.lub.lengths)

    def injection_pressure(self, state=None) -> float:
        s = self.state if state is None else state
        return float(self.weights @ s.pressure)

    def injection_opening(self) -> float:
        """The faces' normal opening at the injection point at the last
        solve (m): each flow node's the mean of its edge nodes' (the copies
        of a pair agree)."""
        net = self.net
        w, count = np.zeros(net.num_nodes), np.zeros(net.num_nodes)
        np.add.at(w, net.edges.ravel(), np.asarray(self.faces.w, float).ravel())
        np.add.at(count, net.edges.ravel(), 1.0)
        return float(self.weights @ (w / np.maximum(count, 1.0)))

    def publish(self) -> None:
        """The flow's pressure and flux at every pair of the mesh, and each
        fracture's largest pressure, onto the discretisation's fluid
        (face_values writes them; off the network the given pressures, no flux)."""
        disc, net, s = self.disc, self.net, self.state
        cm = disc.cm
        q = self.lub.fluxes(s.pressure, self.faces.w)
        node_flux = np.zeros(net.num_nodes)
        count = np.zeros(net.num_nodes)
        np.add.at(node_flux, net.segments.ravel(), np.repeat(q, 2))
        np.add.at(count, net.segments.ravel(), 1.0)
        node_flux /= np.maximum(count, 1.0)
        n_pairs = len(cm.pairs)
        given = disc.fluid.pressures(0.0)   # the fractures off the network: their given pressures
        pressure = given[np.asarray(cm.pair_fracture, np.int64)] if n_pairs else np.zeros(0)
        flux = np.zeros(n_pairs)
        at = net.pair.ravel() >= 0
        pressure[net.pair.ravel()[at]] = s.pressure[net.edges.ravel()[at]]
        flux[net.pair.ravel()[at]] = node_flux[net.edges.ravel()[at]]
        per_fracture = given.copy()
        for f in np.unique(net.fracture):
            per_fracture[int(f)] = float(np.max(s.pressure[np.unique(net.edges[net.fracture == f])]))
        disc.fluid.flow = (pressure, flux, per_fracture)

    def slip_front(self) -> float:
        """The farthest pair of the network slipping in the last solve from
        the injection point (m; 0 where none slips)."""
        c = self.disc.contact
        res = c.result
        if res is None or getattr(res, "state", None) is None:
            return 0.0
        rows = c.rows
        slipping = rows.pair[rows.coulomb & (res.state == SLIP)]
        if not len(slipping):
            return 0.0
        x = np.asarray(self.disc.cm.x)[np.asarray(self.disc.cm.pairs)[slipping, 0]]
        return float(np.max(np.linalg.norm(x - self.weights @ self.net.x, axis=1)))


@dataclass
class Outcome:
    """How a march on one geometry ended: "growth" (a tip reached KIc at
    `time`; `unstable` where no time passed), "frame", "end"; the state
    there (solved: the geometry's faces and displacement are at it), the
    time steps' history [(t, p at the point, injected, stored, leaked,
    slip front)] and the steps and solves it took."""
    kind: str
    time: float
    history: list = field(default_factory=list)
    steps: int = 0
    solves: int = 0
    unstable: bool = False


def march(drive: FlowDrive, geo: Geometry, keq, KIc: float) -> Outcome:
    """Time steps on geo from its state's time (module doc). keq(t): the
    largest K_eq of the growing tips at the discretisation's current
    solution, the state's time t (None: nothing may grow). Leaves geo.state, drive.time and
    drive.dt at the outcome's time, the discretisation solved and accepted
    there."""
    t = geo.state.time
    stops = drive.stops()
    stops = stops[stops > t * (1 + 1e-14)]
    gap = float(np.min(np.diff(np.r_[0.0, drive.frames])))
    dt = drive.dt if drive.dt else FIRST * gap
    out = Outcome("end", t)
    # K_eq where the geometry begins is no state of the run: the fluid carried to a grown mesh has
    # not yet flowed into the new crack (no step of no time does that); the first step's start
    # counts as below KIc, and where the tips are at KIc as soon as any time passes, the event is
    # found there (unstable growth: the step took no time, to the search's tolerance)
    k = -np.inf
    source_nodes = geo.weights > 0
    while True:
        target = min(t + dt, float(stops[0]))
        if stops[0] - target < 0.25 * dt:   # no sliver of a step before a stop
            target = float(stops[0])
        new, dt_used = _step(drive, geo, geo.state, target, out)
        k_new = _keq_after(geo, new, keq)
        if k_new is not None and k_new >= KIc * (1 - KEQ_TOL):   # at the event, or past it
            if k_new > KIc * (1 + KEQ_TOL):
                new = _locate(drive, geo, geo.state, k, new, k_new, keq, KIc, out)
            geo.disc.solver.accept()
            out.unstable = new.time - t <= UNSTABLE * max(t, 1e-300)
            _commit(drive, geo, new, dt_used, out)
            out.kind = "growth"
            return out
        geo.disc.solver.accept()
        # the next step: held where the pressure changed much at a node other than the source's
        disturbance = max(float(np.max(np.abs(new.pressure - drive.initial_pressure))), 1e-300)
        change = float(np.max(np.abs(new.pressure - geo.state.pressure)[~source_nodes], initial=0.0)) / disturbance
        dt = dt_used * min(GROWTH, max(0.5, CHANGE / max(change, 1e-300)))
        _commit(drive, geo, new, dt, out)
        t, k = new.time, k_new
        if t >= stops[0] * (1 - 1e-14):
            stops = stops[1:]
            if t >= drive.end * (1 - 1e-14):
                out.kind = "end"
                return out
            if np.any(np.abs(drive.frames - t) <= 1e-12 * t):
                out.kind = "frame"
                return out


def _step(drive, geo, state, target, out):
    """The coupled step from `state` to `target`, halved where it fails:
    (the new state, the time step taken)."""
    t = state.time
    for _ in range(MAX_RETRIES):
        if not target - t > SHORTEST * t:   # a step the time cannot resolve: none is left to halve
            break
        try:
            new, info = geo.lub.step(state, target, drive.source(geo.weights, t, target), geo.faces)
        except ArithmeticError:
            target = t + 0.5 * (target - t)
            continue
        out.solves += info.solves
        out.steps += 1
        _require_fluid(new, target)
        return new, target - t
    raise ComputationError(f"the flow found no state after {t:.6g} s even with a time step of {target - t:.3g} s")


def _require_fluid(state, t):
    """A node drained below the floor holds less than the fluid that fills
    it, never less than none: Carter's leak-off is taken whatever a node
    holds, and where it outruns the fluid reaching the faces the network
    would hold less than nothing (beyond the round-off of the fluid there
    was: a closed face's opening, near nothing, at the round-off of its
    mechanics). The model ends there (ComputationError), saying so. Where
    nothing leaked a node's fluid below none is no overdraw: it is open
    faces that overlap (a negative storage aperture, as near a tip the
    fluid's suction closes before the fluid arrives), and the balance holds
    it as it holds the rest."""
    if state.leaked <= 0.0:
        return
    short = -float(np.sum(np.minimum(state.fluid, 0.0)))
    if short > OVERDRAWN * max(abs(state.initial) + abs(state.injected), 1e-300):
        raise ComputationError(f"by {t:.6g} s Carter's leak-off drew more fluid from faces than reached them "
                               f"(they would hold {short:.3g} m^3/m less than none; {state.leaked:.4g} leaked, "
                               f"{state.initial:.4g} held at the start, {state.injected:.4g} injected): the "
                               f"leak-off is not limited to the fluid a face holds (injection.leak_off too "
                               f"large for the injection)")


def _keq_after(geo, state, keq):
    """The whole displacement at the state's pressure, and K_eq there (None: no tip grows)."""
    geo.faces.complete(state.pressure)
    return None if keq is None else keq(state.time)


def _locate(drive, geo, start, k_lo, hi_state, k_hi, keq, KIc, out) -> FlowState:
    """The state at which the growing tips first reach KIc between `start`
    (K_eq k_lo below KIc) and `hi_state` (k_hi above): Illinois in time on
    K_eq(t) / KIc - 1, each trial the step from `start`; the
    discretisation is left solved at the returned state."""
    t_lo, f_lo = start.time, max(k_lo / KIc - 1, -1.0)
    t_hi, f_hi = hi_state.time, k_hi / KIc - 1
    best, side = hi_state, 0
    for _ in range(100):
        t = t_hi - f_hi * (t_hi - t_lo) / (f_hi - f_lo)
        if not t_lo < t < t_hi or not math.isfinite(k_lo):   # no K_eq at the start: bisection first
            t = 0.5 * (t_lo + t_hi)
        new, _ = _step(drive, geo, start, t, out)
        t = new.time
        f = _keq_after(geo, new, keq) / KIc - 1
        if abs(f) <= KEQ_TOL:
            return new
        if f > 0:
            t_hi, f_hi, best = t, f, new
            if side == 1:
                f_lo *= 0.5
            side = 1
        else:
            t_lo, f_lo, k_lo = t, f, 0.0
            if side == -1:
                f_hi *= 0.5
            side = -1
        if t_hi - t_lo <= UNSTABLE * max(t_hi, 1e-300):
            break
    geo.faces.complete(best.pressure)   # K_eq jumps across the bracket: the earliest state found above KIc
    return best


def _commit(drive, geo, new, dt, out):
    inj = geo.injection_pressure(new)
    out.history.append((new.time, inj, new.injected, new.stored, new.leaked, geo.slip_front()))
    geo.state = new
    drive.time, drive.dt = new.time, dt
    out.time = new.time
