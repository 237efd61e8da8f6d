"""The propagation loop (paper Fig. 8), one step at a time:

    discretise the current fractures (wingcrack.step: mesh, assemble,
    factorise with the Schur complement for contact; on a fixed mesh the
    far field outside the run's patch (propagation.patch) is meshed and
    factorised once for the steps it serves, and a step factorises the
    patch only)
    -> critical load factor (critical_load: the first tip reaches KIc)
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
completed its growth and is "finished" before propagation.steps (the disc's
wings at the load points); a case with no tip that may grow at all stops
with NO_TIP_AT_ALL, and propagation.steps = 0 with NO_STEPS (a run that did
nothing is never "finished").
"""
from __future__ import annotations

import contextlib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

import wingcrack_kernels as K
from .. import step
from ..errors import Collapse, ComputationError, WriteError
from ..parallel import on_root
from ..results import LastSolve, StepRecord, dataframe, tip_rows
from .. import progress as progress_now
from .. import interrupt
from . import checkpoint, growth
from . import injection
from .critical_load import critical_load_factor, scales_with_load
from .fracture_set import FractureSet
from .patch import next_patch

#: no fracture of the case has a free tip that may grow (every end a mouth, or grow = false)
NO_TIP_AT_ALL = "stopped: no tip can grow (no fracture has a free tip that may grow)"
#: propagation.steps = 0: no step was asked for (a run that did nothing is not "finished")
NO_STEPS = "stopped: propagation.steps = 0 (no step asked for; `wingcrack sif` solves the initial geometry)"


#: the load modes in which each step searches the critical load factor ("pressure": of the
#: fracture pressures only, the critical injection pressure)
SEARCHED = ("scale", "pressure")

#: added to the load-limit status of a case in which the load factor multiplies nothing
#: a K_eq below this times KIc is said as 0 in a status: the round-off of SIFs that vanish
ROUND_OFF_K = 1e-9
NOTHING_SCALES = (" (nothing in the case scales with it: every [[bc]] value and slip is 0, and the in-situ stress "
                  "and gravity are not scaled)")


def _scaled_load(case) -> bool:
    """Does the load factor multiply anything (a non-zero bc value, slip or
    fracture pressure; with load = "pressure" the pressures only)?"""
    pressure = any(f.pressure for f in case.fractures)
    if case.propagation.load == "pressure":
        return pressure
    return any(any(b.value) for b in case.bcs) or any(f.slip for f in case.fractures) or pressure


def no_tip_left(records) -> str:
    """The status of a run in which no free tip that may grow is left: the
    growth is complete ("finished") when steps were done (every tip joined or
    reached the boundary), else nothing could ever grow."""
    return "finished" if records else NO_TIP_AT_ALL


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
    step.start_meshing(mesh_timeout)   # the worker's start-up overlaps the imports of preload()
    with interrupt.watching(), _NextMesh() as next_mesh, contextlib.ExitStack() as frozen:
        return _run(case, out, progress, mesh_timeout, resume, finishing, committed, next_mesh, frozen)


class _NextMesh:
    """The next step's mesh (step.MeshRequest), begun during this step; a
    run that ends in any way before collecting it abandons it (the meshing
    worker stops: no answer is left unread)."""

    def __init__(self):
        self.request = None

    def take(self):
        request, self.request = self.request, None
        return request

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        if self.request is not None:
            self.take().cancel()
        return False


@contextlib.contextmanager
def _collector_skips_modules():
    """Every step ends with a full garbage collection (see _release), which
    would scan the objects of the imported modules each time. The modules
    are imported first and their objects frozen (gc.freeze: never scanned,
    never collected) for the run."""
    import gc

    step.preload()
    gc.freeze()
    try:
        yield
    finally:
        gc.unfreeze()


