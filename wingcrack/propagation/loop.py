"""The propagation loop (paper Fig. 8), one step at a time:

    mesh the current fractures -> factorise (+ Schur complement for contact)
    -> critical load factor (the first tip reaches KIc) -> solve + SIFs
    -> advance the tips (MTS direction, Paris-type lengths, L_min rule)
    -> join/stop tips at fractures and the boundary -> next step.

summary.json is rewritten after every step; a failure keeps every finished
step and says "failed: <reason>".
"""
from __future__ import annotations

import contextlib

import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .. import _kernels as K
from ..errors import ComputationError
from .critical_load import critical_load_factor
from .fracture_set import FractureSet
from .growth_law import STRAIGHT, advances
from . import checkpoint, interrupt
from .joining import place_tip
from meshing.admissibility import TIP_CLEARANCE
from ..results import LastSolve, dataframe, tip_rows
from ..adaptivity import next_sizes
from ..parallel import snap

#: the join distance, in rosette radii (see joining.py)
REACH = TIP_CLEARANCE
#: relative tolerance of "K_eq reached KIc". Tips that the discretisation
#: cannot tell apart (displacement correlation is ~1e-3 accurate; the two
#: tips of the symmetric disc differ by ~3e-5 on an unsymmetric mesh) grow
#: together, as the symmetric physics says.
KEQ_RTOL = 1e-3
#: kink angles (rad) and advances (in propagation.length) are rounded to
#: these grids before the geometry is built (parallel.snap: 1 and N
#: processes then build the same geometry; with SIF round-off ~1e-13 a
#: rounding boundary separates them with probability ~1e-5 a tip and step).
#: 1e-8 rad moves a 1 mm step's end by 1e-11 m.
ANGLE_GRID = 1e-8
LENGTH_GRID = 1e-8


@dataclass
class RunResult(LastSolve):
    """A propagation run: status, steps (dicts as in summary.json), the final
    fracture set, and the last step's crack mesh, problem and contact.
    .tips, .polylines, .to_dataframe(), .dolfinx_mesh, .displacement."""
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


def _homogeneous(case, fset) -> bool:
    """Does the whole response scale with the load factor?"""
    m = case.material
    body = m.density * np.linalg.norm(case.body.gravity)
    return (case.propagation.load == "scale" and not np.any(case.stress.tensor())
            and body == 0 and all(f.gap == 0 for f in fset.fractures))


def _grow_index(cm, fset):
    """Indices into cm.tips of the tips that may grow."""
    active = set(fset.active_tips())
    return [i for i, t in enumerate(cm.tips) if (int(t.fracture), int(t.end)) in active]


def run(case, out=None, quiet: bool = True, progress=None, mesh_timeout: float | None = 120.0,
        resume: bool = False) -> RunResult:
    """Grow the case's fractures; see the module doc. `progress(step, info)`
    is called after every step (the CLI's progress bar). With `resume`, go
    on from the checkpoint in `out` (see checkpoint.py). Ctrl-C (SIGINT)
    stops at once with status "stopped: interrupted" (SIGTERM: "stopped:
    terminated"), every finished step kept, and raises KeyboardInterrupt
    (interrupt.Terminated) again."""
    with interrupt.watching(), _collector_skips_modules():
        return _run(case, out, progress, mesh_timeout, resume)


@contextlib.contextmanager
def _collector_skips_modules():
    """Every step ends with a full garbage collection (see _release), which
    scanned the ~120k objects of the imported modules each time: 36 ms a
    step on the disc. The modules are imported first and their objects
    frozen (gc.freeze: never scanned, never collected) for the run."""
    import gc

    import dolfinx.fem.petsc  # noqa: F401 - the heavy imports, before freezing
    import ufl  # noqa: F401

    from ..fem import elasticity, interaction_integral  # noqa: F401

    gc.freeze()
    try:
        yield
    finally:
        gc.unfreeze()


