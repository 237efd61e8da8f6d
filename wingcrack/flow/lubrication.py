"""Lubrication flow of a compressible fluid in the faces' network
(network.FlowNetwork), one backward-Euler time step at a time.

Mass conservation along the faces, with the cubic law for the flux
(volumes per metre of thickness, fluid counted as its volume at the
reference density rho0, that of the reference pressure p0):

    d(rho a)/dt + d(rho q)/ds = rho0 (source - leak-off),
    q = -k dp/ds,   k = w_h^3 / (12 eta),   rho = rho0 exp(c (p - p0)).

a is the storage aperture (the normal opening w = [u].n plus the constant
aperture of the faces: the gap of contact faces and the residual aperture,
or a fracture's fixed `hydraulic_aperture` in its place), w_h the hydraulic
aperture (w + the constant one, or the fixed one: a conduit whose
permeability does not change with slip or opening). Discretised on the
network's P1 hats phi_i (network.py):

    m_i = rho(p_i) V_i,   V_i = int phi_i a ds                 (the fluid at node i)
    R_i = m_i - m_i^n + dt sum_s +-rho_s c_s (p_a - p_b) + L_i - S_i = 0
    c_s = int_s k ds / h_s^2,   rho_s = (rho_a + rho_b) / 2        (segment s = [a, b], length h_s)

S_i the source over the step (a rate: the pumped volume of the schedule
over the step, exact; a pressure given at the point: the multiplier of the
constraint sum_i phi_i(x0) p_i = p_given), L_i Carter's leak-off over the
step, 2 C_L (sqrt(t - t_e) - sqrt(t^n - t_e)) int phi_i ds at the density of
p_i (both faces; t_e the time node i first held fluid). The rows sum to
m - m^n + leaked - injected: the fluid balance holds to the Newton
residual (solved to RTOL of the fluid), not to the discretisation error.
A node whose faces neither store (no aperture, an incompressible fluid)
nor conduct holds its pressure: it is dry (a closed wing's inside, where no
fluid goes). The pressure does not fall below FLOOR (0: a fluid under
tension cavitates): where the fluid cannot fill a node's faces (a dry
fracture joined, a fast tip's suction) it holds FLOOR, partly filled. The
unknown is q, the pressure p = max(q, FLOOR) above the floor and a deficit
below it: node i holds m_i = rho(p_i) V_i + kappa_i min(q_i - FLOOR, 0) of
fluid (kappa_i > 0 any scale), so that the equations stay one per node,
semismooth in q.

The openings come from the mechanics (`Mechanics`): `openings(p)` solves
the faces at the pressure field p and returns w at every edge node, and
`derivative()` dw/dp at that solve (None: the faces do not move with the
pressure). Newton's method on p uses it in the storage term and in the
conductances (full Newton where the derivative is exact: open faces and a
contact state set that holds), with a backtracking line search on the
residual where a change of the contact state makes the step overshoot.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
from scipy import sparse
from scipy.sparse import linalg as splinalg

from .network import FlowNetwork

#: Newton's residual, relative to the fluid that moves in the step: far below any discretisation
#: error, and the fluid balance of the totals (a sum of the residuals over the nodes and the steps)
#: well inside the 1e-8 the run promises
RTOL = 1e-13
#: the most mechanics solves of one time step
MAX_ITERATIONS = 60
#: the most Newton iterations of the flow in one time step (on linearised mechanics)
MAX_NEWTON = 200
#: halvings of a Newton step whose residual does not fall
MAX_HALVINGS = 12
#: the round-off of the residual's terms (the fluid held, the fluxes), relative: a few operations
#: each, and the Newton solve's own error on top (its matrix holds the storage next to dt times the
#: conductances)
ROUND_OFF = 64 * np.finfo(float).eps
#: a Newton iteration that no step improves stops there within this many tolerances
STALL = 100.0
#: the Tikhonov term of the Newton solve, relative to the Jacobian's largest entry
REGULAR = 1e-12
#: the lowest pressure (Pa): an absolute pressure below it is a fluid under tension, which cavitates;
#: a node the fluid cannot fill holds FLOOR, partly filled (as the pump's network, propagation.fluid)
FLOOR = 0.0
#: kappa per metre of faces (m^2 of fluid per Pa of deficit per m): 1e-6 m of aperture a MPa
DEFICIT_SCALE = 1e-12


@dataclass(frozen=True)
class Fluid:
    """viscosity eta (Pa s), compressibility c (1/Pa), the reference pressure
    p0 of the density law (Pa), Carter's leak-off coefficient C_L (m/s^0.5)."""
    viscosity: float
    compressibility: float = 0.0
    reference_pressure: float = 0.0
    leak_off: float = 0.0

    def density(self, p) -> np.ndarray:
        """rho(p) / rho0."""
        return np.exp(self.compressibility * (np.asarray(p, float) - self.reference_pressure))