def _run(case, out, progress, mesh_timeout, resume, finishing, committed, next_mesh, frozen) -> RunResult:
    """Fig. 8, step after step, with the ends of a run: a stop (the status a
    step returns), a collapse of the body (the end of its loading path), a
    failure (every finished step kept), an interrupt (kept and resumable)."""
    run = _Run(case, out, mesh_timeout, next_mesh)
    if resume:
        run.resume()
        for record in run.records:
            run.tell(committed, record)
    run.begin(frozen)
    steps = case.propagation.steps
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
    """What a run carries from step to step: the fractures, the load factor,
    the records, and what the next mesh and solve reuse (the sizes of the
    error estimate, the converged slip, the patch and its far field)."""

    def __init__(self, case, out, mesh_timeout, next_mesh):
        from mpi4py import MPI

        from ..io.summary import SummaryWriter

        self.case, self.prop = case, case.propagation
        self.out = None if out is None else Path(out)   # made ready by api.run
        self.mesh_timeout, self.next_mesh = mesh_timeout, next_mesh
        self.fset = FractureSet.from_case(case)
        self.rule = growth.Rule.of(case)
        self.pump = injection.Pump.of(case) if self.prop.load == "injection" else None
        self.lam = 0.0 if self.prop.load in SEARCHED else self.pump.pressure if self.pump else 1.0
        self.records = []
        self.disc = None
        self.shown = None   # the discretisation of the last recorded step, while it is not released
        self.sizes = None   # the error-estimate size field for the next mesh (mesh.adaptive)
        self.history = None   # the converged slip of the faces (friction), carried to the next mesh
        self.patch = None     # the circle remeshed every step (propagation.patch; fixed meshes only)
        self.far = None       # the far field's factorisation outside it (fem.far_field), kept while it serves
        self.k = 0            # the step under way (the first one to do, before the loop)
        self.warnings = []    # about the whole run (from `finishing`)
        self.writes = self.out is not None and MPI.COMM_WORLD.rank == 0
        self.summary_file = SummaryWriter(self.out / "summary.json") if self.writes else None
        self.checkpoints = checkpoint.Writer(self.out, case) if self.writes else None
        self.last = None      # the record of the last committed step

    def resume(self):
        if self.out is None:
            raise ValueError("resume needs the output folder of the run")
        ck = checkpoint.load(self.out, self.case)
        self.fset, self.lam, self.sizes, self.k = ck["fset"], ck["load_factor"], ck["sizes"], ck["step"] + 1
        self.history, self.patch = ck["history"], ck["patch"]
        self.records = [StepRecord.from_dict(s) for s in ck["steps"]]
        if self.pump is not None:
            self.pump.restore(ck["pump"])

    def begin(self, frozen):
        """The first step's mesh is begun before DOLFINx is imported: its gmsh
        overlaps the imports of preload()."""
        if self.k < self.prop.steps and self.fset.active_tips():
            self.request_mesh()
            frozen.enter_context(_collector_skips_modules())   # a run of no step imports no DOLFINx
        self.done = self.fset.copy()   # the fractures after the last finished step

    def request_mesh(self):
        self.patch = next_patch(self.patch, self.case, self.fset)
        self.next_mesh.request = step.start_mesh(self.case, self.fset.fractures, sizes=self.sizes,
                                                 timeout=self.mesh_timeout, patch=self.patch)

    def network(self):
        """With a pump, the injected network's fractures ((n,) bool), else None."""
        return None if self.pump is None else self.pump.mask(len(self.fset.fractures))

    def step(self, k):
        """Step k: mesh, the critical load, solve, SIFs, growth, the next mesh
        begun, the step committed. Returns the status the run stops with, or
        None where the fractures grew."""
        case, prop, fset = self.case, self.prop, self.fset
        timer = step.Timer()
        progress_now.step_started(k)
        interrupt.check()
        if not fset.active_tips():
            return no_tip_left(self.records)
        disc = self.discretise(timer)
        interrupt.check()
        grow = growth.may_grow(disc.cm, fset)
        if not grow:
            return no_tip_left(self.records)
        solves = 1
        pumped = None
        if prop.load in SEARCHED:
            progress_now.doing("the critical-load search")
            homogeneous = _homogeneous(case, disc, fset)   # before the solves: they may accept a slip
            crit = _critical_load(case, disc, fset, grow, self.lam, homogeneous)
            if crit.load_factor is None:
                return self.at_the_limit(k, disc, grow, timer, int(crit.solves) + 1)
            held, self.lam, solves = self.lam, crit.load_factor, int(crit.solves)
        elif self.pump is not None:
            progress_now.doing("the fluid balance and the critical pressure")
            pumped = injection.critical(self.pump, disc, fset.fractures, _keq(case, disc, fset, grow),
                                        case.material.KIc, case.material.E,
                                        _homogeneous(case, disc, fset, self.network()), _pressure_scale(case))
            if pumped.stop is not None:
                return self.pump_stopped(k, disc, grow, timer, pumped)
            self.lam, solves = pumped.pressure, pumped.solves
        progress_now.doing(f"the solve at load factor {self.lam:.6g}")
        disc.solution_at(self.lam)   # the search's last trial is often at it
        timer.lap("solve")
        interrupt.check()
        progress_now.doing("the stress intensity factors")
        tips = disc.sifs(case, fset.polylines())
        timer.lap("sif")
        # the converged slip along the fractures as meshed (before they grow): the next mesh's reference
        converged = _slip_history(disc, fset)
        fluid = None if pumped is None else self.fluid_state(disc, pumped)   # before growth: the step's geometry

        candidates = growth.candidates(tips, disc.cm, grow)
        if prop.load == "fixed" and not growth.reached(candidates, self.rule).any():
            # the solved step is a result too: recorded with its files, no growth
            self.record(self.finished(k, self.lam, disc, tips, timer, solves=1), disc)
            return "stopped: no tip reaches KIc under the fixed load"
        progress_now.doing("growth, the step's files and the next mesh")
        grown = growth.grow(fset, candidates, len(tips), self.rule, case.domain)
        timer.lap("growth")
        interrupt.check()
        if not grown.grew:
            # nothing moved: the next step would be this one again. Recorded (not
            # checkpointed: a resumed run solves it again and stops the same way)
            self.record(self.finished(k, self.lam, disc, tips, timer, solves=solves, fluid=fluid), disc)
            return f"stopped: no tip can grow ({grown.why_none()})"
        if case.mesh.adaptive:
            from ..adaptivity import next_sizes   # DOLFINx's: imported by preload() before the first step

            self.sizes = next_sizes(disc.problem, case.mesh.tip_size, case.mesh.size)
            timer.lap("estimate")
        if k + 1 < prop.steps and fset.active_tips():
            # step k+1's mesh is made while step k is written; it fails (if it does) as step k+1
            self.request_mesh()
            timer.lap("mesh")
        record = self.finished(k, self.lam, disc, tips, timer, solves=solves, fluid=fluid,
                               states=[t.state for t in grown.tips], advances=[t.advance for t in grown.tips])
        if prop.load in SEARCHED:
            record.critical_load_factor = _own_critical(case, tips, grow, self.lam, held, homogeneous)
        elif pumped is not None and not pumped.unstable:
            record.critical_load_factor = self.lam   # the critical pressure of the step's geometry
        self.commit(k, record, disc, converged, fluid)
        return None

    def fluid_state(self, disc, pumped) -> dict:
        """The pumped step's fluid, at its solution and on its geometry
        (before growth): the step, each fracture's volume and pressure, the
        hydraulic groups and lengths (injection.step_record's)."""
        fractures = self.fset.fractures
        return {"step": pumped, "volumes": self.pump.volumes(disc, fractures), "groups": self.pump.groups(self.fset),
                "pressures": disc.pressure_at(pumped.pressure),
                "lengths": [float(np.linalg.norm(np.diff(f.points, axis=0), axis=1).sum()) for f in fractures]}

    def pump_stopped(self, k, disc, grow, timer, pumped) -> str:
        """The pump stops the run before a tip reaches KIc (end_time or
        shut-in), or the pressure would pass its limit: the state where it
        stops is recorded (a result too, as at the load factor limit: the
        user sees how far from KIc the tips stayed) and the status says it."""
        pump, E = self.pump, self.case.material.E
        if pumped.stop == "limit":
            limit = pump.search_limit(E)
            disc.solve(limit)
            v = pump.network_volume(disc, self.fset.fractures)
            pumped.pressure, pumped.volume, pumped.time = limit, v, max(pump.time_of(v, limit), pump.time)
            pumped.history.append((pumped.time, limit, v))
        else:
            injection.stopped(pump, pumped, disc, self.fset.fractures, _pressure_scale(self.case))
        timer.lap("solve")
        tips = disc.sifs(self.case, self.fset.polylines())
        timer.lap("sif")
        self.record(self.finished(k, pumped.pressure, disc, tips, timer, solves=pumped.solves + 1,
                                  fluid=self.fluid_state(disc, pumped)), disc)
        ratio = max(tips[i].K_eq for i in grow) / self.case.material.KIc
        said = f"{ratio:.3g}" if ratio >= ROUND_OFF_K else "0"
        need = "" if pumped.needed is None else f"; they need {pumped.needed:.6g} Pa"
        below = f"the largest K_eq is {said} KIc{need}"
        p, t = pumped.pressure, pumped.time
        if pumped.stop == "limit":
            return f"stopped: no tip reaches KIc below the pressure limit 0.1 E = {p:.6g} Pa (there {below})"
        if t == pump.schedule.end:
            return f"stopped: end_time reached: at {t:g} s the network holds {p:.6g} Pa ({below})"
        return (f"stopped: shut-in from {t:g} s: the network's fluid holds {p:.6g} Pa ({below}), and no more "
                "comes")

    def discretise(self, timer):
        """This step's discretisation, the last one's factors released first."""
        _release(self.disc)   # the previous step's factors and forms
        self.disc = self.shown = None
        disc = self.disc = step.discretise(self.case, self.fset.fractures, timer, sizes=self.sizes,
                                           timeout=self.mesh_timeout, history=self.history,
                                           mesh=self.next_mesh.take(), patch=self.patch, far=self.far,
                                           network=self.network())
        if disc.far is not self.far and self.far is not None:
            self.far.destroy()   # the patch moved on: its far field is another
        self.far = disc.far
        return disc

    def at_the_limit(self, k, disc, grow, timer, solves) -> str:
        """No tip reaches KIc below the load factor limit. The step solved at
        the limit is a result too (as under a fixed load): the user sees how
        far from KIc the tips stayed, in its record and its files."""
        limit = self.prop.max_load_factor
        progress_now.doing(f"the solve at the load factor limit {limit:.6g}")
        disc.solve(limit)
        timer.lap("solve")
        tips = disc.sifs(self.case, self.fset.polylines())
        timer.lap("sif")
        self.record(self.finished(k, limit, disc, tips, timer, solves=solves), disc)
        ratio = max(tips[i].K_eq for i in grow) / self.case.material.KIc
        # below 1e-9 KIc a K_eq is the round-off of SIFs that vanish (faces stuck or closed)
        said = f"{ratio:.3g}" if ratio >= ROUND_OFF_K else "0"
        return f"stopped: no tip reaches KIc below the load factor limit {limit:g} (there the " \
            f"largest K_eq is {said} KIc)" + ("" if _scaled_load(self.case) else NOTHING_SCALES)

    def finished(self, k, lam, disc, tips, timer, fluid=None, **more):
        """Step k's record, its files written; with a pump (fluid: fluid_state)
        its time, injection and networks, the time the PVD's axis."""
        if fluid is None:
            return step.finish(self.out, k, lam, disc, tips, timer, KIc=self.case.material.KIc, **more)
        pumped = injection.step_record(self.pump, fluid["step"], fluid["volumes"], fluid["groups"],
                                       fluid["pressures"], fluid["lengths"])
        times = [r.time for r in self.records] + [pumped["time"]]
        record = step.finish(self.out, k, lam, disc, tips, timer, KIc=self.case.material.KIc, times=times, **more)
        record.time, record.injection, record.networks = pumped["time"], pumped["injection"], pumped["networks"]
        return record

    def record(self, record, disc):
        self.records.append(record)
        self.shown = disc

    def commit(self, k, record, disc, converged, fluid=None):
        """Step k committed whole: its record, the fractures grown, summary.json
        and the checkpoint agree (an interrupt waits until they do). With a
        pump (fluid: fluid_state), its time and pressure are the run's, and
        the fractures joined enter the network."""
        with interrupt.deferred():
            self.record(record, disc)
            if self.pump is not None:
                self.pump.advance(fluid["step"], self.done.fractures)
                self.pump.join(self.fset, fluid["volumes"], fluid["pressures"])
            if self.prop.connect_pressure:   # the next step meshes and loads with the connected pressures
                self.fset.connect_pressures(exclude=() if self.pump is None else self.pump.network)
            self.done = self.fset.copy()
            self.history = converged
            self.last = record

            def save():
                if self.writes:
                    self.write("running")
                    self.checkpoints.save(k, self.fset, self.lam, self.records, self.sizes, self.history,
                                          self.patch, pump=None if self.pump is None else self.pump.to_dict())

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
    from ..contact.slip_history import SlipHistory

    return SlipHistory.record(disc.cm, fset.fractures, disc.pair_slips())


