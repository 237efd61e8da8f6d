"""A network of many short fractures, for timing the geometric check and the
mesher's planning (not a test): N straight fractures 0.022 m long, centred
on the nodes of a 0.06 m grid in a 2 m x 2 m plate, at random orientations
(seeded), tip_size 0.005 m. Neighbours are 0.038 m apart at the least, well
over the clearances (1.5 rosettes, 0.0075 m), so `check` accepts the case;
with --cross the nodes hold X's instead (two fractures 0.04 m long crossing
at 40 to 90 degrees), so that the intersection search has 500 junctions
to find and the rules to measure.

    .venv/bin/python benchmarks/grid_network.py                # times check and planning
    .venv/bin/python benchmarks/grid_network.py --write FILE   # writes the case
    .venv/bin/python benchmarks/grid_network.py --cross        # a network with crossings
    .venv/bin/python benchmarks/grid_network.py --sif OUTDIR   # runs `sif` on the Coulomb network
    .venv/bin/python benchmarks/grid_network.py --sif OUTDIR --base CHECKOUT [--pairs N] [--record FILE]

--sif: the scale case of the network issue (1,000 Coulomb fractures, friction
0.6, under 1 MPa of vertical compression) through `sif`, its phases' seconds
(summary.json), the contact solve's saddle-point work (fem.pair_saddle: each
factorisation's seconds, the first with MUMPS's analysis, and each set solved
by an update of the factorisation kept) and the process's peak memory printed.
With --base, N pairs of runs (the order turned every pair), each its own
process: this checkout's and CHECKOUT's (this script run by its .venv, so its
wingcrack), one at a time (10-12 GB each), the machine's load average noted at
each; --record writes the figures and the ratio of the medians as JSON (the
performance page's network table, benchmarks/doc_tables.py).

Printed: the seconds of Case.from_dict (everything `wingcrack check`
computes) and of meshing.start_crack_mesh up to gmsh (the plan: mouths,
junctions, crossings, rosettes, the point-symmetry search), best of
--repeat runs.
"""
from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

SEED = 20260301
PLATE = 2.0       # m
SPACING = 0.06    # m, between the centres
LENGTH = 0.022    # m
TIP = 0.005       # m, mesh.tip_size
SIZE = 0.05       # m, mesh.size
CROSS_LENGTH = 0.04   # m, the segments of an X (--cross)


def fractures(n: int = 1000, seed: int = SEED, cross: bool = False) -> list[list[list[float]]]:
    """n segments on the grid's nodes (the first of a seeded shuffle of the
    nodes inside the plate), random orientations. With `cross`, n/2 nodes
    each hold an X: two segments CROSS_LENGTH long crossing at their middles
    at 40 to 90 degrees (tips 0.013 m or more from the other segment and
    0.014 m from each other: over the clearances)."""
    rng = np.random.default_rng(seed)
    k = int(math.floor((PLATE - 2 * SPACING) / SPACING)) + 1
    grid = SPACING + SPACING * np.stack(np.meshgrid(np.arange(k), np.arange(k), indexing="ij"), axis=-1).reshape(-1, 2)
    nodes = (n + 1) // 2 if cross else n
    if nodes > len(grid):
        raise SystemExit(f"at most {len(grid) * (2 if cross else 1)} fractures fit the grid")
    c = grid[np.sort(rng.permutation(len(grid))[:nodes])]
    angle = rng.uniform(0.0, math.pi, nodes)
    if not cross:
        d = 0.5 * LENGTH * np.stack([np.cos(angle), np.sin(angle)], axis=1)
        return [[(c[i] - d[i]).tolist(), (c[i] + d[i]).tolist()] for i in range(n)]
    other = angle + np.radians(rng.uniform(40.0, 90.0, nodes))
    out = []
    for i in range(nodes):
        for phi in (angle[i], other[i])[: n - len(out)]:
            d = 0.5 * CROSS_LENGTH * np.array([math.cos(phi), math.sin(phi)])
            out.append([(c[i] - d).tolist(), (c[i] + d).tolist()])
    return out