@dataclass
class FlowState:
    """The fluid at a time: the pressure p (n,) (Pa), the fluid m (n,) each
    node holds (m^2 per metre at rho0), the totals injected and leaked since
    the start (m^2 per metre), and the time each node first held fluid
    (Carter's exposure time, s)."""
    time: float
    pressure: np.ndarray
    fluid: np.ndarray
    injected: float = 0.0
    leaked: float = 0.0
    exposed: np.ndarray = None
    initial: float = None   # the fluid held at the start (sum of m)

    def __post_init__(self):
        if self.exposed is None:
            self.exposed = np.full(len(self.pressure), self.time)
        if self.initial is None:
            self.initial = float(np.sum(self.fluid))

    @property
    def stored(self) -> float:
        """The fluid the network holds beyond what it held at the start."""
        return float(np.sum(self.fluid)) - self.initial

    def imbalance(self) -> float:
        """injected - stored - leaked, relative to all the fluid there was
        (held at the start and injected since): the fluid held is a sum over
        the nodes, whose round-off is that fraction of it."""
        scale = max(abs(self.initial) + abs(self.injected), 1e-300)
        return (self.injected - self.stored - self.leaked) / scale


class RigidFaces:
    """Faces that do not move with the pressure: a fixed opening (k, 3)."""

    def __init__(self, opening):
        self.w = np.asarray(opening, float)

    def openings(self, p) -> np.ndarray:
        return self.w

    def derivative(self):
        return None


@dataclass
class Source:
    """Where and how the fluid enters over a step: weights (n,) the hats at
    the injection point; either `volume`, the fluid the pump delivers over
    the step (m^2/m at rho0), or `pressure`, the pressure held there (Pa)."""
    weights: np.ndarray
    volume: float | None = None
    pressure: float | None = None


@dataclass
class StepInfo:
    """How a step went: the flow's Newton iterations, the mechanics' solves,
    the final residual (of the fluid that moved), the halvings back towards
    the best state, the dry nodes."""
    iterations: int = 0
    solves: int = 0
    residual: float = 0.0
    halvings: int = 0
    dry: int = 0


class _Linearised:
    """The mechanics linearised at p_k: w = w_k + W (p - p_k) (W None: w_k)."""

    def __init__(self, p_k, w_k, W, resolution=0.0):
        self.p_k, self.w_k, self.W, self.resolution = p_k, np.asarray(w_k, float), W, resolution

    def openings(self, p):
        if self.W is None:
            return self.w_k
        return self.w_k + (np.asarray(self.W) @ (p - self.p_k)).reshape(self.w_k.shape)

    def derivative(self):
        return self.W


class _Frozen(_Linearised):
    """The openings of a solve, held."""

    def __init__(self, w, resolution=0.0):
        super().__init__(None, w, None, resolution)