def _own_critical(case, tips, grow, lam, held, homogeneous: bool):
    """The load factor at which the step's first growing tip reaches KIc,
    though the run held a higher one (after the peak): where the response
    scales with the load, lam KIc / K_eq(lam) (K proportional to the load on
    the step's geometry); elsewhere the search's root where it rose above
    the held load, and None where it started above KIc (path-dependent: a
    lower critical load is not the answer of another loading)."""
    if homogeneous:
        k = max(tips[i].K_eq for i in grow)
        return lam * case.material.KIc / k if k > 0 else None
    return lam if lam > held else None


def _homogeneous(case, disc, fset, network=None) -> bool:
    """Does the step's whole response scale with the load factor (no in-situ stress or other fixed load,
    no reference slip, no cohesion)? network: with a pump, the injected network."""
    rows = disc.contact.rows
    return scales_with_load(case, fset, network) and not np.any(disc.contact.reference) and \
        not np.any(rows.cohesion)


def _keq(case, disc, fset, grow):
    """keq(load): the largest K_eq of the tips `grow` after a solve at
    `load`, by the SIFs that drive growth."""
    polylines = fset.polylines()
    trials = [0]

    def keq(load):
        trials[0] += 1
        progress_now.doing(f"the critical-load search, trial {trials[0]} at load factor {load:.6g}")
        disc.solution_at(load)   # a pump's balance may have solved at it
        KI, KII = disc.driving_sifs(case, polylines)
        th = K.mts_angle(KI[grow], KII[grow])
        k = float(np.max(K.equivalent_k(KI[grow], KII[grow], th)))
        step.require_finite("K_eq", k)
        return k

    return keq


