"""What a time step of the flow along the fractures costs against an
elastic solve of the same mesh (`make bench`; alone: a table).

On each case's first geometry, paired in one process (a shared machine's
load moves both alike), after a first discretisation that compiles or
loads the forms:
- the elastic solve: the FE problem assembled and factorised with its
  contact problem, and one solve with contact (step.discretise's assemble,
  factorize and contact phases, and Solver.solve) - what a step of any run
  does on its mesh;
- the flow's set-up on that geometry (the faces' compliance in the pairs'
  jump space, the loads the pressure leaves: once a geometry);
- a time step: the coupled backward-Euler step on the faces (its Newton
  iterations, the contact solved on the faces; its own column), the whole
  displacement at its pressure and the tips' SIFs (K_eq: a growth event's test),
  the median over the run's steps up to the case's first frame.

The issue's bound: a time step at most 2x the elastic solve. A geometry's
first time step carries the set-up too (a grown mesh's), given as its own
ratio.

    python benchmarks/flow_cost.py [--cases fault ...] [--json FILE]
"""
from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import results_file

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT / "tests")]

from builders import flowing_fault, flowing_kgd  # noqa: E402

#: the bound on a time step over the elastic solve of the same mesh
BOUND = 2.0


def cases() -> dict:
    """{name: case table}: a fault of 250 face pairs, one of 1,100 (the
    fluid-driven slip of the verification at T = 0.5 and 0.9), the KGD
    with a flowing fluid."""
    return {"fault 250 pairs": flowing_fault(half_length=57.0, frames=1, end_time=0.4),
            "fault 1,100 pairs": flowing_fault(half_length=268.0, frames=1, end_time=2.0),
            "KGD": flowing_kgd(steps=1)}


def measure(name: str, table: dict) -> dict:
    # lazy: DOLFINx, which doc_tables.py (this module's table for the docs) does without
    from wingcrack import sifs
    from wingcrack.case import Case
    from wingcrack.propagation import flow_march
    from wingcrack.propagation.fracture_set import FractureSet
    from wingcrack.step import Timer, discretise

    case = Case.from_dict(table)
    fset = FractureSet.from_case(case)
    discretise(case, fset.fractures, Timer()).solver.release()   # the forms compiled or loaded: not the mesh's cost
    timer = Timer()
    disc = discretise(case, fset.fractures, timer)
    t0 = time.perf_counter()
    disc.solver.solve(1.0)
    solve = time.perf_counter() - t0
    elastic = sum(timer.seconds.get(k, 0.0) for k in ("assemble", "factorize", "contact", "patch")) + solve
    drive = flow_march.FlowDrive.of(case)
    polylines = fset.polylines()
    t0 = time.perf_counter()
    geo = flow_march.Geometry.of(drive, case, disc, fset.fractures)
    setup = time.perf_counter() - t0
    steps, faces = [], []   # a time step's seconds, and those of its coupled flow on the faces
    out = flow_march.Outcome("end", 0.0)
    state, t, dt = geo.state, 0.0, flow_march.FIRST * drive.frames[0]
    while t < drive.frames[0] * (1 - 1e-12) and len(steps) < 40:
        t_next = min(t + dt, float(drive.frames[0]))
        t0 = time.perf_counter()
        new, dt_used = flow_march._step(drive, geo, state, t_next, out)
        t1 = time.perf_counter()
        geo.faces.complete(new.pressure)
        sifs.driving(case, disc, polylines)   # the tips' SIFs: K_eq, the growth event's test
        disc.solver.accept()
        steps.append(time.perf_counter() - t0)
        faces.append(t1 - t0)
        state, t, dt = new, new.time, 1.5 * dt_used
    disc.solver.release()
    step = statistics.median(steps)
    on_faces = statistics.median(faces)
    return {"name": name, "pairs": len(disc.cm.pairs), "dofs": disc.dofs, "elastic": round(elastic, 4),
            "setup": round(setup, 4), "step": round(step, 5), "faces": round(on_faces, 5), "steps": len(steps),
            "solves": round(out.solves / max(len(steps), 1), 3), "ratio": round(step / elastic, 4),
            "first_ratio": round((setup + step) / elastic, 4)}


HEADER = ["| case | DOFs | face pairs | elastic solve (s) | flow set-up (s) | time step (s, median of) | "
          "of it the flow on the faces (s) | mechanics solves a step | time step / elastic solve | "
          "set-up + time step / elastic solve |",
          "|---|---|---|---|---|---|---|---|---|---|"]


def row(r: dict) -> str:
    return (f"| {r['name']} | {r['dofs']} | {r['pairs']} | {r['elastic']} | {r['setup']} | {r['step']} ({r['steps']}) | "
            f"{r['faces']} | {r['solves']} | {r['ratio']:.3f} | {r['first_ratio']:.3f} |")


def main(argv=None) -> list:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", nargs="*", help="of: " + ", ".join(cases()))
    ap.add_argument("--json", type=Path, help="also write the figures here (benchmarks/flow_cost.json)")
    args = ap.parse_args(argv)
    chosen = {k: v for k, v in cases().items() if not args.cases or k in args.cases}
    print("\n".join(HEADER), flush=True)
    load = [results_file.load()]
    rows = []
    for name, table in chosen.items():
        rows.append(measure(name, table))
        print(row(rows[-1]), flush=True)
    load.append(results_file.load())
    worst = max(r["ratio"] for r in rows)
    print(f"  the largest time step / elastic solve {worst:.3f}; bound <= {BOUND:g}: "
          f"{'met' if worst <= BOUND else 'not met'}; load average (1 min) {load[0]:g} before, {load[1]:g} after")
    if args.json:
        results_file.write(
            args.json, "a time step of the flow along the fractures against the elastic solve of the same mesh",
            "benchmarks/flow_cost.py: in one process, each case's first geometry: the elastic solve (assemble, "
            "factorise with the contact's Schur complement, the pair compliance, one contact solve), the flow's "
            "set-up (the faces' compliance and loads, once a geometry), and the median time step (the coupled "
            "backward-Euler step, then the whole displacement and the tips' SIFs) up to the first frame",
            load, bound=BOUND, cases=rows)
    return rows


if __name__ == "__main__":
    main()