def case(n: int = 1000, seed: int = SEED, cross: bool = False) -> dict:
    return {
        "title": f"grid network of {n} fractures",
        "material": {"E": 10e9, "nu": 0.25, "KIc": 1e6, "plane": "strain"},
        "domain": {"shape": "rectangle", "corner": [0.0, 0.0], "size": [PLATE, PLATE]},
        "fractures": [{"points": p, "faces": "frictionless"} for p in fractures(n, seed, cross)],
        "bc": [{"on": "bottom", "displacement": [0.0, 0.0]}, {"on": "top", "traction": [1e6, -1e6]}],
        "mesh": {"size": SIZE, "tip_size": TIP},
        "propagation": {"steps": 1, "length": TIP},
    }


def coulomb(d: dict) -> dict:
    """The network as the scale case: Coulomb faces, compression from the top, held below."""
    for f in d["fractures"]:
        f["faces"], f["friction"] = "coulomb", 0.6
    d["bc"] = [{"on": "top", "traction": [0.0, -1e6]}, {"on": "bottom", "displacement_y": 0.0},
               {"at": [0.0, 0.0], "displacement_x": 0.0}]
    d["mesh"]["size"] = 0.2
    return d


def sif(d: dict, out: Path, as_json: bool = False) -> dict:
    import json
    import resource

    import wingcrack
    from wingcrack.fem import pair_saddle

    from mpi4py import MPI

    work = {"factorisations": [], "updates": []}
    _time_sets(pair_saddle.PairSaddle, work)
    t0 = time.perf_counter()
    wingcrack.sif(wingcrack.Case.from_dict(d), out, force=True)
    wall = time.perf_counter() - t0
    peak = MPI.COMM_WORLD.allreduce(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)   # KiB, all ranks
    if MPI.COMM_WORLD.rank:
        return {}   # rank 0 writes the summary
    step = json.loads((out / "summary.json").read_text())["steps"][0]
    c = step["contact"]
    figures = {"wall": round(wall, 2), "phases": {k: round(v, 2) for k, v in step["seconds"].items()},
               "dofs": step["dofs"], "rows": c["rows"], "sets": c["iterations"], "processes": MPI.COMM_WORLD.size,
               "peak_gb": round(peak / 2**20, 2), **work}
    if as_json:
        print(json.dumps(figures))
        return figures
    phases = ", ".join(f"{k} {v:.1f}" for k, v in step["seconds"].items() if v >= 0.05)
    print(f"{len(d['fractures'])} Coulomb fractures: sif {wall:.1f} s ({phases}); {step['dofs']} DOFs, "
          f"{c['rows']} pair rows, {c['iterations']} active sets; {MPI.COMM_WORLD.size} process(es), "
          f"peak {peak / 2**20:.1f} GB (summed)")
    print("  saddle-point sets: factorised in " + ", ".join(f"{t:.1f}" for t in work["factorisations"])
          + " s (the first with the analysis); updated in "
          + (", ".join(f"{t:.1f} s ({r} rows)" for t, r in work["updates"]) or "none"))
    return figures


def _time_sets(cls, work: dict) -> None:
    """Wraps the saddle solver's set solves (this process only) to record
    each factorisation's seconds and each update's (seconds, rows changed)."""
    factorised, updated = cls._factorised, cls._updated

    def _factorised(self, low):
        t = time.perf_counter()
        x = factorised(self, low)
        work["factorisations"].append(round(time.perf_counter() - t, 2))
        return x

    def _updated(self, low):
        t, before = time.perf_counter(), self.updates
        x = updated(self, low)
        if self.updates > before:
            rows = -1 if low is None else \
                int(np.count_nonzero(np.add.reduceat(np.abs(low - self._factored), self._lower_pattern.indptr[:-1])))
            work["updates"].append((round(time.perf_counter() - t, 2), rows))
        return x

    cls._factorised, cls._updated = _factorised, _updated


