"""`make bench`: the benchmark report (not a test; no timing is asserted).

Prints, each section marked:
- one `wingcrack.sif` on the 45-degree Brazilian disc at about 30,000 DOFs,
  once to compile the forms and then REPEAT times: its phases with their share;
  contact and Coulomb friction against the plain solve on that mesh; the mesher
  alone on the disc (mesh_disc.py);
- every case of cases/ end to end, with the issue's phases per step and the
  ratios to today (cases.py, against benchmarks/baseline.json);
- what friction changes in the cases (friction_cases.py) and what injection
  changes in paper 4.3 (pressure_cases.py), read from those same runs, and
  what a step of a pumped run costs against the given pressure
  (injection_cost.py);
- each Coulomb case's friction solves against the frictionless solve of the
  same pair system, and its worst step against its median (friction_solve.py);
- what the pictures cost: the disc run with pictures over --no-plots, paired
  (pictures_cost.py);
- what a time step of the flow along the fractures costs against an elastic
  solve of the same mesh (flow_cost.py);
- issue 16's targets 1-3 (targets.py; 3, the 1.10M DOF step, with --large);
- with --large, the 1,000-fracture network through `sif` (grid_network.py:
  3.75M DOFs, the contact by the saddle route; its phases and each
  factorisation and update of its sets; 4-5 minutes, 10-12 GB);
- the 30k-300k DOF scaling on 1 and 2 MPI ranks (scaling.py), with the 1M
  point of target 3 when --large ran it.

    python benchmarks/run.py [--repeat N] [--large] [--cases NAME ...] [--keep DIR]
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


def bench_friction(repeat: int):
    """Coulomb friction against frictionless contact on the same 45-degree
    disc mesh (~30k DOFs): one factorisation with the Schur complement on
    the pair dofs serves both laws; the contact solve (elastic solve + pair
    iterations + response) and the whole solve with the factorisation, as
    ratios to frictionless contact, with the iterations."""
    import time
    from dataclasses import replace

    from wingcrack.case import Case
    from wingcrack.contact.constraints import constraint_rows
    from wingcrack.fem.contact_problem import ContactProblem
    from wingcrack.fem.elasticity import ElasticProblem
    from wingcrack.fem.pair_operator import PairOperator
    from wingcrack.loads import case_loads
    from wingcrack.step import solve_initial

    base = Case.from_toml(ROOT / "cases" / "brazilian_disc_45.toml")
    base = replace(base, mesh=replace(base.mesh, size=0.0014))
    laws = {"frictionless": base}
    for mu in (0.3, 0.6):
        laws[f"coulomb mu = {mu}"] = replace(base, fractures=[replace(f, faces="coulomb", friction=mu, cohesion=0.0)
                                                               for f in base.fractures])
    sol = solve_initial(base)   # compiles the forms
    fm, m = sol.problem.fm, base.material
    loads = case_loads(base, sol.cm)
    rows = {name: constraint_rows(sol.cm, case.fractures) for name, case in laws.items()}
    fac, solve, its = [], {name: [] for name in laws}, {}
    for _ in range(repeat):
        p = ElasticProblem(fm, m.E, m.nu, m.plane, loads)
        t0 = time.perf_counter()
        p.factorize(schur_dofs=PairOperator.pair_dofs(fm, rows["frictionless"]))
        fac.append(time.perf_counter() - t0)
        contacts = {name: ContactProblem(p, r) for name, r in rows.items()}   # each S before any solve
        for name, contact in contacts.items():
            t0 = time.perf_counter()
            res = contact.solve(1.0)
            solve[name].append(time.perf_counter() - t0)
            its[name] = res.iterations
        p.destroy()
    f = statistics.median(fac)
    print(f"\n45-degree disc, Coulomb friction against frictionless contact: {fm.num_dofs} DOFs; "
          f"factorisation with the Schur complement {f:.3f} s, shared (median of {repeat})")
    t0 = statistics.median(solve["frictionless"])
    for name in laws:
        t = statistics.median(solve[name])
        print(f"  {name:18s} {len(rows[name]):4d} rows {its[name]:3d} iterations  solve {t:.4f} s  "
              f"/ frictionless {t / t0:5.2f}   with the factorisation {(f + t) / (f + t0):5.2f}")


def section(title: str) -> None:
    print(f"\n{'=' * 100}\nBENCHMARK: {title}\n{'=' * 100}", flush=True)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--large", action="store_true",
                    help="target 3 too (a step at 1.10M DOFs on 1 and 2 ranks), and the 1,000-fracture network")
    ap.add_argument("--cases", nargs="+", help="these cases of cases/ only (default: every one)")
    ap.add_argument("--keep", type=Path, help="keep the case results in this folder")
    args = ap.parse_args(argv)

    import cases
    import targets
    from friction_cases import main as friction_table
    from friction_solve import coulomb_cases, main as friction_solve
    from flow_cost import main as flow_cost
    from injection_cost import main as injection_cost
    from mesh_disc import main as bench_mesh
    from pictures_cost import main as pictures_cost
    from pressure_cases import main as pressure_table
    from ratios import load_baseline
    from scaling import TARGETS, main as bench_scaling

    names = args.cases or cases.case_names()
    unknown = [n for n in names if n not in cases.case_names()]
    if unknown:
        ap.error(f"--cases: no such case in cases/: {', '.join(unknown)}")

    print("wingcrack benchmark report (make bench): wall-clock figures of this machine now, "
          "not a test; the machine may be shared")
    section("one solve of the 45-degree disc at ~30k DOFs: phases, contact, friction, the mesher")
    bench_sif(args.repeat)
    bench_contact(args.repeat)
    bench_friction(args.repeat)
    bench_mesh(args.repeat)
    baseline = load_baseline()
    with tempfile.TemporaryDirectory() as tmp:
        out = args.keep or Path(tmp)
        section(f"every case of cases/ end to end ({len(names)}), against today")
        runs = cases.run_all(names, out / "cases")
        cases.report(runs, baseline)
        section("what friction changes, what injection changes (the same runs)")
        friction_table([str(out / "cases")], runs=runs)
        pressure_table([str(out / "cases")], runs=runs)
        section("a step of a pumped run against the same case under a given pressure (the same runs)")
        injection_cost(runs=runs)
        chosen = [n for n in names if n in coulomb_cases()]
        if chosen:
            section("the friction solve against the frictionless one, and the worst step, per Coulomb case")
            friction_solve(["--cases"] + chosen)
        section("what the pictures cost: the 45-degree disc, 34 steps, with pictures / --no-plots, paired")
        pictures_cost(["--repeat", str(args.repeat)])
        section("a time step of the flow along the fractures against an elastic solve of the same mesh")
        flow_cost([])
        section("issue 16, targets 1-3" if args.large else "issue 16, targets 1-2 (3 with --large)")
        print(baseline.get("about", "?"))
        tdir = out / "targets"
        tdir.mkdir(parents=True, exist_ok=True)
        base_targets = baseline.get("targets", {})
        targets.disc_34(tdir, base_targets)
        targets.fine_disc(tdir, base_targets)
        large = targets.large(tdir, base_targets) if args.large else None
        if args.large:
            import subprocess

            section("the 1,000-fracture network, sif (grid_network.py): phases and the saddle-point sets")
            subprocess.run([sys.executable, str(ROOT / "benchmarks" / "grid_network.py"), "--sif",
                            str(out / "network")], check=False)
    section("scaling: one step at 30k-300k DOFs" + (" and target 3's 1M" if large else "") + ", 1 and 2 ranks")
    bench_scaling(["--sizes"] + [str(n) for n in TARGETS if n < targets.LARGE_DOFS], extra=large)
    print(f"\n{'=' * 100}\nEND of the benchmark report\n{'=' * 100}")


if __name__ == "__main__":
    sys.exit(main())