def _run(case, out, progress, mesh_timeout, resume) -> RunResult:
    from mpi4py import MPI

    from ..api import _Timer, _summary, all_sifs, build
    from ..io.summary import write_summary

    comm = MPI.COMM_WORLD
    out = None if out is None else Path(out)   # made ready by api.run
    fset = FractureSet.from_case(case)
    mat, prop = case.material, case.propagation
    Eprime = mat.E if mat.plane == "stress" else mat.E / (1 - mat.nu ** 2)
    h = case.mesh.tip_size
    lam = 0.0 if prop.load == "scale" else 1.0
    steps, status = [], "finished"
    last = (None, None, None)
    sizes = None   # the error-estimate size field for the next mesh (mesh.adaptive)
    first = 0
    if resume:
        if out is None:
            raise ValueError("resume needs the output folder of the run")
        ck = checkpoint.load(out, case)
        fset, lam, steps, sizes, first = ck["fset"], ck["load_factor"], ck["steps"], ck["sizes"], ck["step"] + 1

    done = {"fset": fset.copy()}   # the fractures after the last finished step

    def summary_now(st):
        s = _summary(case, st, steps)
        s["fractures"] = [{"points": np.asarray(p, float).tolist(), "origin": o, "fracture": i}
                          for i, f in enumerate(done["fset"].fractures) for p, o in f.pieces()]
        return s

    def write(st):
        if out is not None and comm.rank == 0:
            write_summary(out / "summary.json", summary_now(st))

    k = first
    for k in range(first, prop.steps):
        timer = _Timer()
        try:
            interrupt.check()
            if not fset.active_tips():
                status = "stopped: no tip can grow (every tip joined, at the boundary or not growing)"
                break
            _release(last[1])   # the previous step's factors and forms
            last = (None, None, None)
            cm, problem, contact = build(case, fset.fractures, timer,
                                         mesh_kwargs={"timeout": mesh_timeout, "sizes": sizes})
            last = (cm, problem, contact)
            interrupt.check()
            grow = _grow_index(cm, fset)
            if not grow:
                status = "stopped: no tip can grow (every tip joined, at the boundary or not growing)"
                break

            def keq(load):
                contact.solve(load)
                KI, KII = _correlation(case, cm, problem)
                th = K.mts_angle(KI[grow], KII[grow])
                return float(np.max(K.equivalent_k(KI[grow], KII[grow], th)))

            if prop.load == "scale":
                crit = critical_load_factor(keq, mat.KIc, lam, _homogeneous(case, fset), prop.max_load_factor)
                if crit.load_factor is None:
                    status = f"stopped: no tip reaches KIc below the load factor limit {prop.max_load_factor:g}"
                    break
                lam = crit.load_factor
            contact.solve(lam)
            timer.lap("solve")
            interrupt.check()
            tips = all_sifs(case, cm, problem, contact, fset.polylines())
            timer.lap("sif")

            # -- growth ---------------------------------------------------
            keqs = np.array([tips[i].K_eq for i in grow])
            reached = keqs >= mat.KIc * (1 - KEQ_RTOL)
            if prop.load == "fixed" and not reached.any():
                # the solved step is a result too: recorded with its files, no growth
                status = "stopped: no tip reaches KIc under the fixed load"
                steps.append(_record(out, k, lam, cm, problem, contact, tips, timer, solves=1))
                break
            G = np.where(reached, keqs ** 2 / Eprime, 0.0)
            theta = snap([tips[i].theta for i in grow], ANGLE_GRID)
            L = snap(advances(G, prop.length, prop.alpha, 0.4 * h, theta), LENGTH_GRID * prop.length)
            states = {i: "arrested" for i in range(len(tips))}
            adv = {i: 0.0 for i in range(len(tips))}
            for j, i in enumerate(grow):
                if L[j] <= 0:
                    continue
                t = tips[i]
                f = fset.fractures[t.fracture]
                if f.ends[t.end] != "tip":
                    continue   # met end to end by a tip that grew before it in this step
                tipinfo = cm.tips[i]
                d = np.cos(theta[j]) * np.asarray(tipinfo.ex) + np.sin(theta[j]) * np.asarray(tipinfo.ey)
                p, state = place_tip(fset, t.fracture, t.end, d, L[j], case.domain, REACH * h)
                if state == "joined" and _on_own_fracture(f, t.end, p):
                    continue   # a kink folding back onto its own crack would cut out a free sliver: no growth
                if state == "joined":   # on another fracture's growing end: link them end to end
                    p = _meet_tip_to_tip(fset, t.fracture, p, REACH * h)
                a = f.tip(t.end)
                if abs(theta[j]) <= STRAIGHT and state == "tip" and L[j] < 0.4 * h:
                    f.move_tip(t.end, p)       # straight on: move the tip node
                else:
                    f.extend(t.end, p)
                f.ends[t.end] = state
                states[i] = "growing" if state == "tip" else state
                adv[i] = float(np.linalg.norm(p - a))
            timer.lap("growth")
            interrupt.check()
            _check_no_crossing(fset)
            if case.mesh.adaptive:
                sizes = next_sizes(problem, h, case.mesh.size)
                timer.lap("estimate")
            step = _record(out, k, lam, cm, problem, contact, tips, timer,
                           solves=int(crit.solves) if prop.load == "scale" else 1, states=states, advances=adv)
            with interrupt.deferred():   # the step is committed whole: summary and checkpoint agree
                steps.append(step)
                done["fset"] = fset.copy()
                write("running" if k < prop.steps - 1 else status)
                if out is not None and comm.rank == 0:
                    checkpoint.save(out, case, k, fset, lam, steps, sizes)
            if progress is not None:
                progress(k, step)
        except KeyboardInterrupt as err:   # Ctrl-C or SIGTERM
            status = interrupt.stop_status(err)
            write(status)
            raise
        except ComputationError as err:
            status = f"failed: step {k}: {err}"
            write(status)
            raise ComputationError(status) from None
        except (RuntimeError, ValueError, np.linalg.LinAlgError) as err:
            status = f"failed: step {k}: {' '.join(str(err).split())}"
            write(status)
            raise ComputationError(status) from None
    write(status)
    result = RunResult(status, steps, fset, summary_now(status), out, mesh=last[0], problem=last[1], contact=last[2])
    if out is not None:
        result.files = _files(out, len(steps))
    return result