@dataclass
class _Evaluation:
    """The residual of the flow's equations at the unknown p (q of the
    module doc: the pressure where it is above the floor), the multiplier
    lam of a given pressure, with what the Jacobian needs, the fluid each
    node holds, the residual's norm, the tolerance and the scale it is
    measured against."""
    p: np.ndarray
    lam: float
    R: np.ndarray
    w: np.ndarray
    rho: np.ndarray
    V: np.ndarray
    c: np.ndarray
    rho_s: np.ndarray
    dp: np.ndarray
    held: np.ndarray = None
    norm: float = 0.0
    tol: float = 0.0
    scale: float = 0.0


class _StepProblem:
    """The equations of one backward-Euler step (module doc) for a given
    mechanics model, and Newton's method on them."""

    def __init__(self, lub, state, dt, carter, source, mechanics, rtol):
        self.lub, self.dt, self.carter, self.source, self.rtol = lub, dt, carter, source, rtol
        self.m_old = state.fluid
        self.given = source.pressure is not None
        self.wts = np.asarray(source.weights, float)

    def evaluate(self, model, q, lam=None) -> _Evaluation:
        """The equations at the unknown q (module doc: p = max(q, 0), the
        fluid rho V + kappa min(q, 0))."""
        lub, seg = self.lub, self.lub.net.segments
        p = np.maximum(q, FLOOR)
        w = model.openings(p)
        rho = lub.fluid.density(p)
        V = lub.volumes(w)
        c = lub.conductances(w)
        rho_s = 0.5 * (rho[seg[:, 0]] + rho[seg[:, 1]])
        dp = p[seg[:, 0]] - p[seg[:, 1]]
        flux = rho_s * c * dp
        held = rho * V + lub.kappa * np.minimum(q - FLOOR, 0.0)
        R = held - self.m_old + self.dt * (lub._G @ flux) + rho * self.carter
        if self.given:
            if lam is None:   # the multiplier that best balances the residual: the source's least squares
                lam = float(self.wts @ R / (self.wts @ self.wts))
            r = R - self.wts * lam
        else:
            lam, r = 0.0, R - self.wts * self.source.volume
            R = r
        e = _Evaluation(q, lam, R if not self.given else R, w, rho, V, c, rho_s, dp, held=held)
        e.norm = float(np.max(np.abs(r), initial=0.0))
        # the residual's scale: the fluid that moves in the step (the inflow, the leak-off, the change of
        # the fluid held), floored at the round-off of its terms (the fluid held, the fluxes: a
        # difference of pressures carries their round-off, which the conductance over a long step
        # magnifies where the pressure has evened out) and of the openings the mechanics computes (its
        # `resolution`, m), so that the balance of the totals holds to RTOL of what came and went,
        # however much the network held before
        moved = max(abs(lam) if self.given else abs(self.source.volume), float(np.sum(rho * self.carter)),
                    float(np.max(np.abs(held - self.m_old), initial=0.0)))
        level = rho_s * c * (np.abs(p[seg[:, 0]]) + np.abs(p[seg[:, 1]]))   # a flux's terms: p's round-off
        noise = ROUND_OFF * (np.abs(self.m_old) + self.dt * (abs(lub._G) @ level)) + \
            rho * lub.lengths * model.resolution
        floor = float(np.max(noise, initial=0.0))
        e.scale = max(moved, floor, 1e-300)
        e.tol = max(self.rtol * moved, floor)
        return e

    def residual(self, e: _Evaluation) -> np.ndarray:
        return e.R - self.wts * e.lam if self.given else e.R

    def newton(self, model, p, lam, info) -> tuple[np.ndarray, float]:
        """The root p (and multiplier) of the step's equations with the
        openings of `model`, from p; a backtracking line search where the
        residual does not fall."""
        n = self.lub.net.num_nodes
        e = self.evaluate(model, p, lam)
        first = True
        while first or e.norm > e.tol:
            first = False
            if e.norm == 0.0:
                break
            if info.iterations >= MAX_NEWTON:
                raise ArithmeticError(f"the flow's Newton iteration did not converge in {MAX_NEWTON} "
                                      f"iterations (residual {e.norm / e.scale:.3g} of the fluid)")
            info.iterations += 1
            J, dry = self.lub._jacobian(model, e.w, e.rho, e.V, e.c, e.rho_s, e.dp, self.dt, self.carter, e.p)
            info.dry = int(np.sum(dry))
            # the P1 pressure has more nodes than the faces have openings (a tip node's hat loads pairs
            # only): where nothing conducts, a field that loads no face stores nothing, and J is
            # singular in it; a Tikhonov term of round-off size leaves that part of p where it was
            J = J + REGULAR * float(abs(J).max()) * (sparse.identity(n) if sparse.issparse(J) else np.eye(n))
            r = self.residual(e).copy()
            r[dry] = 0.0
            wts = self.wts
            if self.given:
                A = sparse.bmat([[J, -sparse.csr_matrix(wts[:, None])], [sparse.csr_matrix(wts[None, :]), None]],
                                format="csc") if sparse.issparse(J) else \
                    np.block([[J, -wts[:, None]], [wts[None, :], np.zeros((1, 1))]])
                rhs = np.r_[-r, self.source.pressure - wts @ e.p]
            else:
                A, rhs = (J.tocsc() if sparse.issparse(J) else J), -r
            x = splinalg.spsolve(A, rhs) if sparse.issparse(A) else np.linalg.solve(A, rhs)
            dp_, dlam = (x[:n], x[n]) if self.given else (x, 0.0)
            step = 1.0
            for _ in range(MAX_HALVINGS + 1):
                trial = self.evaluate(model, e.p + step * dp_, e.lam + step * dlam if self.given else None)
                if trial.norm < e.norm or trial.norm <= trial.tol:
                    break
                step *= 0.5
            if trial.norm >= e.norm and e.norm <= STALL * e.tol:
                break   # at the round-off of the dense solve: no step lowers the residual
            e = trial
        return e.p, e.lam


