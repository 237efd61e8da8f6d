"""The Python face of wingcrack: what the command line calls.

    case = wingcrack.Case.from_toml("cases/brazilian_disc_45.toml")
    result = wingcrack.sif(case, out="results/disc45")
    result.tips[0].KI, result.tips[0].KI_M
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import __version__
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


class _Timer:
    def __init__(self):
        self.seconds = {}
        self._t = time.perf_counter()

    def lap(self, name):
        t = time.perf_counter()
        self.seconds[name] = self.seconds.get(name, 0.0) + (t - self._t)
        self._t = t


@dataclass
class Solution:
    """One solved geometry: mesh arrays, the fem problem, contact, SIFs."""
    cm: object          # meshing.CrackMesh
    problem: object     # fem.elasticity.ElasticProblem
    contact: object     # fem.contact_problem.ContactProblem
    tips: list          # TipSIF


def build(case, fractures, timer: _Timer, mesh_kwargs=None):
    """Mesh `fractures` (case Fracture or GrowingFracture objects, with
    .points) in the case's domain, assemble, factorise (with the Schur
    complement on the contact pair dofs) and set up contact.

    Returns (crack_mesh, problem, contact)."""
    from meshing.crack_mesh import crack_mesh

    from .contact.constraints import constraint_rows
    from .fem.contact_problem import ContactProblem
    from .fem.elasticity import ElasticProblem
    from .fem.mesh import to_dolfinx
    from .errors import ComputationError
    from .fem.pair_operator import PairOperator
    from .free_pieces import describe, free_pieces
    from .loads import case_loads
    from .parallel import on_root

    polylines = [np.asarray(f.points, float) for f in fractures]
    cm = on_root(lambda: crack_mesh(case.domain, polylines, case.bc_points(), case.mesh.size,
                                     case.mesh.tip_size, sectors=case.mesh.sectors, **(mesh_kwargs or {})))
    timer.lap("mesh")
    fm = to_dolfinx(cm)
    timer.lap("to_dolfinx")
    m = case.material
    loads = case_loads(case, cm)
    pieces = free_pieces(cm, loads)
    if pieces:
        raise ComputationError("the stiffness matrix is singular: a fracture cuts off a piece of the body that "
                               f"no displacement condition holds ({describe(pieces)})")
    problem = ElasticProblem(fm, m.E, m.nu, m.plane, loads)
    rows = constraint_rows(cm, fractures)
    timer.lap("assemble")
    problem.factorize(schur_dofs=PairOperator.pair_dofs(fm, rows) if len(rows) else None)
    timer.lap("factorize")
    contact = ContactProblem(problem, rows)
    timer.lap("contact")
    return cm, problem, contact


def all_sifs(case, cm, problem, contact, polylines):
    """TipSIF of every tip (both methods) for the current solution."""
    from .tip_sifs import tip_sifs

    m = case.material
    forces = contact.nodal_forces(len(cm.x)) if contact.result is not None else None
    return tip_sifs(problem, cm, polylines, case.domain, m.E, m.nu, m.plane,
                    case.stress.tensor(), face_forces=forces)


def solve_initial(case, timer: _Timer | None = None, load_factor: float = 1.0) -> Solution:
    """Mesh the case's initial geometry, solve with contact, compute SIFs."""
    timer = timer or _Timer()
    cm, problem, contact = build(case, case.fractures, timer)
    contact.solve(load_factor)
    timer.lap("solve")
    tips = all_sifs(case, cm, problem, contact, [np.asarray(f.points, float) for f in case.fractures])
    timer.lap("sif")
    return Solution(cm, problem, contact, tips)


def contact_summary(sol: Solution) -> dict:
    c = sol.contact
    rows = c.rows
    out = {"pairs": int(len(sol.cm.pairs)), "rows": int(len(rows)), "closed": 0, "iterations": 0}
    if c.result is not None:
        out["closed"] = int(np.sum(c.result.active))
        out["iterations"] = int(c.result.iterations)
        out["kkt"] = c.result.kkt_residuals(rows.gap, rows.normal)
    return out


def _summary(case, status, steps):
    return {
        "title": case.title,
        "version": __version__,
        "status": status,
        "steps": steps,
        "fractures": [{"points": np.asarray(f.points, float).tolist(), "origin": "pre-existing"}
                      for f in case.fractures],
    }


def _state(tip, KIc) -> str:
    """In a static solve a tip 'grows' if it has reached the toughness."""
    return "growing" if KIc is not None and tip.K_eq >= KIc * (1 - 1e-9) else "arrested"


def _step(step, load_factor, dofs, cells, tips, seconds, contact=None, KIc=None):
    return {
        "step": step,
        "load_factor": load_factor,
        "dofs": int(dofs),
        "cells": int(cells),
        "tips": [dict(fracture=t.fracture, end=t.end, x=t.x, y=t.y, KI=t.KI, KII=t.KII,
                      KI_M=t.KI_M, KII_M=t.KII_M, G=t.G, theta=t.theta, K_eq=t.K_eq,
                      advance=0.0, state=_state(t, KIc)) for t in tips],
        "contact": contact or {"pairs": 0, "closed": 0, "iterations": 0},
        "seconds": {k: round(v, 6) for k, v in seconds.items()},
    }


def _prepare_out(out, force: bool = False) -> Path:
    """io.outdir.prepare on rank 0; every rank raises its FolderError."""
    from mpi4py import MPI

    from .errors import FolderError
    from .io.outdir import prepare

    comm = MPI.COMM_WORLD
    problem = None
    if comm.rank == 0:
        try:
            prepare(out, force)
        except FolderError as err:
            problem = (err.path, err.reason)
    problem = comm.bcast(problem, root=0)
    if problem is not None:
        raise FolderError(*problem)
    return Path(out)


