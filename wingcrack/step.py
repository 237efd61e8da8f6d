"""One step of wingcrack, the same for `sif` (step 0, at load factor 1) and
for every step of `run` (the paper's Fig. 8 loop, propagation/loop.py).
Its stages, in order, each a function of records:

    fractures (polylines), what the steps before carried (Carried)
      1. mesh         start_mesh -> the crack mesh, made in the meshing
                      worker under a time limit (mesh_request.py)
      2. FE problem   the DOLFINx mesh, the loads, the contact rows, the
                      pieces only contact holds
      3. contact      the problem factorised with its contact problem
                      (solver.py: how it factorises is the solver's own),
                      the reference slip carried on; the fluid's view of
                      the fractures (fracture_fluid.py)   = Discretisation
      4. solve        disc.solver.solve(load factor): elasticity + the
                      active set on the faces
      5. SIFs         sifs.at_tips: both methods at every tip   = [TipSIF]
      6. records      finish: the step's files (step_files.py) and its
                      record (face_values.py, sif_agreement.py)
                                                        = results.StepRecord

solve_initial runs them all once: what `sif` computes. A computation that
fails raises one of FAILURES; failure() turns it into the status
"failed: step <k>: <reason>", the same for both commands.
"""
from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from . import progress, sifs
from .contact.constraints import constraint_rows
from .errors import ComputationError, WriteError
from .face_values import contact_record
from .floating import Floating
from .fracture_fluid import FractureFluid
from .free_pieces import describe, free_pieces
from .loads import case_loads
from .mesh_request import MESH_TIMEOUT, MeshRequest, start_mesh
from .results import MESH_STATS, StepRecord, Summary, TipRecord
from .schedule import Schedule
from .sif_agreement import result_warnings, sif_warnings
from .step_files import files_of, write_step_files
from .version import __version__

#: the stages and their records, with what the callers take from here (the mesh request, the files)
__all__ = ["FAILURES", "MESH_TIMEOUT", "Carried", "Discretisation", "MeshRequest", "Solution", "Timer",
           "discretise", "failure", "files_of", "finish", "floating_pieces", "propagation_asked", "solve_initial",
           "start_mesh", "static_states", "summary"]

#: a tip "reached" KIc in a static solve (sif): K_eq >= KIc (1 - this)
STATIC_RTOL = 1e-9
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
class Carried:
    """What a step takes from the steps before it (all None at the first):
    for its mesh, sizes (the error-estimate size field of the last step)
    and patch (the run's propagation.patch.Patch, the circle remeshed);
    for its solve, history (the converged slip of the last step's faces,
    contact.slip_history.SlipHistory, carried to this mesh's Coulomb pairs
    by arc length as the reference of the first increment) and far (the
    far field factorised at an earlier step, fem.far_field.FarField:
    reused while the mesh's far field is its own; discretise keeps the one
    its step used here and destroys the one it replaced)."""
    sizes: object = None
    patch: object = None
    history: object = None
    far: object = None

    def keep_far(self, far) -> None:
        if far is not self.far and self.far is not None:
            self.far.destroy()   # the patch moved on: its far field is another
        self.far = far


@dataclass
class Discretisation:
    """A geometry made ready to solve: cm, the crack mesh (meshing.CrackMesh:
    nodes, P2 cells, face pairs, tips with their rosette nodes); solver, the
    elastic problem factorised with its contact problem (solver.Solver:
    solve, solution_at, accept, release); fluid, the fractures' pressures
    and openings (fracture_fluid.FractureFluid)."""
    cm: object
    solver: object
    fluid: FractureFluid

    @property
    def problem(self):
        """The elastic problem (fem.elasticity.ElasticProblem: mesh, u)."""
        return self.solver.problem

    @property
    def contact(self):
        """The contact problem (fem.contact_problem.ContactProblem: rows, result)."""
        return self.solver.contact

    def coupled_faces(self, net):
        """The faces as the flow along the fractures on the network `net`
        (flow.network.FlowNetwork of cm) sees them: the contact and friction
        solved on the faces at a pressure field (fem.coupled_faces)."""
        from .fem.coupled_faces import CoupledFaces   # the FE layer: a flowing run's, loaded by its first step

        return CoupledFaces(self, net)

    @property
    def dofs(self) -> int:
        return int(self.problem.fm.num_dofs)

    @property
    def cells(self) -> int:
        return int(self.problem.fm.num_cells)


@dataclass
class Solution(Discretisation):
    """A discretised geometry solved at one load factor, with its tips' SIFs."""
    tips: list = ()


