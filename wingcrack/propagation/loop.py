"""The propagation loop (paper Fig. 8), one step at a time:

    discretise the current fractures (wingcrack.step: mesh, FE problem,
    factorised with its contact problem)
    -> the step's load factor (loading.py: the critical load factor, at
       which the first tip reaches KIc; a pump's critical pressure,
       pumped.py; or the fixed load)
    -> solve + SIFs (wingcrack.step)
    -> growth (growth: MTS direction, Paris-type lengths, the L_min rule,
       joining other fractures and the boundary)
    -> the next mesh's sizes (the error estimate)
    -> the next step's mesh begun in the meshing worker, while this step's
       files, summary.json and the checkpoint are written -> next step.

summary.json is rewritten after every step; a failure keeps every finished
step and says "failed: <reason>". A step in which no tip moves ends the run
("stopped: no tip can grow (...)"): the next step would be the same. A run
whose every tip has joined another fracture or reached the boundary has
completed its growth and is "finished" before propagation.steps; a case
with no tip that may grow at all stops with NO_TIP_AT_ALL, and
propagation.steps = 0 with NO_STEPS (a run that did nothing is never
"finished").
"""
from __future__ import annotations

import contextlib
import gc
from dataclasses import dataclass, field
from pathlib import Path

from .. import interrupt, sifs, startup, step
from .. import progress as progress_now
from ..contact.slip_history import SlipHistory
from ..errors import Collapse, ComputationError, WriteError
from ..face_values import pair_slips
from ..io.summary import SummaryWriter
from ..parallel import on_root, on_world_root
from ..results import LastSolve, StepRecord, dataframe, tip_rows
from . import checkpoint, growth
from .flowing import Flowing
from .fracture_set import FractureSet
from .loading import SEARCHED, Fixed, Searched
from .patch import next_patch
from .pumped import Pumped

#: no fracture of the case has a free tip that may grow (every end a mouth, or grow = false)
NO_TIP_AT_ALL = "stopped: no tip can grow (no fracture has a free tip that may grow)"
#: propagation.steps = 0: no step was asked for (a run that did nothing is not "finished")
NO_STEPS = "stopped: propagation.steps = 0 (no step asked for; `wingcrack sif` solves the initial geometry)"


def no_tip_left(records) -> str:
    """The status of a run in which no free tip that may grow is left: the
    growth is complete ("finished") when steps were done (every tip joined or
    reached the boundary), else nothing could ever grow."""
    return "finished" if records else NO_TIP_AT_ALL


def loading_of(case):
    """The loading of propagation.load (loading.py)."""
    load = case.propagation.load
    if load == "injection":
        return Flowing(case) if case.injection.viscosity is not None else Pumped(case)
    return Searched(case) if load in SEARCHED else Fixed(case)


@dataclass
class RunResult(LastSolve):
    """A propagation run: status, steps (dicts as in summary.json), the final
    fracture set, and the last step's crack mesh, problem and contact.
    .tips, .polylines, .to_dataframe(), .dolfinx_mesh, .displacement. mesh,
    problem, contact, .dolfinx_mesh and .displacement are None when the run
    ended on a geometry it did not record (stopped on the load factor limit:
    the search's trial solve is no step)."""
    status: str
    steps: list
    fractures: FractureSet
    summary: dict
    out: Path | None = None
    files: dict = field(default_factory=dict)
    mesh: object = None
    problem: object = None
    contact: object = None

    @property
    def tips(self) -> list:
        """The last step's tips (dicts as in summary.json)."""
        return self.steps[-1]["tips"] if self.steps else []

    @property
    def polylines(self) -> list:
        """Every fracture's polyline (n, 2) at the end, wings included."""
        return [f.points.copy() for f in self.fractures.fractures]

    def to_dataframe(self):
        """One row per step and tip (pandas; see results.tip_rows for plain dicts)."""
        return dataframe(tip_rows(self.steps))


