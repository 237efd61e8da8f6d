"""The Python face of wingcrack: what the command line calls.

    case = wingcrack.Case.from_toml("cases/brazilian_disc_45.toml")
    result = wingcrack.sif(case, out="results/disc45")
    result.tips[0].KI, result.tips[0].KI_M

`sif` is step 0 of the pipeline in wingcrack/step.py; `run` is the loop in
wingcrack/propagation/loop.py over the same steps. Both write the same
result layout (see io/outdir.py) and draw its pictures from it (io/).
"""
from __future__ import annotations

import contextlib
from dataclasses import dataclass, field
from pathlib import Path

from . import drawing, interrupt, startup, step
from .case import Case
from .errors import CaseError, ComputationError, FolderError, WriteError
from .io import outdir
from .io.outdir import check_folder_name
from .io.plotting import plot   # plot: the public `wingcrack.plot`, one function
from .io.summary import write_summary
from .parallel import on_world_root
from .progress import ProgressBar
from .results import LastSolve, dataframe, tip_rows


@dataclass
class SifResult(LastSolve):
    """One static solve of the initial geometry.

    tips: list of TipSIF (KI, KII by displacement correlation; KI_M, KII_M by
    the interaction integral; G; theta (MTS kink angle, rad); K_eq), in the tip
    frames of the case contract. summary: the dict written to summary.json.
    .to_dataframe() (one row per tip; needs pandas), .dolfinx_mesh and
    .displacement (the DOLFINx solve).
    """
    tips: list
    summary: dict
    seconds: dict
    dofs: int
    cells: int
    mesh: object = None          # meshing.CrackMesh
    problem: object = None       # fem.elasticity.ElasticProblem (mesh, u)
    out: Path | None = None
    files: dict = field(default_factory=dict)
    contact: object = None       # fem.contact_problem.ContactProblem

    def to_dataframe(self):
        """One row per tip (pandas; tip_rows(self.summary['steps']) gives plain dicts)."""
        return dataframe(tip_rows(self.summary.get("steps", [])))


def _require_case(case) -> None:
    """CaseError unless `case` is a wingcrack.Case (a dict, a path or None
    would otherwise fail deep inside with an AttributeError)."""
    if not isinstance(case, Case):
        raise CaseError("case", f"expected a wingcrack.Case, got {type(case).__name__} (build one with "
                        "wingcrack.Case.from_toml(path) or wingcrack.Case.from_dict(table))")


def sif(case, out=None, force: bool = False) -> SifResult:
    """One solve of the initial geometry at load factor 1 (with contact on
    non-open faces) and the SIFs of every tip: step 0 of a run. With a pump
    (load = "injection"), the state at t = 0: the injected network at its
    initial pressure, every other load as given.

    With `out`, writes the layout of a one-step run there: summary.json,
    step_0000.vtu (displacement, stress), faces_0000.vtu (opening, slip,
    contact traction), fields.pvd, faces.pvd and fractures.png. A folder
    holding a previous result raises FolderError unless `force` (which
    deletes that result first; see io.outdir). A failed computation raises
    ComputationError after writing a summary whose status is
    "failed: step 0: <reason>". A picture that cannot be drawn is a warning
    in summary.json ("warnings"), not a failure.
    """
    _require_case(case)
    if out is not None:
        check_folder_name(out)
    interrupt.forget()   # a stop before this call (a run's, caught by the caller) is past
    startup.start_processes(pictures=out is not None)   # gmsh's and matplotlib's imports overlap ours
    with _folder_lock(out, create=True):
        return _sif(case, out, force)


def _sif(case, out, force) -> SifResult:
    from .propagation.fracture_set import FractureSet   # overlap: the propagation package after the worker starts

    root = on_world_root()   # MPI starts here (the solve's would), before the folder's work
    if out is not None:
        out = outdir.prepare_for_result(out, force)
    case = case.at_start()   # with a pump: t = 0, the network at its initial pressure
    writes = out is not None and root
    pieces = FractureSet.from_case(case).summary()

    def write(summary):
        if writes:
            write_summary(out / "summary.json", summary.to_dict())

    def failed(err: Exception, steps: list) -> ComputationError:
        """The error that ends the solve failing with `err`, its status
        written where it can be (see loop.run)."""
        status = step.failure(0, err)
        try:
            write(step.summary(case, status, steps, pieces))
        except WriteError as unwritten:
            if not (isinstance(err, WriteError) and err.path == unwritten.path):
                status += f" (summary.json not updated: {unwritten.reason})"
        return ComputationError(status)

    timer = step.Timer()
    try:
        sol = step.solve_initial(case, timer)
        record = step.finish(out, 0, 1.0, sol, sol.tips, timer, states=step.static_states(sol.tips, case.material.KIc),
                             KIc=case.material.KIc)
    except Exception as err:
        stop = interrupt.cause(err)
        if stop is not None:   # an error that a stop caused (an import it interrupted): the stop
            raise stop from None
        if not isinstance(err, step.FAILURES):
            raise
        raise failed(err, []) from None
    summary = step.summary(case, "finished", [record], pieces)
    files = step.files_of(out, 1) if out is not None else {}
    try:
        if writes:
            try:
                summary.warnings += _pictures(out, summary.to_dict(), False, False, files)
            except KeyboardInterrupt as err:   # Ctrl-C or SIGTERM
                summary.status = interrupt.stop_status(err)   # the data are all there: `wingcrack plot OUT` draws it
                with contextlib.suppress(WriteError):   # the stop is the news
                    write(summary)
                raise
        write(summary)
    except WriteError as err:   # the folder takes no more files (the step's are all there)
        raise failed(err, [record]) from None
    seconds = dict(timer.seconds)
    seconds["total"] = sum(seconds.values())
    return SifResult(sol.tips, summary.to_dict(), seconds, sol.dofs, sol.cells, sol.cm, sol.problem, out, files,
                     contact=sol.contact)


