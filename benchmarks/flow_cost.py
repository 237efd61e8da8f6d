"""What a time step of the flow along the fractures costs against an
elastic solve of the same mesh (`make bench`; alone: a table).

On each case's first geometry, paired in one process (a shared machine's
load moves both alike):
- the elastic solve: the FE problem assembled and factorised with its
  contact problem, and one solve with contact (step.discretise's assemble,
  factorize and contact phases, and Solver.solve) - what a step of any run
  does on its mesh;
- the flow's set-up on that geometry (the faces' compliance in the pairs'
  jump space, the loads the pressure leaves: once a geometry);
- a time step: the coupled backward-Euler step on the faces (its Newton
  iterations, the contact solved on the faces), the whole displacement at
  its pressure and the tips' K_eq (a growth event's test), the median over
  the run's steps up to the case's first frame.

    python benchmarks/flow_cost.py [--cases fault ...]
"""
from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT / "tests")]

from builders import flowing_fault, flowing_kgd  # noqa: E402


def cases() -> dict:
    """{name: case table}: a fault of 250 face pairs, one of 1,100 (the
    fluid-driven slip of the verification at T = 0.5 and 0.9), the KGD
    with a flowing fluid."""
    return {"fault 250 pairs": flowing_fault(half_length=57.0, frames=1, end_time=0.4),
            "fault 1,100 pairs": flowing_fault(half_length=268.0, frames=1, end_time=2.0),
            "KGD": flowing_kgd(steps=1)}


def measure(name: str, table: dict) -> dict:

    from wingcrack.case import Case
    from wingcrack.propagation import flow_march
    from wingcrack.propagation.fracture_set import FractureSet
    from wingcrack.step import Timer, discretise

    case = Case.from_dict(table)
    fset = FractureSet.from_case(case)
    timer = Timer()
    disc = discretise(case, fset.fractures, timer)
    t0 = time.perf_counter()
    disc.solver.solve(1.0)
    solve = time.perf_counter() - t0
    elastic = sum(timer.seconds.get(k, 0.0) for k in ("assemble", "factorize", "contact", "patch")) + solve
    drive = flow_march.FlowDrive.of(case)
    t0 = time.perf_counter()
    geo = flow_march.Geometry.of(drive, case, disc, fset.fractures)
    setup = time.perf_counter() - t0
    steps = []
    out = flow_march.Outcome("end", 0.0)
    state, t, dt = geo.state, 0.0, flow_march.FIRST * drive.frames[0]
    while t < drive.frames[0] * (1 - 1e-12) and len(steps) < 40:
        t_next = min(t + dt, float(drive.frames[0]))
        t0 = time.perf_counter()
        new, dt_used = flow_march._step(drive, geo, state, t_next, out)
        geo.faces.complete(new.pressure)
        disc.solver.accept()
        steps.append(time.perf_counter() - t0)
        state, t, dt = new, new.time, 1.5 * dt_used
    disc.solver.release()
    step = statistics.median(steps)
    return {"name": name, "pairs": len(disc.cm.pairs), "dofs": disc.dofs, "elastic": elastic, "setup": setup,
            "step": step, "steps": len(steps), "solves": out.solves / max(len(steps), 1),
            "ratio": step / elastic}


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", nargs="*", help="of: " + ", ".join(cases()))
    args = ap.parse_args(argv)
    chosen = {k: v for k, v in cases().items() if not args.cases or k in args.cases}
    print("| case | DOFs | face pairs | elastic solve (s) | flow set-up (s) | time step (s, median of) | "
          "mechanics solves a step | time step / elastic solve |")
    print("|---|---|---|---|---|---|---|---|")
    for name, table in chosen.items():
        r = measure(name, table)
        print(f"| {name} | {r['dofs']} | {r['pairs']} | {r['elastic']:.3f} | {r['setup']:.3f} | "
              f"{r['step']:.4f} ({r['steps']}) | {r['solves']:.2f} | {r['ratio']:.3f} |")


if __name__ == "__main__":
    main()
