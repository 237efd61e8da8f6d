"""One step of wingcrack, the same for `sif` (step 0, at load factor 1) and
for every step of `run` (the paper's Fig. 8 loop, propagation/loop.py):
    fractures (polylines)
      -> discretise(): crack mesh (meshing worker, under a time limit)
         -> DOLFINx mesh -> loads -> free pieces? -> assembly
         -> factorisation (+ Schur complement on the contact pair dofs)
         -> contact set-up                                  = Discretisation
      -> Discretisation.solve(load factor): elasticity + active set
      -> Discretisation.sifs(): both methods at every tip   = [TipSIF]
      -> finish(): the step's files (step_XXXX.vtu, faces_XXXX.vtu, the
         .pvd indices) and its record                       = results.StepRecord

A computation that fails raises one of FAILURES; failure() turns it into the
status "failed: step <k>: <reason>", the same for both commands.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

import wingcrack_kernels as K
from meshing import mesher, start_worker
from . import progress
from .contact.constraints import constraint_rows, pre_existing_pairs
from .errors import ComputationError, WriteError
from .fem.nodal import nodal_displacements
from .floating import Floating
from .free_pieces import describe, free_pieces
from .io.faces import SLIP, STICK, write_faces
from .io.fields import write_field_arrays
from .io.outdir import FACES_PVD, FIELDS_PVD, SUMMARY, faces_name, fields_name
from .io.pvd import increasing, write_pvd
from .loads import case_loads, opening_functionals
from .parallel import RootPending, on_root, world_rank
from .results import MESH_STATS, ContactRecord, StepRecord, Summary, TipRecord
from .schedule import Schedule
from .version import __version__

#: seconds gmsh may take for one mesh; then it is retried once, coarser, and
#: then the step fails (meshing/timeout.py)
MESH_TIMEOUT = 120.0
#: the two SIF methods disagree at a tip when KI or KII differ by more than
#: this fraction of the interaction integral's K = sqrt(KI_M^2 + KII_M^2)
#: of the tip, and by more than this fraction of SIF_FLOOR * the step's K
#: scale (sif_scale: the larger of KIc and the step's largest K)
SIF_AGREEMENT = 0.01
#: Below SIF_FLOOR * the step's K scale a tip's own K is no measure of the
#: disagreement. Both methods' errors are absolute, fractions of the field's
#: K scale (the verification states them so: on the Griffith crack DC 0.3 %
#: and M 0.04 % of s sqrt(pi a); on a closed crack |KI| < 5e-3 of it), so at
#: a closed or shielded tip whose K is round-off or a small fraction of the
#: scale they differ by "100 % of K" while each is as accurate as anywhere.
#: Such a tip is far from growth: K_eq <= 1.3 K (the MTS criterion's
#: largest ratio, at KII/KI = -sqrt(3)) < 0.65 of the scale, KIc where the
#: step is critical; it would take a disagreement of 0.35 KIc, 70 times the
#: floor of 0.5 % of the scale, to change that, and that still warns. At a
#: tip above the floor the rule is 1 % of its own K.
SIF_FLOOR = 0.5
#: a tip "reached" KIc in a static solve (sif): K_eq >= KIc (1 - this)
STATIC_RTOL = 1e-9
#: pair systems of more rows than this are solved as sparse saddle-point systems (fem.pair_saddle):
#: the dense route's pair compliance (m^2 numbers) and MUMPS's dense Schur complement on the pair dofs
#: (4 dofs a pair) grow with the square of the pairs, 0.8 GB at this size
DENSE_ROWS = 5000
#: what ends a computation with "failed: <reason>" (every finished step kept)
FAILURES = (ComputationError, RuntimeError, ValueError, np.linalg.LinAlgError)


class Timer:
    """Wall-clock seconds per phase: lap(name) adds the time since the last lap."""

    def __init__(self):
        self.seconds = {}
        self._t = time.perf_counter()

    def lap(self, name: str) -> None:
        t = time.perf_counter()
        self.seconds[name] = self.seconds.get(name, 0.0) + (t - self._t)
        self._t = t


@dataclass
class Discretisation:
    """A geometry made ready to solve: cm, the crack mesh (meshing.CrackMesh:
    nodes, P2 cells, face pairs, tips with their rosette nodes); problem, the
    elastic problem (fem.elasticity.ElasticProblem, assembled and
    factorised); contact, its contact problem (fem.contact_problem);
    pressures, the fluid pressure of every fracture it was built from, at
    load factor 1 (their indices are cm.pair_fracture's); network, with
    load = "injection", the injected network's fractures, whose pressure
    is the load factor."""
    cm: object
    problem: object
    contact: object
    pressures: np.ndarray = None   # (n_fractures,) the fractures' given pressures (Pa, factor 1)
    far: object = None   # the far field's factorisation it used (fem.far_field.FarField), or None
    network: np.ndarray = None   # (n_fractures,) bool, load = "injection" only
    solved_at: float | None = None   # the load factor of the last solve
    residual: np.ndarray = None   # (p,) each pair's residual aperture (m; a pumped case's pre-existing faces)
    _openings: object = field(default=None, repr=False)

    @property
    def dofs(self) -> int:
        return int(self.problem.fm.num_dofs)

    @property
    def cells(self) -> int:
        return int(self.problem.fm.num_cells)

    def solve(self, load_factor: float):
        """Displacement at `load_factor`, with contact (the active set) on the
        faces that have it, friction as one increment from the reference slip
        (see accept); the contact result (None without rows)."""
        self.solved_at = float(load_factor)
        return self.contact.solve(load_factor)

    def solution_at(self, load_factor: float):
        """The solution at `load_factor`: the last solve's where it was at
        this load factor, else a new solve (the contact result). The same:
        nothing but a solve changes the state a solve starts from, or
        accept(), which takes the last solve's own solution, whose increment
        to the same load is none."""
        if self.solved_at != float(load_factor):
            return self.solve(load_factor)
        return self.contact.result

    def accept(self) -> None:
        """The current solution becomes the converged state the next solve
        starts from (friction is path dependent; without it nothing changes)."""
        self.contact.accept()

    def pair_slips(self) -> np.ndarray:
        """(p,) the slip [u].t of every Coulomb pair at the current solution
        (0 elsewhere): the history the next mesh carries on."""
        c = self.contact
        out = np.zeros(len(self.cm.pairs))
        if c.result is not None:
            k = c.rows.coulomb
            out[c.rows.pair[k]] = c.result.jump[k]
        return out

    def correlation_sifs(self, case):
        """(KI, KII) of every tip by displacement correlation: four nodal
        displacements a tip, cheap enough for the critical-load search."""
        from .tip_sifs import correlation_sifs   # DOLFINx: loaded by a run's first step, not by check

        m = case.material
        return correlation_sifs(self.problem, self.cm, m.E, m.nu, m.plane)

    def sifs(self, case, polylines) -> list:
        """TipSIF of every tip of the mesh for the current solution: both
        methods, and theta, K_eq, G of the method that drives growth
        (case.propagation.sif). polylines: the fractures' (n, 2) points."""
        from .tip_sifs import tip_sifs   # DOLFINx: loaded by a run's first step, not by check

        m = case.material
        forces = self.face_forces()
        tips = tip_sifs(self.problem, self.cm, [np.asarray(p, float) for p in polylines], case.domain, m.E, m.nu,
                        m.plane, case.stress.tensor(), face_forces=forces)
        for t in tips:
            require_finite(f"a SIF at fracture {t.fracture} end {t.end}",
                           [v for v in (t.KI, t.KII, t.KI_M, t.KII_M, t.G, t.K_eq) if v is not None])
        return driving(tips, case)

    def face_forces(self):
        """(n_nodes, 2) the forces on the face nodes at the current solution,
        contact and fluid pressure (the interaction integral's crack-face
        term), or None when the faces carry none."""
        out = None
        if self.contact.result is not None:
            out = self.contact.nodal_forces(len(self.cm.x))
        p = self.problem.loads.face_forces_at(self.problem.load_factor_solved)
        if p is not None:
            out = p if out is None else out + p
        return out

    def pressure_at(self, load_factor: float) -> np.ndarray:
        """(n_fractures,) the fluid pressure of each fracture at `load_factor`
        (Pa; the given pressures times the factor that multiplies them; with
        load = "injection" the factor itself on the injected network)."""
        if self.pressures is None:   # built without them: dry fractures
            n = int(np.max(self.cm.pair_fracture, initial=-1)) + 1 if len(self.cm.pairs) else 0
            return np.zeros(n)
        if self.network is not None:
            return np.where(self.network, float(load_factor), self.pressures)
        return self.pressures * self.problem.loads.pressure_factor(load_factor)

    def openings(self) -> np.ndarray:
        """(n_fractures,) the integral of the normal opening [u].n over each
        fracture's faces, wings included, at the current solution (m^2 per
        metre; loads.opening_functionals: the consistent P2 integral, the
        pressure's work per unit pressure). Collective."""
        if self._openings is None:
            from .fem.nodal_functionals import NodalFunctionals   # the FE layer: loaded by a run's first step

            self._openings = NodalFunctionals(self.problem, opening_functionals(self.cm, len(self.pressure_at(1.0))))
        return self._openings.values()

    def driving_sifs(self, case, polylines):
        """(KI, KII) of every tip by the method that drives growth: displacement
        correlation alone (cheap), or the interaction integral (where it has
        no room, correlation)."""
        if sif_method(case) == "correlation":
            return self.correlation_sifs(case)
        tips = self.sifs(case, polylines)
        return (np.array([t.KI if t.KI_M is None else t.KI_M for t in tips], float),
                np.array([t.KII if t.KII_M is None else t.KII_M for t in tips], float))

    def pair_states(self):
        """(state (p,) int8 OPEN / STICK / SLIP (io.faces), closed (p,) bool:
        in contact, state != OPEN on a normal row) of every face-node pair,
        in cm.pairs order. Local (no communication)."""
        closed = np.zeros(len(self.cm.pairs), bool)
        c = self.contact
        if c.result is not None:
            normal = c.rows.normal
            closed[c.rows.pair[normal]] = c.result.active[normal]
        return c.pair_states(len(self.cm.pairs)), closed

    def face_values(self) -> dict:
        """The faces' values of every face-node pair, in cm.pairs order
        (io/faces.py writes them): {"jump": (p, 2) [u] = u(+) - u(-) (m),
        "normal_traction": (p,) t_n (Pa, <= 0 in contact; 0 without a normal
        row), "tangential_traction": (p,) t_t = -forces_t / weight = t.sigma.n
        (Pa, the shear stress on the face plane, signed as the slip it
        drives; 0 without a tangential row), "state" and "closed"
        (pair_states), "slip_increment": (p,) s - s_reference (m; 0 on
        non-coulomb pairs), "pressure": (p,) the fluid pressure of the pair's
        fracture at the solved load (Pa), "aperture": (p,) the fluid's aperture
        w + g + the residual aperture (m; w = [u].n, g the initial gap where a
        normal row holds it, the residual aperture on pre-existing faces)}.
        Collective (the face displacements are gathered)."""
        pairs = np.asarray(self.cm.pairs, dtype=np.int64).reshape(-1, 2)
        fm, u = self.problem.fm, self.problem.u
        jump = nodal_displacements(fm, u, pairs[:, 0]) - nodal_displacements(fm, u, pairs[:, 1])
        normal_traction = np.zeros(len(pairs))
        tangential_traction = np.zeros(len(pairs))
        slip_increment = self.contact.slip_increments(len(pairs))
        state, closed = self.pair_states()
        c = self.contact
        if c.result is not None:
            normal = c.rows.normal
            t = c.tractions()
            normal_traction[c.rows.pair[normal]] = t[normal]
            tangential_traction[c.rows.pair[~normal]] = t[~normal]
        pressure = self.pressure_at(self.problem.load_factor_solved)[np.asarray(self.cm.pair_fracture, np.int64)] \
            if len(pairs) else np.zeros(0)
        gap = np.zeros(len(pairs))
        normal = c.rows.normal
        gap[c.rows.pair[normal]] = c.rows.gap[normal]
        n = np.asarray(self.cm.pair_normal, float).reshape(-1, 2)
        aperture = np.sum(jump * n, axis=1) + gap + (0.0 if self.residual is None else self.residual)
        return {"jump": jump, "normal_traction": normal_traction, "tangential_traction": tangential_traction,
                "state": state, "slip_increment": slip_increment, "closed": closed, "pressure": pressure,
                "aperture": aperture}

    def contact_record(self) -> ContactRecord:
        c = self.contact
        rec = ContactRecord(int(len(self.cm.pairs)), int(len(c.rows)))
        if c.result is not None:
            state, _ = self.pair_states()
            rec.closed = int(np.sum(c.result.active))
            rec.stick, rec.slip = int(np.sum(state == STICK)), int(np.sum(state == SLIP))
            rec.iterations = int(c.result.iterations)
            rec.kkt = c.result.kkt_residuals(c.rows.gap, c.rows.normal)
            rec.fallback = bool(c.result.fallback)
            rec.broken = int(getattr(c.result, "broken", 0))
            rec.loose = int(getattr(c.result, "loose", 0))
            if getattr(c.result, "state", None) is not None:
                rec.friction = c.result.friction_residuals(c.rows.weight)
        return rec

    def release(self) -> None:
        """Free the MUMPS factors now (tens of MB a step)."""
        self.problem.destroy()
        if getattr(self.contact, "saddle", None) is not None:
            self.contact.saddle.destroy()


@dataclass
class Solution(Discretisation):
    """A discretised geometry solved at one load factor, with its tips' SIFs."""
    tips: list = ()


def sif_method(case) -> str:
    """"correlation" or "interaction": which SIFs drive growth."""
    return case.propagation.sif


def driving(tips: list, case) -> list:
    """`tips` (TipSIF) with theta, K_eq and G of the SIFs that drive growth:
    unchanged for displacement correlation; from KI_M, KII_M for the
    interaction integral, where it had room (else correlation's stay)."""
    if sif_method(case) == "correlation" or not tips:
        return tips
    m = case.material
    kap = K.kappa(m.nu, m.plane)
    out = []
    for t in tips:
        if t.KI_M is None:
            out.append(t)
            continue
        KI, KII = np.array([t.KI_M], float), np.array([t.KII_M], float)
        theta = np.atleast_1d(K.mts_angle(KI, KII))
        out.append(replace(t, theta=float(theta[0]), K_eq=float(np.atleast_1d(K.equivalent_k(KI, KII, theta))[0]),
                           G=float(np.atleast_1d(K.energy_release_rate(KI, KII, m.E, m.nu, kap))[0])))
    return out


class MeshRequest:
    """The crack mesh of some fractures, begun (start_mesh) and not yet
    collected: discretise(..., mesh=request) waits for it. Under MPI rank 0
    meshes; collecting is collective (every rank gets the mesh or the error,
    also an error of the start, which is raised there and not before)."""

    def __init__(self, case, fractures, sizes, timeout, patch=None):
        self.polylines = [np.asarray(f.points, float).copy() for f in fractures]
        self.sizes = sizes
        self.patch = patch
        self._pending = RootPending(lambda: mesher.start_crack_mesh(
            case.domain, self.polylines, case.bc_points(), case.mesh.size, case.mesh.tip_size,
            sectors=case.mesh.sectors, sizes=sizes, timeout=timeout,
            patch=None if patch is None else patch.for_mesher()))

    def is_for(self, polylines, sizes, patch=None) -> bool:
        return sizes is self.sizes and patch == self.patch and len(polylines) == len(self.polylines) and \
            all(np.array_equal(a, b) for a, b in zip(polylines, self.polylines))

    def result(self):
        """The CrackMesh (collective)."""
        return self._pending.result()

    def cancel(self) -> None:
        """Abandon it (the meshing worker stops); local."""
        self._pending.cancel()


def start_mesh(case, fractures, sizes=None, timeout: float | None = MESH_TIMEOUT, patch=None) -> MeshRequest:
    """Begin the crack mesh of `fractures` (as discretise would mesh them)
    in the meshing worker and return at once, so that the caller works
    meanwhile (the propagation loop writes the previous step's files);
    discretise(..., mesh=the request) collects it. The time limit runs from
    now. Nothing is raised here: a geometry that cannot be meshed fails
    where the mesh is collected, as the step it belongs to. patch: the
    run's propagation.patch.Patch (None: the whole body meshed freely)."""
    return MeshRequest(case, fractures, sizes, timeout, patch)


def preload() -> None:
    """Import the modules that a step solves with (DOLFINx, the FE layer)
    now, so that a caller can freeze them for the run (gc.freeze) before the
    first step; the propagation loop reaches the FE layer only through here."""
    from .fem import preload as fem_preload

    fem_preload()


def start_meshing(timeout: float | None = MESH_TIMEOUT) -> None:
    """Start the meshing worker (rank 0, when meshing goes to it: a time
    limit), so that its start-up overlaps the caller's (DOLFINx's import,
    the form compilation) instead of the first mesh's wait."""

    if timeout is not None and world_rank() == 0:
        start_worker()


def discretise(case, fractures, timer: Timer, sizes=None, timeout: float | None = MESH_TIMEOUT,
               history=None, mesh: MeshRequest | None = None, patch=None, far=None,
               network=None) -> Discretisation:
    """Mesh `fractures` (anything with .points: case Fracture or
    GrowingFracture) in the case's domain, with the bc points as nodes, in
    the meshing worker under `timeout` seconds; then the DOLFINx mesh, the
    loads, the check for pieces nothing holds, assembly, factorisation (with
    the Schur complement on the contact pair dofs) and the contact rows.
    sizes: the error-estimate size field of the previous step (or None);
    history: the converged slip of the previous step's faces
    (contact.slip_history.SlipHistory), carried to this mesh's Coulomb pairs
    by arc length as the reference of the first increment (None: no slip);
    mesh: the mesh of these fractures and sizes begun by start_mesh (None:
    begun here); patch: the run's propagation.patch.Patch for the mesh;
    far: the far field factorised at an earlier step of this patch
    (fem.far_field.FarField): reused when this mesh's far field is its, else
    (and when there is none) a new one is factorised where the mesh has a
    far field; the one used is Discretisation.far (the caller's to destroy
    when it changes); network: with load = "injection", (n_fractures,) bool,
    the injected network (its pressure is the load factor; default: the
    injected fracture and those it meets, as at the start)."""
    polylines = [np.asarray(f.points, float) for f in fractures]
    if case.propagation.load == "injection" and network is None:
        network = case.network_at_start()
    if mesh is None:   # begun before the imports below, which then overlap gmsh
        mesh = start_mesh(case, fractures, sizes, timeout, patch)
    elif not mesh.is_for(polylines, sizes, patch):
        mesh.cancel()
        raise RuntimeError("the mesh begun for this step is of other fractures or sizes (a bug in the caller)")
    try:
        from .fem.contact_problem import ContactProblem
        from .fem.elasticity import ElasticProblem
        from .fem.far_field import FarField
        from .fem.mesh import to_dolfinx
        from .fem.pair_operator import PairOperator
    except BaseException:   # Ctrl-C during the imports: the mesh is not collected
        mesh.cancel()
        raise

    progress.doing("meshing")
    cm = mesh.result()
    timer.lap("mesh")
    fm = to_dolfinx(cm)
    timer.lap("to_dolfinx")
    m = case.material
    loads = case_loads(case, cm, fractures, network)
    rows = constraint_rows(cm, fractures)
    floating = floating_pieces(cm, loads, rows, free_pieces(cm, loads))
    saddle = len(rows) > DENSE_ROWS
    if saddle and floating is not None:
        raise ComputationError(f"pieces that only contact holds in a pair system of {len(rows)} rows: their rigid "
                               f"modes need the dense pair problem, which holds at most {DENSE_ROWS} rows")
    timer.lap("assemble")
    if far is not None and (floating is not None or saddle or not far.matches(cm)):
        far = None   # the patch moved on, or a gauge changed its supports (the caller destroys the old one)
    timer.lap("patch")
    # with the far field kept, K is assembled where the reduced factorisation reads it only
    problem = ElasticProblem(fm, m.E, m.nu, m.plane, loads, cm=cm,
                             far_interior=None if far is None else far.interior_of(cm))
    timer.lap("assemble")
    started = False
    if far is None and cm.far is not None and floating is None and not saddle:
        far = FarField.start(problem, cm)
        started = far is not None
    timer.lap("patch")
    if not saddle:   # the saddle-point route factorises K with the contact rows, K alone never
        progress.doing(f"factorising the stiffness ({fm.num_dofs} DOFs, {len(rows)} pair rows)")
        problem.factorize(schur_dofs=PairOperator.pair_dofs(fm, rows) if len(rows) else None, far=far)
    timer.lap("factorize")
    if far is not None and not problem.reused_far:   # other supports in the far field: factorised whole
        if started:
            far.destroy()
        far = None
    cm.stats["far_field"] = None if far is None else ("factorised" if started else "reused")
    contact = ContactProblem(problem, rows, floating, saddle=saddle)
    if history is not None and contact.has_friction:
        contact.set_reference(history.at(cm, fractures))
    timer.lap("contact")
    residual = None
    if case.injection is not None and case.injection.residual_aperture:
        residual = case.injection.residual_aperture * pre_existing_pairs(cm, fractures)
    return Discretisation(cm, problem, contact, np.array([float(f.law.pressure) for f in fractures]), far,
                          network=None if network is None else np.asarray(network, bool), residual=residual)


def floating_pieces(cm, loads, rows, pieces):
    """The pieces that no displacement condition holds (free_pieces), to be
    held by contact (wingcrack.floating, its gauge set in `loads`); None
    when there are none. ComputationError where a piece's faces carry no
    contact row (open faces): nothing can hold it."""
    if not pieces:
        return None

    faces = np.zeros(len(cm.x), bool)
    faces[np.r_[rows.plus, rows.minus].astype(np.int64)] = True
    bare = [p for p in pieces if not faces[p.nodes].any()]
    if bare:
        raise ComputationError("the stiffness matrix is singular: a fracture cuts off a piece of the body that "
                               f"no displacement condition holds and no contact either ({describe(bare)}; its faces "
                               "are open)")
    floating = Floating.of(cm, pieces, np.asarray(cm.pairs, np.int64).reshape(-1, 2))
    loads.gauge = list(floating.gauge)
    return floating


def solve_initial(case, timer: Timer | None = None, load_factor: float = 1.0,
                  timeout: float | None = MESH_TIMEOUT) -> Solution:
    """The case's initial geometry discretised, solved at `load_factor`
    (with contact) and its SIFs: what `sif` computes."""
    timer = timer or Timer()
    progress.step_started(0)
    try:
        d = discretise(case, case.fractures, timer, timeout=timeout)
        progress.doing(f"the solve at load factor {load_factor:.6g}")
        d.solve(load_factor)
        timer.lap("solve")
        progress.doing("the stress intensity factors")
        tips = d.sifs(case, [f.points for f in case.fractures])
        timer.lap("sif")
    finally:
        progress.step_ended()
    return Solution(d.cm, d.problem, d.contact, d.pressures, tips=tips)


def static_states(tips, KIc) -> list:
    """In a static solve a tip is "growing" when it has reached the toughness."""
    return ["growing" if KIc is not None and t.K_eq >= KIc * (1 - STATIC_RTOL) else "arrested" for t in tips]


def sif_scale(tips, KIc=None) -> float:
    """The K scale of a step's tips (Pa m^0.5): the larger of KIc (None:
    the case has none) and the largest interaction-integral K =
    sqrt(KI_M^2 + KII_M^2) of the tips that have one."""
    ks = [float(np.hypot(t.KI_M, t.KII_M)) for t in tips if t.KI_M is not None and t.KII_M is not None]
    return max(ks + [float(KIc or 0.0)])


def sif_warnings(tips, KIc=None) -> list:
    """One line for each of a step's `tips` where displacement correlation
    (KI, KII) and the interaction integral (KI_M, KII_M, the reference: it
    integrates the whole field around the tip, where correlation reads four
    nodes next to it) differ by more than SIF_AGREEMENT of the tip's K =
    sqrt(KI_M^2 + KII_M^2) and of SIF_FLOOR * sif_scale(tips, KIc): the
    disagreement at a tip whose K is far below the K that drives growth
    (KIc, the case's; None: the step's largest K alone) is no news."""
    out = []
    floor = SIF_FLOOR * sif_scale(tips, KIc)
    for t in tips:
        if t.KI_M is None or t.KII_M is None:
            continue
        k = float(np.hypot(t.KI_M, t.KII_M))
        off = max(abs(t.KI - t.KI_M), abs(t.KII - t.KII_M))
        if k > 0 and off > SIF_AGREEMENT * max(k, floor):
            out.append(f"fracture {t.fracture} end {t.end}: displacement correlation KI {t.KI:.6g}, KII {t.KII:.6g} "
                       f"and the interaction integral KI_M {t.KI_M:.6g}, KII_M {t.KII_M:.6g} Pa m^0.5 differ by "
                       f"{100 * off / k:.3g} % of K")
    return out


def finish(out, k: int, load_factor: float, disc: Discretisation, tips: list, timer: Timer, solves: int = 1,
           states=None, advances=None, KIc=None, times=None) -> StepRecord:
    """The record of solved step k (tip states and advances when it grew;
    "arrested" and 0 otherwise), its files written when there is an output
    folder `out`; the fractures' pressures at `load_factor`
    (Discretisation.pressure_at); its SIF warnings against the case's KIc
    (sif_warnings). times: the physical times of steps 0..k (s), or None."""
    if out is not None:
        write_step_files(out, k, load_factor, disc, times)
        timer.lap("output")
    states = states or ["arrested"] * len(tips)
    advances = advances or [0.0] * len(tips)
    seconds = {name: round(v, 6) for name, v in timer.seconds.items()}
    seconds["total"] = round(sum(timer.seconds.values()), 6)
    pressures = [float(p) for p in disc.pressure_at(load_factor)]
    return StepRecord(k, load_factor, disc.dofs, disc.cells,
                      [TipRecord.of(t, s, a) for t, s, a in zip(tips, states, advances)],
                      disc.contact_record(), seconds, {n: disc.cm.stats[n] for n in MESH_STATS}, solves,
                      sif_warnings(tips, KIc), pressures)


def require_finite(what: str, values) -> None:
    """ComputationError when a value of the solution is NaN or inf (a case
    whose magnitudes floating point cannot hold): said at once, instead of
    growth on NaN or a summary that cannot be written."""
    bad = [v for v in np.atleast_1d(np.asarray(values, float)) if not np.isfinite(v)]
    if bad:
        raise ComputationError(f"the solution is not finite ({what} is {bad[0]:g}): the magnitudes of the case "
                               "are beyond floating point")


def write_step_files(out, k: int, load_factor: float, disc: Discretisation, times=None) -> None:
    """step_XXXX.vtu and faces_XXXX.vtu of step k (with the step and its
    load factor as field data, and its time where `times`, the times of
    steps 0..k, are given: then the ParaView indices' time axis), and the
    two ParaView indices over steps 0..k, rewritten so that an interrupted
    run keeps a complete index.
    Collective: the values are gathered first, then rank 0 writes, and a
    file it cannot write (WriteError) is raised on every rank (parallel.on_root:
    otherwise the others would wait for rank 0 in the next step)."""

    out = Path(out)
    about = {"step": k, "load_factor": load_factor}
    axis = None if times is None else increasing(times)
    if times is not None:
        about["time"] = float(times[k])
    fields = disc.problem.nodal_fields(len(disc.cm.x), [t.node for t in disc.cm.tips])   # on rank 0
    faces = disc.face_values()

    def write():
        write_field_arrays(out / fields_name(k), disc.cm, fields, field_data=about)
        write_faces(out / faces_name(k), disc.cm, faces, field_data=about)
        write_pvd(out / FIELDS_PVD, [fields_name(j) for j in range(k + 1)], axis)
        write_pvd(out / FACES_PVD, [faces_name(j) for j in range(k + 1)], axis)

    on_root(write)


def files_of(out, n: int) -> dict:
    """{name: path} of the data files of a result of n steps in `out`
    (span names such as step_{0000..0014}.vtu; the pictures are added by
    api)."""

    def span(name):
        return name(0) if n == 1 else name(0).replace("0000", f"{{0000..{n - 1:04d}}}")

    out = Path(out)
    files = {"summary": out / SUMMARY}
    if n:   # one field file and one face file per step, and their indices
        files.update(fields=out / span(fields_name), faces=out / span(faces_name),
                     fields_pvd=out / FIELDS_PVD, faces_pvd=out / FACES_PVD)
    return files


def failure(k: int, err: BaseException) -> str:
    """The status of a computation that failed at step k; of one whose
    output could not be written (WriteError), "failed: cannot write <file>:
    <reason>" (the file says which step; the folder is at fault, not the
    step)."""
    if isinstance(err, WriteError):
        return f"failed: {err}"
    return f"failed: step {k}: {' '.join(str(err).split()) or type(err).__name__}"


def summary(case, status: str, steps: list, fractures: list, warnings=(), run: bool = False) -> Summary:
    """The summary of a result: `steps` (StepRecord), `fractures` the pieces
    [{points, origin, fracture}] of the last finished geometry, warnings
    about the whole result; one line more when the SIF methods disagreed.
    A run's (`run`) says how far it may grow (propagation_asked)."""
    return Summary(case.title, __version__, status, list(steps), fractures,
                   result_warnings(steps, sif_method(case)) + list(warnings), KIc=case.material.KIc,
                   propagation=propagation_asked(case) if run else None)


def propagation_asked(case) -> dict:
    """summary.json's "propagation" of a run of `case`: the steps asked and
    the longest advance of a step (m), so no tip moves farther than their
    product (the growth animation's view is chosen from it at the first step);
    with a pump its schedule (times and rates, s and m^3/s per m; end_time),
    which history.png's breakdown curve follows between the states solved."""
    asked = {"steps": int(case.propagation.steps), "length": float(case.propagation.length)}
    if case.propagation.load == "injection":
        asked["schedule"] = Schedule.of(case.injection).to_dict()
    return asked


def result_warnings(steps: list, method: str = "correlation") -> list:
    """The warnings of a whole result from its steps' own (one line, however
    many steps and tips)."""
    flagged = [(s.step, w) for s in steps for w in s.warnings]   # a step's warnings are sif_warnings
    if not flagged:
        return []
    steps_hit = sorted({k for k, _ in flagged})
    first_step, first = flagged[0]
    where = f"step {first_step}" if len(steps_hit) == 1 else f"{len(steps_hit)} steps (first: step {first_step})"
    driver = ("growth is driven by displacement correlation (propagation.sif = \"interaction\" uses the other)"
              if method == "correlation" else "growth is driven by the interaction integral")
    return [f"the two SIF methods differ by more than {100 * SIF_AGREEMENT:g} % of K (and "
            f"{100 * SIF_AGREEMENT * SIF_FLOOR:g} % of the larger of KIc and the step's largest K) at {len(flagged)} "
            f"tip(s) in {where}: {first}; {driver}; see the steps' warnings in summary.json"]