class Lubrication:
    """The discrete flow on `network` (module doc). constant (k, 3): the
    constant part of the storage aperture at each edge node (m: the gap and
    residual aperture, or the fixed hydraulic aperture of a conduit);
    hydraulic (k,): a conduit edge's fixed hydraulic aperture (m), NaN on
    the others (their hydraulic aperture is the storage aperture); held
    (k,) bool: the edges whose faces the contact holds apart (none by
    default), whose aperture is never below least (k,) (m; 0 by default:
    the positive part; see volumes)."""

    def __init__(self, network: FlowNetwork, fluid: Fluid, constant=None, hydraulic=None, held=None,
                 least=None):
        self.net, self.fluid = network, fluid
        k = network.num_edges
        self.constant = np.zeros((k, 3)) if constant is None else np.asarray(constant, float).reshape(k, 3)
        self.hydraulic = np.full(k, np.nan) if hydraulic is None else np.asarray(hydraulic, float).reshape(k)
        self.Phi = network.volume_matrix()
        #: (2k, 1) per segment: its faces the contact holds apart
        held_seg = (np.zeros(k, bool) if held is None else np.asarray(held, bool).reshape(k)).repeat(2)
        self._held_q = held_seg[:, None]
        #: (k, 3) the least aperture of each edge's held faces (m), and (2k, 1) per segment
        self._least = np.zeros((k, 3)) if least is None else np.repeat(np.asarray(least, float).reshape(k, 1), 3, 1)
        self._least_q = self._least[:, 0].repeat(2)[:, None]
        self.lengths = network.tributary()
        #: the fluid a node's deficit q < FLOOR stands for, per Pa (m^2/Pa: any scale; a nominal aperture a
        #: nominal pressure): the unknown's meaning below the floor, no result depends on it
        self.kappa = self.lengths * DEFICIT_SCALE
        conduit = np.repeat(np.isfinite(self.hydraulic), 2)   # per segment
        self._conduit = conduit
        seg_h = np.repeat(np.nan_to_num(self.hydraulic), 2)
        self._conduit_c = np.where(conduit, seg_h ** 3 / (12 * fluid.viscosity) / network.length, 0.0)
        s = network.segments
        n = network.num_nodes
        # the segments' incidence: (n, 2k), +1 at a segment's first node, -1 at its second
        self._G = sparse.csr_matrix((np.r_[np.ones(len(s)), -np.ones(len(s))],
                                     (np.r_[s[:, 0], s[:, 1]], np.r_[np.arange(len(s)), np.arange(len(s))])),
                                    shape=(n, len(s)))

    # ---- the fields of an opening

    def volumes(self, w) -> np.ndarray:
        """(n,) V_i = int phi_i a ds, a = w + the constant aperture; on the
        faces the contact holds apart (`held`) a no less than their least
        aperture (`least`: 0, or a wing's residual aperture). Their P2
        opening dips below zero between a node the contact holds closed and
        an open one (the contact holds the nodes, not the stretches between
        them), a volume no fluid fills and no pressure could (a closed wing
        beside the kink that opens: its negative volume left the step
        without a root); and a shut wing's rough faces leave the fluid
        their residual aperture. Open faces keep the opening as the
        elasticity gives it: where they overlap (a moving tip's suction)
        the network holds that much less, as the mechanics says."""
        a = np.asarray(w, float).reshape(-1, 3) + self.constant
        if not self._held_q.any():
            return self.Phi @ a.ravel()
        a_q = self.net.at_quadrature(a)
        return self.net.integrate(np.where(self._held_q, np.maximum(a_q, self._least_q), a_q))

    def volume_derivative(self, w) -> sparse.csr_matrix:
        """(n, 3k) dV/dw: the volume matrix over the quadrature points where
        the opening counts (volumes: not where held faces are at their least
        aperture)."""
        below = self._floored(w)
        return self.Phi if not below.any() else self.net.volume_matrix(~below)

    def _floored(self, w) -> np.ndarray:
        """(2k, q) bool: the quadrature points of held faces whose aperture
        is at most their least one (there it is the least one)."""
        a = self.net.at_quadrature(np.asarray(w, float).reshape(-1, 3) + self.constant)
        return self._held_q & (a <= self._least_q)

    def _apertures_q(self, w) -> np.ndarray:
        """(2k, q) the hydraulic aperture at the quadrature points (>= 0; on
        held faces >= their least aperture)."""
        a = self.net.at_quadrature(np.asarray(w, float).reshape(-1, 3) + self.constant)
        return np.where(self._held_q, np.maximum(a, self._least_q), np.maximum(a, 0.0))

    def conductances(self, w) -> np.ndarray:
        """(2k,) c_s = int_s k ds / h_s^2 (m^2 / (Pa s) per m^2... : the flux
        (m^2/s) through segment s is c_s h_s (p_a - p_b))."""
        a = self._apertures_q(w)
        c = np.einsum("sq,sq->s", a ** 3, self.net.ds) / (12 * self.fluid.viscosity) / self.net.length ** 2
        return np.where(self._conduit, self._conduit_c, c)

    def conductance_derivative(self, w) -> sparse.csr_matrix:
        """(2k, 3k) d c_s / d w at the edge nodes (0 on conduits)."""
        a = self._apertures_q(w) * ~self._floored(w)   # no derivative where the least aperture holds
        d = 3 * a ** 2 * self.net.ds / (12 * self.fluid.viscosity) / self.net.length[:, None] ** 2   # (2k, q)
        vals = np.einsum("sq,sqm->sm", d, self.net.shape)
        vals[self._conduit] = 0.0
        k = self.net.num_edges
        rows = np.repeat(np.arange(2 * k), 3)
        cols = (3 * np.repeat(np.arange(k), 2)[:, None] + np.arange(3)).ravel()
        return sparse.csr_matrix((vals.ravel(), (rows, cols)), shape=(2 * k, 3 * k))

    def fluxes(self, p, w) -> np.ndarray:
        """(2k,) the volume flux q (m^2/s, along the segment's direction) of
        each segment: c_s h_s (p_a - p_b)."""
        p = np.asarray(p, float)
        s = self.net.segments
        return self.conductances(w) * self.net.length * (p[s[:, 0]] - p[s[:, 1]])

    def fluid_of(self, p, w) -> np.ndarray:
        """(n,) the fluid m_i = rho(p_i)/rho0 V_i each node holds."""
        return self.fluid.density(p) * self.volumes(w)

    def initial_state(self, p0, w, time: float = 0.0, exposed=None) -> FlowState:
        """The state at pressure p0 (a number or (n,)) on the opening w."""
        p = np.broadcast_to(np.asarray(p0, float), (self.net.num_nodes,)).copy()
        return FlowState(float(time), p, self.fluid_of(p, w), exposed=exposed)

    # ---- leak-off

    def _carter(self, state: FlowState, t1: float) -> np.ndarray:
        """(n,) Carter's leak-off volume over [t0, t1] at each node (m^2/m at the node's density)."""
        cl = self.fluid.leak_off
        if not cl:
            return np.zeros(self.net.num_nodes)
        e = state.exposed
        t0 = state.time
        after = np.sqrt(np.maximum(t1 - e, 0.0)) - np.sqrt(np.maximum(t0 - e, 0.0))
        return 2.0 * cl * after * self.lengths

    # ---- the step

    def step(self, state: FlowState, t1: float, source: Source, mechanics=None,
             rtol: float = RTOL) -> tuple[FlowState, StepInfo]:
        """The state at t1 > state.time: backward Euler, from
        state.pressure. mechanics: openings(p) and derivative() (module doc;
        RigidFaces for faces that do not move), and `last`, (p, w) of its last
        solve, or None. The mechanics is left solved at the returned pressure.

        Newton's method on p, the mechanics linearised: each outer iteration
        solves the flow to convergence with the openings w_k + W_k (p - p_k)
        (w_k, W_k = dw/dp the mechanics' at p_k; the first from its last
        solve), then solves the mechanics at the new pressure; done when
        the flow's residual with those openings is within the tolerance.
        Where the linearisation is exact (closed faces, open ones whose
        contact states hold) one mechanics solve a step; the flow's own
        nonlinearity (the density, the cubic law) costs no mechanics solve."""
        net = self.net
        mechanics = RigidFaces(np.zeros((net.num_edges, 3))) if mechanics is None else mechanics
        dt = float(t1) - state.time
        if not dt > 0:
            raise ValueError(f"a time step must go forward (from {state.time:g} s to {t1:g} s)")
        carter = self._carter(state, t1)
        wts = np.asarray(source.weights, float)
        p = state.pressure.copy()
        if source.pressure is not None:   # a field that meets the constraint, changed at the source's nodes only
            at = wts > 0
            p[at] += (source.pressure - wts @ p) / np.sum(wts[at])
        info = StepInfo()
        problem = _StepProblem(self, state, dt, carter, source, mechanics, rtol)
        last = getattr(mechanics, "last", None)
        # the first linearisation at the state's pressure: the mechanics' last solve where it was there
        # (a step retried with a shorter time step left it at a trial of the failed one)
        if last is None or not np.array_equal(last[0], np.maximum(state.pressure, FLOOR)):
            p_k, w_k = p, mechanics.openings(p)
            info.solves += 1
        else:
            p_k, w_k = last
        W_k = mechanics.derivative()
        lam = None
        accepted = []   # the residual norms of the states the outer iteration moved to
        best = None

        def solved(q, lam):   # the mechanics solved at the pressure of the unknown q, and the flow's residual there
            w = mechanics.openings(np.maximum(q, FLOOR))
            info.solves += 1
            return w, problem.evaluate(_Frozen(w, getattr(mechanics, "resolution", 0.0)), q, lam)

        while True:
            model = _Linearised(p_k, w_k, W_k, getattr(mechanics, "resolution", 0.0))
            p_new, lam = problem.newton(model, p if best is None else q_k, lam, info)
            w, true = solved(p_new, lam)
            if true.norm <= true.tol:
                break
            # a semismooth Newton step may cross a change of the contact states (the linearisation held
            # the states of the last one): the new state is taken where its residual is below the
            # largest of the last two taken (non-monotone: crossing a kink of the opening, as a crack
            # starts to open, first overshoots, then lands), else back towards the best one
            halvings = 0
            while accepted and true.norm >= max(accepted[-2:]) and true.norm > true.tol:
                halvings += 1
                info.halvings += 1
                if halvings > MAX_HALVINGS:
                    raise ArithmeticError(f"the flow and the faces found no common state in {info.solves} "
                                          f"solves (residual {true.norm / true.scale:.3g} of the fluid)")
                p_new = 0.5 * (p_new + best.p)
                lam = None if lam is None else 0.5 * (lam + best.lam)
                w, true = solved(p_new, lam)
            if true.norm <= true.tol:
                break
            if info.solves >= MAX_ITERATIONS:
                raise ArithmeticError(f"the flow and the faces did not converge in {MAX_ITERATIONS} solves "
                                      f"(residual {true.norm / true.scale:.3g} of the fluid)")
            accepted.append(true.norm)
            best = true if best is None or true.norm < best.norm else best
            q_k = p_new
            p_k, w_k, W_k = np.maximum(p_new, FLOOR), w, mechanics.derivative()
        m = true.held
        injected = true.lam if source.pressure is not None else float(source.volume)
        leaked = float(np.sum(true.rho * carter))
        info.residual = true.norm / true.scale
        out = FlowState(float(t1), np.maximum(p_new, FLOOR), m, state.injected + injected, state.leaked + leaked,
                        state.exposed.copy(), state.initial)
        return out, info

    def _jacobian(self, mechanics, w, rho, V, c, rho_s, dp, dt, carter, q):
        """dR/dq (sparse, or dense where the mechanics has a derivative) and
        the dry nodes (a zero row: neither storage nor conductance): the
        pressure's derivative where q is above the floor, the deficit's
        kappa where it is below."""
        fl, net = self.fluid, self.net
        seg = net.segments
        cf = fl.compressibility
        k_s = len(seg)
        # d F_s / d p_a, d p_b
        dFa = rho_s * c + 0.5 * cf * rho[seg[:, 0]] * c * dp
        dFb = -rho_s * c + 0.5 * cf * rho[seg[:, 1]] * c * dp
        dF = sparse.csr_matrix((np.r_[dFa, dFb], (np.r_[np.arange(k_s), np.arange(k_s)], np.r_[seg[:, 0], seg[:, 1]])),
                               shape=(k_s, net.num_nodes))
        J = sparse.diags(cf * rho * (V + carter)) + dt * (self._G @ dF)
        W = mechanics.derivative()
        above = (np.asarray(q) > FLOOR).astype(float)   # dp/dq
        below = self.kappa * (1.0 - above)
        if W is not None:   # the faces move with p: the storage's and the conductances' share
            W = np.asarray(W, float)
            dc = self.conductance_derivative(w)
            J = J.toarray() + rho[:, None] * (self.volume_derivative(w) @ W) + \
                dt * (self._G @ sparse.diags(rho_s * dp) @ dc @ W)
            J = J * above[None, :] + np.diag(below)
            diag = np.abs(np.diag(J))
            off = np.abs(J).sum(axis=1) - diag
        else:
            J = (J @ sparse.diags(above) + sparse.diags(below)).tocsr()
            diag = np.abs(J.diagonal())
            off = np.asarray(abs(J).sum(axis=1)).ravel() - diag
        big = max(float(np.max(diag + off, initial=0.0)), 1e-300)
        dry = (diag + off) <= 1e-14 * big
        if np.any(dry):   # hold their pressure: dp = 0 (a diagonal of the matrix's own scale)
            if sparse.issparse(J):
                keep = sparse.diags((~dry).astype(float))
                J = (keep @ J + sparse.diags(big * dry.astype(float))).tocsr()
            else:
                J[dry] = 0.0
                J[dry, dry] = big
        return J, dry
