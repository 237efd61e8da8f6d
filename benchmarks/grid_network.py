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

--sif: the scale case of the network issue (1,000 Coulomb fractures, friction
0.6, under 1 MPa of vertical compression) through `sif`, its phases' seconds
(summary.json) and the process's peak memory printed.

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


def sif(d: dict, out: Path) -> None:
    import json
    import resource

    import wingcrack

    from mpi4py import MPI

    t0 = time.perf_counter()
    wingcrack.sif(wingcrack.Case.from_dict(d), out, force=True)
    wall = time.perf_counter() - t0
    peak = MPI.COMM_WORLD.allreduce(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)   # KiB, all ranks
    if MPI.COMM_WORLD.rank:
        return   # rank 0 writes the summary
    step = json.loads((out / "summary.json").read_text())["steps"][0]
    phases = ", ".join(f"{k} {v:.1f}" for k, v in step["seconds"].items() if v >= 0.05)
    c = step["contact"]
    print(f"{len(d['fractures'])} Coulomb fractures: sif {wall:.1f} s ({phases}); {step['dofs']} DOFs, "
          f"{c['rows']} pair rows, {c['iterations']} active sets; {MPI.COMM_WORLD.size} process(es), "
          f"peak {peak / 2**20:.1f} GB (summed)")


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
    args = ap.parse_args()
    d = case(args.n, args.seed, args.cross)
    if args.sif:
        sif(coulomb(d), args.sif)
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