def run(case, out=None, progress=None, mesh_timeout: float | None = step.MESH_TIMEOUT,
        resume: bool = False, finishing=None, committed=None) -> RunResult:
    """Grow the case's fractures; see the module doc. `progress(step, info)`
    is called after every step (the CLI's progress bar). With `resume`, go
    on from the checkpoint in `out` (see checkpoint.py). `finishing(summary)`
    is called with the final summary (a dict) after the last step and before
    summary.json says the final status, and returns warnings (strings) to
    add to it: api.run draws the pictures there, so that a finished result
    has them. Ctrl-C (SIGINT) stops at once with status "stopped:
    interrupted", every finished step kept, and raises KeyboardInterrupt
    again; SIGTERM the same with "stopped: terminated". `committed(k,
    record)` is called with every step committed to the folder and its
    record (a dict as in summary.json), resumed ones first: api.run has the
    animation's frames drawn there as the run goes."""
    startup.start_processes(mesh_timeout)   # its start-up overlaps the imports of startup.solving_modules()
    with interrupt.watching(), _Run(case, out, mesh_timeout) as run:
        return _run(run, progress, resume, finishing, committed)


def _run(run, progress, resume, finishing, committed) -> RunResult:
    """Fig. 8, step after step, with the ends of a run: a stop (the status a
    step returns), a collapse of the body (the end of its loading path), a
    failure (every finished step kept), an interrupt (kept and resumable)."""
    if resume:
        run.resume()
        for record in run.records:
            run.tell(committed, record)
    run.begin()
    steps = run.prop.steps
    status = NO_STEPS if not run.records and run.k >= steps else "finished"
    for k in range(run.k, steps):
        run.k = k
        try:
            stop = run.step(k)
        except KeyboardInterrupt as err:   # Ctrl-C or SIGTERM
            raise run.stopped(err)
        except Collapse as err:   # the body cannot carry the load: the end of its loading path, not a failure
            run.uncommitted(k)
            status = f"stopped: step {k}: the body cannot carry the load: {err}"
            break
        except Exception as err:
            raise run.failure(err)
        if stop is not None:
            status = stop
            break
        run.tell(committed, run.last)
        run.report(progress, k)
    run.finish(status, finishing)
    return run.result(status)