def _critical_load(case, disc, fset, grow, start, homogeneous: bool):
    """critical_load.CriticalLoad: the load factor (>= start) at which the
    first of the tips `grow` reaches KIc, by the SIFs that drive growth.
    With friction every trial starts from the bracket's lower end (accepted
    there), and the response scales with the load only from zero slip."""
    return critical_load_factor(_keq(case, disc, fset, grow), case.material.KIc, start, homogeneous,
                                case.propagation.max_load_factor, accept=disc.accept)


def _pressure_scale(case) -> float:
    """A pressure scale of a pumped case (Pa): the largest of the in-situ
    stress, the given pressures, the initial pressure and the net pressure
    KIc / sqrt(pi tip_size) that opens a crack a rosette long: the critical
    search's first step above the balance and the balance's without a slope."""
    given = [f.pressure for f in case.fractures] + [case.injection.initial_pressure]
    net = case.material.KIc / np.sqrt(np.pi * case.mesh.tip_size)
    return float(max(np.abs(case.stress.tensor()).max(), max(given), net))


def _release(disc):
    """Free the previous step's objects now: the MUMPS factors (tens of MB a
    step) are destroyed explicitly, and DOLFINx objects sit in reference
    cycles that Python's collector, blind to their C++ memory, would keep."""
    import gc

    if disc is not None:
        disc.release()
    with interrupt.deferred():   # a KeyboardInterrupt inside a GC callback would be lost
        gc.collect()