def _release(problem):
    """Free the previous step's objects now: the MUMPS factors (tens of MB a
    step) are destroyed explicitly, and DOLFINx objects sit in reference
    cycles that Python's collector, blind to their C++ memory, would keep."""
    import gc

    if problem is not None:
        problem.destroy()
    with interrupt.deferred():   # a KeyboardInterrupt inside a GC callback would be lost
        gc.collect()


class _Sol:
    def __init__(self, cm, contact):
        self.cm, self.contact = cm, contact


def _correlation(case, cm, problem):
    from ..tip_sifs import correlation_sifs

    m = case.material
    return correlation_sifs(problem, cm, m.E, m.nu, m.plane)


def _on_own_fracture(f, end, p) -> bool:
    """Is the join point `p` on the growing fracture's own polyline (beyond
    the segment at the tip)? Joining there closes a loop around a piece of
    the body that nothing holds."""
    pts = f.points[:-1] if end == 1 else f.points[1:]
    if len(pts) < 2:
        return False
    scale = float(np.ptp(f.points, axis=0).max()) or 1.0
    return K.point_polyline_distance(np.asarray(p, float), pts) <= 1e-9 * scale


def _meet_tip_to_tip(fset, fi, p, reach):
    """A join point within `reach` of another fracture's free end (a tip)
    would leave that tip's rosette no room: the two meet at that end, which
    stops growing too ("joined"). Returns the join point."""
    for g, other in enumerate(fset.fractures):
        if g == fi:
            continue
        for e in (0, 1):
            if other.ends[e] == "tip" and np.linalg.norm(other.tip(e) - p) <= reach:
                other.ends[e] = "joined"
                return other.tip(e).copy()
    return p