class _Run:
    """What a run carries from step to step: the fractures, the loading
    (its load factor; a pump), the records, what the next mesh and solve
    reuse (step.Carried: the sizes of the error estimate, the patch and its
    far field, the converged slip) and the next step's mesh once begun. As
    a context: at its end a mesh begun and never collected is abandoned
    (the meshing worker stops: no answer is left unread), and the FE
    modules are unfrozen."""

    def __init__(self, case, out, mesh_timeout):
        self.case, self.prop = case, case.propagation
        self.out = None if out is None else Path(out)   # made ready by api.run
        self.mesh_timeout = mesh_timeout
        self.fset = FractureSet.from_case(case)
        self.rule = growth.Rule.of(case)
        self.loading = loading_of(case)
        self.carried = step.Carried()
        self.next_mesh = None   # the next step's step.MeshRequest, begun during this step
        self.frozen = contextlib.ExitStack()   # the FE modules frozen for the run (startup.solving_modules)
        self.records = []
        self.disc = None
        self.kept = False   # the last step was a frame: the next goes on on its discretisation
        self.shown = None   # the discretisation of the last recorded step, while it is not released
        self.k = 0            # the step under way (the first one to do, before the loop)
        self.warnings = []    # about the whole run (from `finishing`)
        self.writes = self.out is not None and on_world_root()
        self.summary_file = SummaryWriter(self.out / "summary.json") if self.writes else None
        self.checkpoints = checkpoint.Writer(self.out, case) if self.writes else None
        self.last = None      # the record of the last committed step

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.frozen.close()
        if self.next_mesh is not None:
            self.next_mesh.cancel()
            self.next_mesh = None
        return False

    def resume(self):
        if self.out is None:
            raise ValueError("resume needs the output folder of the run")
        ck = checkpoint.load(self.out, self.case)
        self.fset, self.loading.lam, self.k = ck["fset"], ck["load_factor"], ck["step"] + 1
        self.carried = step.Carried(sizes=ck["sizes"], patch=ck["patch"], history=ck["history"])
        self.records = [StepRecord.from_dict(s) for s in ck["steps"]]
        self.loading.restore(ck["pump"])

    def begin(self):
        """The first step's mesh is begun before DOLFINx is imported: its gmsh
        overlaps the imports (startup.py)."""
        if self.k < self.prop.steps and (self.fset.active_tips() or self.loading.timed):
            self.request_mesh()
            self.frozen.enter_context(startup.solving_modules())   # a run of no step imports no DOLFINx
        self.done = self.fset.copy()   # the fractures after the last finished step

    def request_mesh(self):
        c = self.carried
        c.patch = next_patch(c.patch, self.case, self.fset)
        self.next_mesh = step.start_mesh(self.case, self.fset.fractures, sizes=c.sizes, timeout=self.mesh_timeout,
                                         patch=c.patch)

    def step(self, k):
        """Step k: mesh, FE problem and contact; the load factor; solve and
        SIFs; growth; the next mesh begun; the step committed. Returns the
        status the run stops with, or None where the fractures grew."""
        timer = step.Timer()
        progress_now.step_started(k)
        interrupt.check()
        timed = self.loading.timed   # a flowing run goes on in time, growing or not
        if not self.fset.active_tips() and not timed:
            return no_tip_left(self.records)
        disc = self.discretise(timer)
        interrupt.check()
        grow = growth.may_grow(disc.cm, self.fset)
        if not grow and not timed:
            return no_tip_left(self.records)
        found = self.loading.find(disc, self.fset, grow)
        if found.stop is not None:   # the loading stops the run below KIc: the step solved there is a result too
            tips = self.tips_of(disc, timer)
            self.record(self.finished(k, found.load_factor, disc, tips, timer, solves=found.solves,
                                      fluid=self.loading.fluid(disc, self.fset)), disc)
            return found.stop(tips)
        progress_now.doing(f"the solve at load factor {found.load_factor:.6g}")
        disc.solver.solution_at(found.load_factor)   # the search's last trial is often at it
        tips = self.tips_of(disc, timer)
        # the converged slip along the fractures as meshed (before they grow): the next mesh's reference
        converged = _slip_history(disc, self.fset)
        fluid = self.loading.fluid(disc, self.fset)   # a pump's, before growth: on the step's geometry
        if found.frame:   # a state in time on this geometry: recorded, and the next step goes on from it
            record = self.finished(k, found.load_factor, disc, tips, timer, solves=found.solves, fluid=fluid)
            self.commit(k, record, disc, converged, fluid)
            self.kept = True
            return None
        candidates = growth.candidates(tips, disc.cm, grow)
        if self.loading.unreached and not growth.reached(candidates, self.rule).any():
            # the solved step is a result too: recorded with its files, no growth
            self.record(self.finished(k, found.load_factor, disc, tips, timer, solves=found.solves), disc)
            return self.loading.unreached
        progress_now.doing("growth, the step's files and the next mesh")
        grown = growth.grow(self.fset, candidates, len(tips), self.rule, self.case.domain)
        timer.lap("growth")
        interrupt.check()
        if not grown.grew:
            # nothing moved: the next step would be this one again. Recorded (not
            # checkpointed: a resumed run solves it again and stops the same way)
            self.record(self.finished(k, found.load_factor, disc, tips, timer, solves=found.solves, fluid=fluid),
                        disc)
            return f"stopped: no tip can grow ({grown.why_none()})"
        self.prepare_next(k, disc, timer)
        record = self.finished(k, found.load_factor, disc, tips, timer, solves=found.solves, fluid=fluid,
                               states=[t.state for t in grown.tips], advances=[t.advance for t in grown.tips])
        record.critical_load_factor = self.loading.critical(tips, grow)
        self.commit(k, record, disc, converged, fluid)
        return None

    def discretise(self, timer):
        """This step's discretisation, the last one's factors released first
        (the last one itself where it was a frame: the same geometry)."""
        if self.kept:
            self.kept = False
            return self.disc
        _release(self.disc)   # the previous step's factors and forms
        self.disc = self.shown = None
        mesh, self.next_mesh = self.next_mesh, None
        self.disc = step.discretise(self.case, self.fset.fractures, timer, carried=self.carried, mesh=mesh,
                                    network=self.loading.mask(len(self.fset.fractures)))
        return self.disc

    def tips_of(self, disc, timer) -> list:
        """The SIFs of disc's current solution (the step's solve lapped first)."""
        timer.lap("solve")
        interrupt.check()
        progress_now.doing("the stress intensity factors")
        tips = sifs.at_tips(self.case, disc, self.fset.polylines())
        timer.lap("sif")
        return tips

    def prepare_next(self, k, disc, timer):
        """The next step's mesh sizes (the error estimate, mesh.adaptive) and
        its mesh begun: made while step k is written; it fails (if it does)
        as step k+1."""
        if self.case.mesh.adaptive:
            from ..adaptivity import next_sizes   # DOLFINx: imported by startup.solving_modules() before

            self.carried.sizes = next_sizes(disc.problem, self.case.mesh.tip_size, self.case.mesh.size)
            timer.lap("estimate")
        if k + 1 < self.prop.steps and self.fset.active_tips():
            self.request_mesh()
            timer.lap("mesh")

    def finished(self, k, lam, disc, tips, timer, fluid=None, **more):
        """Step k's record, its files written; with a pump (fluid:
        pumped.FluidState) its time, injection and networks, the time the
        PVD's axis."""
        if fluid is None:
            return step.finish(self.out, k, lam, disc, tips, timer, KIc=self.case.material.KIc, **more)
        pumped = fluid.record()
        times = [r.time for r in self.records] + [pumped["time"]]
        record = step.finish(self.out, k, lam, disc, tips, timer, KIc=self.case.material.KIc, times=times, **more)
        record.time, record.injection, record.networks = pumped["time"], pumped["injection"], pumped["networks"]
        return record

    def record(self, record, disc):
        self.records.append(record)
        self.shown = disc

    def commit(self, k, record, disc, converged, fluid=None):
        """Step k committed whole: its record, the fractures grown, summary.json
        and the checkpoint agree (an interrupt waits until they do). The
        loading moves on (a pump: its time and pressure are the run's, and
        the fractures joined enter the network)."""
        with interrupt.deferred():
            self.record(record, disc)
            self.loading.commit(fluid, self.done.fractures, self.fset)
            if self.prop.connect_pressure:   # the next step meshes and loads with the connected pressures
                self.fset.connect_pressures(exclude=self.loading.network)
            self.done = self.fset.copy()
            self.carried.history = converged
            self.last = record

            def save():
                if self.writes:
                    c = self.carried
                    self.write("running")
                    self.checkpoints.save(k, self.fset, self.loading.lam, self.records, c.sizes, c.history, c.patch,
                                          pump=self.loading.state())

            on_root(save)   # a file rank 0 cannot write fails the step on every rank

    def uncommitted(self, k):
        """Step k did not finish: a record it appended goes (its commit failed)."""
        if self.records and self.records[-1].step == k:
            self.records.pop()

    def tell(self, committed, record):
        """committed(k, the record as a dict) of a step committed (see run)."""
        if committed is None:
            return
        try:
            committed(record.step, record.to_dict())
        except KeyboardInterrupt as err:
            raise self.stopped(err)

    def report(self, progress, k):
        """The caller's code, after step k is committed: its own exception goes
        up unchanged (not a failure of the computation, and step k stays in
        summary.json and the checkpoint)."""
        if progress is None:
            return
        try:
            progress(k, self.last.to_dict())
        except KeyboardInterrupt as err:
            raise self.stopped(err)

    def summary_now(self, st) -> dict:
        return step.summary(self.case, st, self.records, self.done.summary(), self.warnings, run=True).to_dict()

    def write(self, st):
        if self.writes:
            self.summary_file.write(step.summary(self.case, st, self.records, self.done.summary(), self.warnings,
                                                 run=True))

    def write_last(self, st) -> str:
        """Write the run's last status `st`: "", or what the news of the run's
        end adds when summary.json cannot be written (it says "running")."""
        try:
            self.write(st)
        except WriteError as err:
            return f" (summary.json not updated: {err.reason})"
        return ""

    def stopped(self, err: KeyboardInterrupt) -> KeyboardInterrupt:
        """The interrupt, its stop written (whether or not summary.json can say it)."""
        self.write_last(interrupt.stop_status(err))
        return err

    def failure(self, err: Exception) -> BaseException:
        """What ends the run where step k raised `err`: the stop that caused it
        (an import it interrupted), err itself where it is not a failure of
        the computation, else a ComputationError with the status written."""
        stop = interrupt.cause(err)
        if stop is not None:
            self.write_last(interrupt.stop_status(stop))
            stop.__cause__, stop.__suppress_context__ = None, True
            return stop
        if not isinstance(err, step.FAILURES):
            return err
        self.uncommitted(self.k)   # step k failed in its commit: it did not finish
        return self.failed(err)

    def failed(self, err: Exception) -> ComputationError:
        """The error that ends the run failing with `err` at step k, its
        status written where it can be. Raised `from` a WriteError, which
        tells api.run that the folder takes no pictures either."""
        status = step.failure(self.k, err)
        note = self.write_last(status)
        if isinstance(err, WriteError) and err.path == str(self.out / "summary.json"):
            note = ""   # the status says it already
        failure = ComputationError(status + note)
        failure.__cause__ = err if isinstance(err, WriteError) else None
        failure.__suppress_context__ = True
        return failure

    def finish(self, status, finishing):
        """The run's warnings (api.run draws the pictures in `finishing`) and
        its final status written."""
        if finishing is not None:
            try:
                self.warnings.extend(finishing(self.summary_now(status)))
            except KeyboardInterrupt as err:
                raise self.stopped(err)   # every step is kept; `wingcrack plot OUT` draws the pictures
            except WriteError as err:   # a picture: every step is kept, but the folder takes no more files
                raise self.failed(err) from err
        try:
            self.write(status)
        except WriteError as err:
            raise self.failed(err) from err

    def result(self, status) -> RunResult:
        shown = self.shown
        result = RunResult(status, [r.to_dict() for r in self.records], self.fset, self.summary_now(status), self.out,
                           mesh=None if shown is None else shown.cm,
                           problem=None if shown is None else shown.problem,
                           contact=None if shown is None else shown.contact)
        if self.out is not None:
            result.files = step.files_of(self.out, len(self.records))
        return result


def _slip_history(disc, fset):
    """The converged slip of the Coulomb faces of `disc` along the fractures
    of `fset` as they were meshed (None without friction)."""
    if not disc.contact.has_friction:
        return None
    return SlipHistory.record(disc.cm, fset.fractures, pair_slips(disc))


def _release(disc):
    """Free the previous step's objects now: the MUMPS factors (tens of MB a
    step) are destroyed explicitly, and DOLFINx objects sit in reference
    cycles that Python's collector, blind to their C++ memory, would keep."""
    if disc is not None:
        disc.solver.release()
    with interrupt.deferred():   # a KeyboardInterrupt inside a GC callback would be lost
        gc.collect()
