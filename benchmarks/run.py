"""`make bench`: per-phase timings of wingcrack solves (not a test).

Runs `wingcrack.sif` on the 45-degree Brazilian disc at about 30,000 DOFs,
once to compile the forms and then REPEAT times, and prints the phases
(mesh, to-DOLFINx, assemble, factorize, solve, SIF, output) with their share.
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


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args(argv)
    bench_sif(args.repeat)


if __name__ == "__main__":
    sys.exit(main())