def run(case, out=None, progress=None, plots: bool = True, force: bool = False, resume: bool = False):
    """Grow the case's wing cracks (see wingcrack.propagation.loop.run) and
    return a RunResult: .status, .steps (summary.json's step records), .tips
    (the last step's), .polylines, .to_dataframe() (one row per step and
    tip; needs pandas), and the last step's .dolfinx_mesh and .displacement.

    progress: True shows a progress bar (load factor, DOFs, closed pairs,
    slowest phase), False/None nothing, or a callable progress(k, step)
    called after every step.

    With `out`: the folder must not hold a previous result unless `force`
    (FolderError; see io.outdir). Writes summary.json, the step files and
    their ParaView indices, and fractures.png at the end; with `plots` also
    history.png and the growth animation. The pictures are drawn before
    summary.json gets its final status; a picture that cannot be drawn is a
    warning there ("warnings"), the status stays. A failed run draws the
    same pictures of its finished steps before raising ComputationError.

    With `resume`, continue the run whose checkpoint `out` holds (stopped,
    killed or interrupted) from its last finished step, to the case's
    propagation.steps; FolderError when there is no checkpoint of this case.
    Ctrl-C stops with status "stopped: interrupted" and re-raises
    KeyboardInterrupt; every finished step is kept (also when it comes
    while the pictures are drawn: `wingcrack plot OUT` draws them)."""
    _require_case(case)
    if not (progress is None or isinstance(progress, bool) or callable(progress)):
        raise TypeError(f"progress: expected True, False, None or a callable progress(k, step), got "
                        f"{type(progress).__name__}")
    if out is not None:
        check_folder_name(out)
    startup.start_processes(pictures=out is not None)   # gmsh's and matplotlib's imports overlap ours
    with _folder_lock(out, create=not resume):
        return _run(case, out, progress, plots, force, resume)


def _folder_lock(folder, create: bool):
    """The lock of the result folder (io.outdir.locked, re-entrant: the
    command line holds it already) for a whole sif or run called from
    Python, so that a second one into the same folder, from another
    process, is refused (FolderError "is in use") instead of mixing its
    files with the first's. Nothing without a folder."""
    return contextlib.nullcontext() if folder is None else outdir.locked(folder, create=create)


def _run(case, out, progress, plots, force, resume):
    from .propagation import checkpoint, loop   # overlap: their imports (scipy's optimizers) after the worker starts

    root = on_world_root()   # MPI starts here (the run's would), before the folder's work
    if resume:
        out = outdir.open_to_resume(out)
        try:
            state = checkpoint.load(out, case)
        except ValueError as err:
            raise FolderError(out, outdir.no_checkpoint(out) or str(err)) from None
        outdir.check_resumable(out, len(state["steps"]), case.propagation.steps)
    elif out is not None:
        out = outdir.prepare_for_result(out, force)
    draw = out is not None and root
    pictures = {}

    def finishing(summary: dict) -> list:
        return _pictures(out, summary, plots, plots, pictures)

    # the animation's frames drawn in the drawing process as the steps are committed
    frames = drawing.Frames(out, case.title, step.propagation_asked(case), bool(case.fractures)) if draw and plots \
        else None
    options = dict(resume=resume, finishing=finishing if draw else None, committed=frames)
    try:
        if progress is True or progress is False or progress is None:
            with ProgressBar(case.propagation.steps, show=bool(progress)) as bar:
                result = loop.run(case, out, progress=bar, **options)
        else:
            result = loop.run(case, out, progress=progress, **options)
    except ComputationError as err:
        if draw and not isinstance(err.__cause__, WriteError):   # a folder that takes no files takes no pictures
            try:
                drawing.plot(out, history=plots, animation=plots)
            except Exception as e:  # noqa: BLE001 - the computation's failure is the news
                raise ComputationError(f"{err} (pictures not drawn: {' '.join(str(e).split())})") from None
        raise
    result.files.update(pictures)
    return result


def _pictures(out, summary: dict, history: bool, animation: bool, files: dict) -> list:
    """Draw the pictures of the result in `out` as `summary` describes it
    (adding their paths to `files`) and return a warning for each that could
    not be drawn: a picture is a view of the data, which are all written.
    Drawn in the drawing process (wingcrack/drawing.py) when it runs."""
    drawn, warnings = drawing.pictures(out, summary, history, animation)
    files.update(drawn)
    return warnings