def crossing_pair(polys):
    """(i, j) of the first two polylines that cross (touching at a T or an
    end is not crossing), or None."""
    for i in range(len(polys)):
        for j in range(i + 1, len(polys)):
            a, b = polys[i], polys[j]
            for s in range(len(a) - 1):
                for r in range(len(b) - 1):
                    hit, t, u, _ = K.segment_intersection(a[s], a[s + 1], b[r], b[r + 1], 1e-12)
                    if hit and 1e-9 < t < 1 - 1e-9 and 1e-9 < u < 1 - 1e-9:
                        return i, j
    return None


def _check_no_crossing(fset):
    """Fractures never cross (they may touch at T-junctions)."""
    pair = crossing_pair(fset.polylines())
    if pair is not None:
        raise ComputationError(f"fractures {pair[0]} and {pair[1]} cross")


def _record(out, k, lam, cm, problem, contact, tips, timer, solves, states=None, advances=None) -> dict:
    """The summary record of solved step k (tip states and advances when it
    grew), its field files written when there is an output folder."""
    from ..api import _step, contact_summary

    step = _step(k, lam, problem.fm.num_dofs, problem.fm.num_cells, tips,
                 dict(timer.seconds), contact_summary(_Sol(cm, contact)))
    if states is not None:
        for i, td in enumerate(step["tips"]):
            td["state"], td["advance"] = states[i], advances[i]
    step["mesh"] = {n: cm.stats[n] for n in ("min_quality", "min_jacobian", "nodes", "tips", "gmsh_retried", "symmetric")}
    step["solves"] = solves
    if out is not None:
        _write_step_fields(out, k, lam, cm, problem, contact)
        timer.lap("output")
        step["seconds"]["output"] = round(timer.seconds["output"], 6)
    step["seconds"]["total"] = round(sum(timer.seconds.values()), 6)
    return step


def _write_step_fields(out, k, load_factor, cm, problem, contact):
    """step_XXXX.vtu and faces_XXXX.vtu of step k (with the step and its
    load factor as field data), and the two ParaView indices over steps
    0..k, rewritten so that an interrupted run keeps a complete index."""
    from mpi4py import MPI

    from ..api import Solution
    from ..io.faces import write_faces
    from ..io.fields import write_fields
    from ..io.outdir import FACES_PVD, FIELDS_PVD, faces_name, fields_name
    from ..io.pvd import write_pvd

    about = {"step": k, "load_factor": load_factor}
    write_fields(out / fields_name(k), problem, cm, field_data=about)
    write_faces(out / faces_name(k), Solution(cm, problem, contact, []), field_data=about)
    if MPI.COMM_WORLD.rank == 0:
        write_pvd(out / FIELDS_PVD, [fields_name(j) for j in range(k + 1)])
        write_pvd(out / FACES_PVD, [faces_name(j) for j in range(k + 1)])


def _files(out, n) -> dict:
    """What a run wrote (pictures are added by api.run)."""
    from ..io.outdir import FACES_PVD, FIELDS_PVD, SUMMARY, faces_name, fields_name

    def span(name):   # step_{0000..0014}.vtu
        return name(0) if n == 1 else name(0).replace("0000", f"{{0000..{n - 1:04d}}}")

    files = {"summary": out / SUMMARY}
    if n:   # one field file and one face file per step, and their indices
        files.update(fields=out / span(fields_name), faces=out / span(faces_name),
                     fields_pvd=out / FIELDS_PVD, faces_pvd=out / FACES_PVD)
    return files