def discretise(case, fractures, timer: Timer, carried: Carried | None = None, mesh: MeshRequest | None = None,
               network=None) -> Discretisation:
    """Stages 1-3 for `fractures` (anything with .points and .law: case
    Fracture or GrowingFracture) in the case's domain: the crack mesh, the
    FE problem, factorised, with its contact. carried: what the steps before
    carried (None: nothing); mesh: the mesh of these fractures and sizes
    begun by start_mesh (None: begun here, under MESH_TIMEOUT); network:
    with load = "injection", (n_fractures,) bool, the injected network (its
    pressure is the load factor; default: the injected fracture and those
    it meets, as at the start)."""
    carried = carried or Carried()
    if case.propagation.load == "injection" and network is None:
        network = case.network_at_start()
    polylines = [np.asarray(f.points, float) for f in fractures]
    if mesh is None:
        mesh = start_mesh(case, fractures, sizes=carried.sizes, patch=carried.patch)
    elif not mesh.is_for(polylines, carried.sizes, carried.patch):
        mesh.cancel()
        raise RuntimeError("the mesh begun for this step is of other fractures or sizes (a bug in the caller)")
    try:
        from . import solver   # overlap: DOLFINx's import while gmsh meshes (startup.py)
        from .fem.mesh import to_dolfinx   # overlap: as above
    except BaseException:   # Ctrl-C during the imports: the mesh is not collected
        mesh.cancel()
        raise

    # 1. mesh
    progress.doing("meshing")
    cm = mesh.result()
    timer.lap("mesh")
    # 2. the FE problem's records
    fm = to_dolfinx(cm)
    timer.lap("to_dolfinx")
    loads = case_loads(case, cm, fractures, network)
    rows = constraint_rows(cm, fractures)
    floating = floating_pieces(cm, loads, rows, free_pieces(cm, loads))
    # 3. factorised, with contact
    factorised = solver.Solver.factorised(fm, cm, case.material, loads, rows, floating, carried.far, timer)
    if carried.history is not None and factorised.contact.has_friction:
        factorised.contact.set_reference(carried.history.at(cm, fractures))
    timer.lap("contact")
    carried.keep_far(factorised.far)
    return Discretisation(cm, factorised, FractureFluid.of(case, cm, factorised.problem, fractures, network))


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
    """The case's initial geometry through stages 1-5: discretised, solved
    at `load_factor` (with contact) and its SIFs: what `sif` computes."""
    timer = timer or Timer()
    progress.step_started(0)
    try:
        d = discretise(case, case.fractures, timer, mesh=start_mesh(case, case.fractures, timeout=timeout))
        progress.doing(f"the solve at load factor {load_factor:.6g}")
        d.solver.solve(load_factor)
        timer.lap("solve")
        progress.doing("the stress intensity factors")
        tips = sifs.at_tips(case, d, [f.points for f in case.fractures])
        timer.lap("sif")
    finally:
        progress.step_ended()
    return Solution(d.cm, d.solver, d.fluid, tips=tips)


def static_states(tips, KIc) -> list:
    """In a static solve a tip is "growing" when it has reached the toughness."""
    return ["growing" if KIc is not None and t.K_eq >= KIc * (1 - STATIC_RTOL) else "arrested" for t in tips]


def finish(out, k: int, load_factor: float, disc: Discretisation, tips: list, timer: Timer, solves: int = 1,
           states=None, advances=None, KIc=None, times=None) -> StepRecord:
    """Stage 6: the record of solved step k (tip states and advances when
    it grew; "arrested" and 0 otherwise), its files written when there is
    an output folder `out`; the fractures' pressures at `load_factor`
    (FractureFluid.pressures); its SIF warnings against the case's KIc
    (sif_warnings). times: the physical times of steps 0..k (s), or None."""
    if out is not None:
        write_step_files(out, k, load_factor, disc, times)
        timer.lap("output")
    states = states or ["arrested"] * len(tips)
    advances = advances or [0.0] * len(tips)
    seconds = {name: round(v, 6) for name, v in timer.seconds.items()}
    seconds["total"] = round(sum(timer.seconds.values()), 6)
    pressures = [float(p) for p in disc.fluid.pressures(load_factor)]
    return StepRecord(k, load_factor, disc.dofs, disc.cells,
                      [TipRecord.of(t, s, a) for t, s, a in zip(tips, states, advances)],
                      contact_record(disc), seconds, {n: disc.cm.stats[n] for n in MESH_STATS}, solves,
                      sif_warnings(tips, KIc), pressures)


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
                   result_warnings(steps, sifs.method(case)) + list(warnings), KIc=case.material.KIc,
                   propagation=propagation_asked(case) if run else None)


def propagation_asked(case) -> dict:
    """summary.json's "propagation" of a run of `case`: the steps asked and
    the longest advance of a step (m), so no tip moves farther than their
    product (the growth animation's view is chosen from it at the first step);
    with a pump its schedule (times and rates, s and m^3/s per m; end_time),
    which history.png's breakdown curve follows between the states solved."""
    asked = {"steps": int(case.propagation.steps), "length": float(case.propagation.length)}
    if case.propagation.load == "injection" and case.injection.pressure is None:   # (not a pressure held)
        asked["schedule"] = Schedule.of(case.injection).to_dict()
    return asked
