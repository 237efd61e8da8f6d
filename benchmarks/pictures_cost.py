"""What the pictures cost (not a test): the 45-degree disc
(cases/brazilian_disc_45.toml with propagation.steps = 34) run with its
pictures and with --no-plots, in turn (with, without, with, ...), each
run its own `wingcrack run` process; the ratio with / without of each
pair's process walls, so that a machine whose speed drifts moves both
runs of a pair alike. The issue's bound: at most 1.2x.

    python benchmarks/pictures_cost.py [--repeat N]
"""
from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
from pathlib import Path

from case_variant import write_variant
from propagation import ROOT, run_case

DISC = ROOT / "cases" / "brazilian_disc_45.toml"
STEPS = {"propagation.steps": 34}
#: the bound on a run with pictures over one without
BOUND = 1.2


def main(argv=None) -> list:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=3, help="pairs of runs (default 3)")
    args = ap.parse_args(argv)
    ratios = []
    with tempfile.TemporaryDirectory() as tmp:
        case = write_variant(DISC, STEPS, Path(tmp) / "disc_34_pictures.toml")
        for i in range(args.repeat):
            with_ = run_case("with", Path(tmp) / f"with_{i}", case=case, plots=True)
            without = run_case("without", Path(tmp) / f"without_{i}", case=case)
            for r in (with_, without):
                if r["exit"] != 0:
                    print(f"  run {r['name']} {i}: exit {r['exit']}: {r['stderr']}")
            ratios.append(with_["wall"] / without["wall"])
            print(f"  pair {i + 1}: with pictures {with_['wall']:.1f} s, without {without['wall']:.1f} s: "
                  f"{ratios[-1]:.2f}x")
    med = statistics.median(ratios)
    print(f"  pictures' cost on the disc ({DISC.name}, 34 steps): with / without {med:.2f}x (median of "
          f"{len(ratios)} pairs, {min(ratios):.2f}-{max(ratios):.2f}); bound <= {BOUND:g}x: "
          f"{'met' if med <= BOUND else 'not met'}")
    return ratios


if __name__ == "__main__":
    main(sys.argv[1:])