def _write_failure(case, out, reason: str, steps=()):
    from mpi4py import MPI

    from .io.summary import write_summary

    if out is not None and MPI.COMM_WORLD.rank == 0:
        write_summary(Path(out) / "summary.json", _summary(case, f"failed: {reason}", list(steps)))


def sif(case, out=None, quiet: bool = True, status: str = "finished", force: bool = False) -> SifResult:
    """One solve of the initial geometry (with contact on non-open faces) and
    the SIFs of every tip.

    With `out`, writes summary.json, fractures.png, fields.vtu (displacement,
    stress) and faces.vtu (opening, slip, contact traction) there. A folder
    holding a previous result raises FolderError unless `force` (which
    deletes that result first; see io.outdir). A failed computation raises
    ComputationError after writing a summary whose status is
    "failed: <reason>".
    """
    from mpi4py import MPI

    from .errors import ComputationError

    if out is not None:
        out = _prepare_out(out, force)
    timer = _Timer()
    try:
        sol = solve_initial(case, timer)
    except ComputationError as err:
        _write_failure(case, out, str(err))
        raise
    cm, problem, tips = sol.cm, sol.problem, sol.tips
    fm = problem.fm
    files = {}
    if out is not None:
        from .io.faces import closed_segments, write_faces
        from .io.fields import write_fields
        from .io.pictures import plot_fractures

        about = {"step": 0, "load_factor": 1.0}
        files["fields"] = write_fields(out / "fields.vtu", problem, cm, field_data=about)
        files["faces"] = write_faces(out / "faces.vtu", sol, field_data=about)
        closed = closed_segments(sol)   # collective: the face displacements are gathered
        if MPI.COMM_WORLD.rank == 0:
            files["picture"] = plot_fractures(
                out / "fractures.png", case.domain,
                [{"points": f.points, "origin": "pre-existing"} for f in case.fractures],
                tips=[{"x": t.x, "y": t.y} for t in tips], rosette=case.mesh.tip_size,
                title=case.title, mesh=cm, closed_segments=closed)
        timer.lap("output")
    seconds = dict(timer.seconds)
    seconds["total"] = sum(seconds.values())
    summary = _summary(case, status, [_step(0, 1.0, fm.num_dofs, fm.num_cells, tips, seconds,
                                            contact_summary(sol), KIc=case.material.KIc)])
    if out is not None and MPI.COMM_WORLD.rank == 0:
        from .io.summary import write_summary

        files["summary"] = out / "summary.json"
        write_summary(files["summary"], summary)
    return SifResult(tips, summary, seconds, fm.num_dofs, fm.num_cells, cm, problem, out, files,
                     contact=sol.contact)


def run(case, out=None, quiet: bool = True, progress=None, plots: bool = True, force: bool = False,
        resume: bool = False):
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
    history.png and the growth animation. A failed run draws the same
    pictures of its finished steps before raising ComputationError.

    With `resume`, continue the run whose checkpoint `out` holds (stopped,
    killed or interrupted) from its last finished step, to the case's
    propagation.steps; FolderError when there is no checkpoint of this case.
    Ctrl-C stops with status "stopped: interrupted" and re-raises
    KeyboardInterrupt; every finished step is kept."""
    from mpi4py import MPI

    from .errors import ComputationError
    from .propagation.loop import run as _run

    if resume:
        from .errors import FolderError
        from .io.outdir import check_writable
        from .propagation import checkpoint

        if out is None:
            raise FolderError(Path("."), "--resume needs the output folder of the run (-o)")
        if not Path(out).is_dir():
            raise FolderError(Path(out), "does not exist: nothing to resume")
        check_writable(out)
        try:
            checkpoint.load(out, case)
        except ValueError as err:
            raise FolderError(Path(out), str(err)) from None
        out = Path(out)
    elif out is not None:
        out = _prepare_out(out, force)
    draw = out is not None and MPI.COMM_WORLD.rank == 0
    try:
        if progress is True or progress is False or progress is None:
            from .progress import ProgressBar

            with ProgressBar(case.propagation.steps, show=bool(progress)) as bar:
                result = _run(case, out, quiet=quiet, progress=bar, resume=resume)
        else:
            result = _run(case, out, quiet=quiet, progress=progress, resume=resume)
    except ComputationError as err:
        if draw:
            try:
                plot(out, history=plots, animation=plots)
            except Exception as e:  # noqa: BLE001 - the computation's failure is the news
                raise ComputationError(f"{err} (pictures not drawn: {' '.join(str(e).split())})") from None
        raise
    if draw:
        result.files.update(plot(out, history=plots, animation=plots))
    return result


def plot(folder, history: bool = True, animation: bool = True, fmt: str | None = None) -> dict:
    """Draw the pictures of a result folder (a run, finished, stopped or
    failed, or a solve) from its summary.json and step files, and return
    {name: path}: fractures.png always; with at least one step, history.png
    (load factor, K_eq of every tip, DOFs) and growth.gif / growth.mp4
    (`fmt`, default mp4 when ffmpeg is on PATH), unless switched off.

    Only these pictures are (re)written: they are views of the data, which
    is never touched. Raises FolderError when `folder` is missing, is not a
    wingcrack result or cannot be written."""
    from .io.outdir import check_writable, read_result
    from .io.pictures import fractures_of_result

    result = read_result(folder)
    folder = check_writable(folder)
    files = {"picture": fractures_of_result(folder / "fractures.png", result)}
    if result.steps and history:
        from .io.history import plot_history

        plot_history(folder / "history.png", result.summary)
        files["history"] = folder / "history.png"
    if result.steps and animation:
        from .io.animation import animate_growth

        files["animation"] = animate_growth(folder, result, fmt)
    return files