def paired(out: Path, base: Path, pairs: int, n: int, seed: int) -> dict:
    """N pairs of `--sif` runs, this checkout's and base's, each its own
    process, alternately (the order turned every pair), one at a time."""
    import json
    import os
    import subprocess

    runs = {"this": [], "base": []}
    for k in range(pairs):
        order = (("this", ROOT), ("base", base)) if k % 2 == 0 else (("base", base), ("this", ROOT))
        for name, checkout in order:
            load = os.getloadavg()[0]
            proc = subprocess.run([str(checkout / ".venv" / "bin" / "python"), __file__, "-n", str(n), "--seed",
                                   str(seed), "--sif", str(out / f"{name}{k}"), "--json"],
                                  capture_output=True, text=True, check=True)
            figures = json.loads(proc.stdout.strip().splitlines()[-1])
            figures["load"] = [round(load, 2), round(os.getloadavg()[0], 2)]
            runs[name].append(figures)
            print(f"  {name:4s} sif {figures['wall']:6.1f} s, solve {figures['phases']['solve']:6.1f} s, "
                  f"{len(figures['factorisations'])} factorisations, {len(figures['updates'])} updates; load "
                  f"{figures['load'][0]} -> {figures['load'][1]}", flush=True)
    import statistics

    med = {name: statistics.median(r["wall"] for r in runs[name]) for name in runs}
    return {"runs": runs, "median_wall": med, "ratio": round(med["this"] / med["base"], 3)}


def best(f, repeat: int) -> float:
    out = math.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        f()
        out = min(out, time.perf_counter() - t0)
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-n", type=int, default=1000)
    ap.add_argument("--seed", type=int, default=SEED)
    ap.add_argument("--cross", action="store_true", help="every other fracture long enough to cross its neighbours")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--write", type=Path, help="write the case as TOML here instead of timing")
    ap.add_argument("--sif", type=Path, metavar="OUTDIR", help="run sif on the Coulomb network into OUTDIR")
    ap.add_argument("--json", action="store_true", help="with --sif: print the figures as one JSON line")
    ap.add_argument("--base", type=Path, metavar="CHECKOUT", help="with --sif: pair with this checkout's runs")
    ap.add_argument("--pairs", type=int, default=2)
    ap.add_argument("--record", type=Path, help="with --base: write the figures here as JSON")
    args = ap.parse_args()
    d = case(args.n, args.seed, args.cross)
    if args.sif and args.base:
        import json
        import subprocess

        result = paired(args.sif, args.base.resolve(), args.pairs, args.n, args.seed)
        commits = [subprocess.run(["git", "-C", str(c), "rev-parse", "--short", "HEAD"], capture_output=True,
                                  text=True).stdout.strip() for c in (ROOT, args.base)]
        result["commits"] = {"this": commits[0], "base": commits[1]}
        print(f"median sif wall: {result['median_wall']['this']:.1f} s ({commits[0]}) against "
              f"{result['median_wall']['base']:.1f} s ({commits[1]}): ratio {result['ratio']:.2f}")
        if args.record:
            args.record.write_text(json.dumps(result, indent=1) + "\n")
        return
    if args.sif:
        sif(coulomb(d), args.sif, as_json=args.json)
        return
    if args.write:
        from admissibility_cases import to_toml

        args.write.write_text(to_toml(d))
        print(f"wrote {args.write}")
        return

    import wingcrack
    from meshing import mesher

    wingcrack.Case.from_dict(d)  # warm-up: imports, the kernels
    t_check = best(lambda: wingcrack.Case.from_dict(d), args.repeat)
    c = wingcrack.Case.from_dict(d)

    def plan():
        pending = mesher.start_crack_mesh(c.domain, c.fracture_points(), c.bc_points(), c.mesh.size, c.mesh.tip_size,
                                      sectors=c.mesh.sectors, timeout=None)
        pending.cancel()

    t_plan = best(plan, args.repeat)
    print(f"{args.n} fractures{' (crossing)' if args.cross else ''}: check {t_check:.3f} s, "
          f"mesher's plan {t_plan:.3f} s (best of {args.repeat})")


if __name__ == "__main__":
    main()
