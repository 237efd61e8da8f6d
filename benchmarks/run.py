"""`make bench`: per-phase timings of wingcrack solves (not a test).

Runs `wingcrack.sif` on the 45-degree Brazilian disc at about 30,000 DOFs,
once to compile the forms and then REPEAT times, and prints the phases
(mesh, to-DOLFINx, assemble, factorize, solve, SIF, output) with their share;
then the mesher alone on the disc (mesh_disc.py), the propagation cases
(propagation.py) and the 30k-1M DOF scaling on 1 and 2 MPI ranks (scaling.py).
"""
from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def disc_case(tip_size=0.0005, size=0.0014):
    from dataclasses import replace
    from wingcrack.case import Case
    case = Case.from_toml(ROOT / "cases" / "brazilian_disc_45_open.toml")
    return replace(case, mesh=replace(case.mesh, size=size, tip_size=tip_size))


def bench_sif(repeat: int):
    import wingcrack
    case = disc_case()
    with tempfile.TemporaryDirectory() as tmp:
        first = wingcrack.sif(case, out=Path(tmp) / "warm")
        runs = [wingcrack.sif(case, out=Path(tmp) / f"r{i}") for i in range(repeat)]
    phases = list(runs[0].seconds)
    med = {p: statistics.median(r.seconds[p] for r in runs) for p in phases}
    total = med["total"]
    print(f"\n45-degree Brazilian disc, wingcrack sif: {runs[0].dofs} DOFs, {runs[0].cells} cells, "
          f"median of {repeat} runs after a compiling run ({first.seconds['total']:.2f} s)")
    for p in phases:
        if p == "total":
            continue
        print(f"  {p:12s} {med[p]:8.3f} s  {100 * med[p] / total:5.1f} %")
    solve_only = med["assemble"] + med["factorize"] + med["solve"]
    print(f"  {'total':12s} {total:8.3f} s")
    print(f"  the solve (assemble + factorize + solve) {solve_only:.3f} s; "
          f"factorization share of it {100 * med['factorize'] / solve_only:.0f} %")


def bench_contact(repeat: int):
    """Contact on the 45-degree disc at ~30k DOFs: factorisation with the
    Schur complement on the pair dofs, the pair system, the active-set
    iterations, and the ratio of the contact solve to the plain solve
    (factorise + solve) on the same mesh."""
    import time
    from dataclasses import replace

    from wingcrack.step import solve_initial
    from wingcrack.case import Case
    from wingcrack.fem.contact_problem import ContactProblem
    from wingcrack.fem.elasticity import ElasticProblem
    from wingcrack.fem.pair_operator import PairOperator
    from wingcrack.loads import case_loads

    case = Case.from_toml(ROOT / "cases" / "brazilian_disc_45.toml")
    case = replace(case, mesh=replace(case.mesh, size=0.0014))
    m = case.material
    sol = solve_initial(case)  # compiles the forms
    fm, rows = sol.problem.fm, sol.contact.rows
    loads = case_loads(case, sol.cm)
    runs = []
    for _ in range(repeat):
        plain = ElasticProblem(fm, m.E, m.nu, m.plane, loads)
        t0 = time.perf_counter()
        plain.factorize()
        plain.solve(1.0)
        t1 = time.perf_counter()
        cp = ElasticProblem(fm, m.E, m.nu, m.plane, loads)
        t2 = time.perf_counter()
        cp.factorize(schur_dofs=PairOperator.pair_dofs(fm, rows))
        t3 = time.perf_counter()
        contact = ContactProblem(cp, rows)
        t4 = time.perf_counter()
        res = contact.solve(1.0)
        t5 = time.perf_counter()
        runs.append((t1 - t0, t3 - t2, t4 - t3, t5 - t4, res.iterations))
    plain_t, fac, op_t, as_t, its = [statistics.median(r[i] for r in runs) for i in range(5)]
    contact_t = fac + op_t + as_t
    print(f"\n45-degree disc with frictionless contact: {fm.num_dofs} DOFs, {len(rows)} constraint rows, "
          f"{int(its)} active-set iteration(s); median of {repeat}")
    print(f"  plain: factorize + solve                  {plain_t:8.3f} s")
    print(f"  contact: factorize with Schur complement  {fac:8.3f} s")
    print(f"           pair compliance S                {op_t:8.4f} s   (once per mesh)")
    print(f"           solve + active set + response    {as_t:8.4f} s   ({as_t / max(its, 1):.4f} s per iteration)")
    print(f"  contact / plain                           {contact_t / plain_t:8.2f}")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args(argv)
    bench_sif(args.repeat)
    bench_contact(args.repeat)
    from mesh_disc import main as bench_mesh
    bench_mesh(args.repeat)
    from propagation import main as bench_propagation
    bench_propagation()
    from scaling import main as bench_scaling
    bench_scaling([])


if __name__ == "__main__":
    sys.exit(main())
