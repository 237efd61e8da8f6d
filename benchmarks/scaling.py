"""`make bench` (issue 8): one propagation step of the 45-degree Brazilian
disc with contact on a uniform mesh of about 30k, 100k, 300k and 1M DOFs, on
1 and 2 MPI ranks. Prints seconds per phase, peak memory per rank, and the
exponent b of a least-squares fit t ~ N^b of every phase over the sizes.

`python benchmarks/scaling.py [--sizes 30000 100000 ...] [--ranks 1 2]
[--json FILE]`
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
CASE = ROOT / "cases" / "brazilian_disc_45.toml"
TARGETS = [30_000, 100_000, 300_000, 1_000_000]
PHASES = ["mesh", "to_dolfinx", "assemble", "factorize", "contact", "solve", "sif", "estimate", "output"]


def mesh_dofs(size: float) -> int:
    """P2 DOFs of the case's mesh at a uniform element size (meshing only)."""
    from meshing.mesher import crack_mesh
    from wingcrack.case import Case

    case = Case.from_toml(CASE)
    cm = crack_mesh(case.domain, [f.points for f in case.fractures], case.bc_points(), size, tip_size(size),
                    sectors=case.mesh.sectors)
    return 2 * len(cm.x)


def tip_size(size: float) -> float:
    return min(5e-4, 0.5 * size)


def sizes_for(targets) -> list[float]:
    """Element sizes for the DOF targets from the power law N = C size^b
    fitted on two meshes where the rosette scales with the size too
    (tip_size = size / 2), so that b is the asymptotic -2."""
    s = np.array([0.001, 0.0007])
    n = np.array([mesh_dofs(x) for x in s])
    b = np.log(n[1] / n[0]) / np.log(s[1] / s[0])
    return [float(s[0] * (t / n[0]) ** (1 / b)) for t in targets]


def case_text(size: float, steps: int = 1) -> str:
    """The case with `steps` steps, a uniform mesh of `size` (no
    error-estimate sizing) and its rosette."""
    out, section = [], None
    for line in CASE.read_text().splitlines():
        s = line.strip()
        if s.startswith("["):
            section = s
        if section == "[mesh]" and s.split("=")[0].strip() in ("size", "tip_size", "adaptive"):
            continue
        if section == "[propagation]" and s.startswith("steps"):
            line = f"steps = {steps}"
        out.append(line)
        if s == "[mesh]":
            out += [f"size = {size!r}", f"tip_size = {tip_size(size)!r}", "adaptive = false"]
    return "\n".join(out) + "\n"


def run(size: float, ranks: int, tmp: Path, steps: int = 1) -> dict:
    """scaling_step.py's record of a run of `steps` steps at `size` on `ranks`
    processes (its first step's DOFs and seconds, every step's in "steps"),
    or {"ranks", "error"}."""
    case = tmp / f"case_{size:.3e}_{steps}.toml"
    case.write_text(case_text(size, steps))
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    cmd = ([ "mpirun", "-n", str(ranks)] if ranks > 1 else []) + \
        [sys.executable, str(ROOT / "benchmarks" / "scaling_step.py"), str(case), str(tmp / f"out_{ranks}")]
    proc = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if proc.returncode != 0:
        return {"ranks": ranks, "error": proc.stderr.strip()[-400:]}
    return json.loads(proc.stdout.strip().splitlines()[-1])


def fit(rows, phase) -> float | None:
    pts = [(r["dofs"], r["seconds"].get(phase, 0.0)) for r in rows if "seconds" in r]
    pts = [(n, t) for n, t in pts if t > 0]
    if len(pts) < 2:
        return None
    n, t = np.log(np.array(pts)).T
    return float(np.polyfit(n, t, 1)[0])


def main(argv=None, extra: dict | None = None) -> None:
    """The table and the fits; `extra` ({ranks: scaling run record}, as
    targets.large made them at 1M DOFs): rows measured already, printed and
    fitted with the others instead of being run again."""
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sizes", type=int, nargs="+", default=TARGETS, help="DOF targets")
    ap.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--json", type=Path, help="also write the measurements here")
    args = ap.parse_args(argv)
    sizes = sizes_for(args.sizes)
    results = {r: [] for r in args.ranks}
    print("\nScaling: one step of the 45-degree disc with contact, uniform mesh (issue 8)")
    with tempfile.TemporaryDirectory() as tmp:
        for target, size in zip(args.sizes, sizes):
            for ranks in args.ranks:
                r = run(size, ranks, Path(tmp))
                r["target"] = target
                results[ranks].append(r)
                if "error" in r:
                    print(f"  ~{target:,} DOFs, {ranks} rank(s): failed: {r['error']}")
                    continue
                sec = r["seconds"]
                phases = "  ".join(f"{p} {sec.get(p, 0.0):.2f}" for p in PHASES)
                print(f"  {r['dofs']:>9,} DOFs {ranks} rank(s): total {sec['total']:7.2f} s | {phases} | "
                      f"peak MiB/rank {', '.join(f'{m:.0f}' for m in r['peak_mib'])} (gmsh child {r['gmsh_peak_mib']:.0f})",
                      flush=True)
    for ranks, r in (extra or {}).items():
        if ranks in results and "error" not in r:
            results[ranks].append(r)
            print(f"  {r['dofs']:>9,} DOFs {ranks} rank(s): total {r['seconds']['total']:7.2f} s "
                  "(step 0 of target 3, above)")
    for ranks, rows in results.items():
        exps = {p: fit(rows, p) for p in PHASES + ["total"]}
        print(f"  fit t ~ N^b, {ranks} rank(s): " + ", ".join(f"{p} {b:.2f}" for p, b in exps.items() if b is not None))
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(results, indent=1))


if __name__ == "__main__":
    main()
