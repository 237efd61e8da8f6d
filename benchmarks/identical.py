"""Are a checkout's results bitwise those of another? For changes that must
not change behaviour (a renovation): every case in cases/ runs as its own
`wingcrack run` process (`wingcrack sif` where the case asks for no step),
and a manifest records, per case, its exit code,
summary.json without its timings (every "seconds" key dropped) and the
SHA-256 of every step and face file's decoded arrays (step_XXXX.vtu,
faces_XXXX.vtu: their compressed bytes may differ for the same data) and of
the ParaView indices' bytes. Pictures are left out (drawn with --no-plots anyway,
and a picture's bytes follow matplotlib's version, not ours).

    .venv/bin/python benchmarks/identical.py --write FILE [--steps N] [--cases NAME ...]
    .venv/bin/python benchmarks/identical.py --check FILE            (the same cases and steps as FILE)

--write runs the cases with this checkout and writes FILE; --check runs
them again (with the steps and cases recorded in FILE) and lists every
difference, exiting 1 if there is any. --steps caps each case's
propagation.steps (a variant case file written beside the outputs), so that
the check fits a coffee break: the first steps hold every stage (meshing,
contact, SIFs, growth, remeshing). Run with another checkout's python to
record its manifest: the `wingcrack` used is the one beside the python.
"""
from __future__ import annotations

import argparse
import hashlib
import json
import subprocess
import sys
import tempfile
import tomllib
from pathlib import Path

import numpy as np

from case_variant import variant_text
from propagation import ROOT, run_case


def manifest_of(out: Path, run: dict) -> dict:
    """What must be identical in one case's output folder."""
    summary = _without_seconds(run["summary"])
    files = sorted(p for p in out.iterdir() if p.suffix in (".vtu", ".pvd"))
    return {"exit": run["exit"],
            "summary": summary,
            "files": {p.name: _digest(p) for p in files}}


def _digest(path: Path) -> str:
    """SHA-256 of what a file holds: a .vtu's decoded arrays (points, cells,
    point, cell and field data, each with its name, dtype and shape), not its
    bytes, whose zlib blocks may differ for the same data (the compressor's
    output is not deterministic: two runs of one checkout differed in a
    block that inflates to the same bytes); other files byte for byte."""
    if path.suffix != ".vtu":
        return hashlib.sha256(path.read_bytes()).hexdigest()
    from meshio import vtu

    mesh = vtu.read(str(path))
    h = hashlib.sha256()

    def add(name, a):
        a = np.ascontiguousarray(a)
        h.update(f"{name}:{a.dtype.str}:{a.shape};".encode())
        h.update(a.tobytes())

    add("points", mesh.points)
    for i, block in enumerate(mesh.cells):
        add(f"cells[{i}].{block.type}", block.data)
    for kind, data in (("point", mesh.point_data), ("field", mesh.field_data)):
        for name in sorted(data):
            add(f"{kind}.{name}", data[name])
    for name in sorted(mesh.cell_data):
        for i, a in enumerate(mesh.cell_data[name]):
            add(f"cell.{name}[{i}]", a)
    return h.hexdigest()


def _without_seconds(x):
    if isinstance(x, dict):
        return {k: _without_seconds(v) for k, v in x.items() if k != "seconds"}
    if isinstance(x, list):
        return [_without_seconds(v) for v in x]
    return x


def run_all(names, steps: int | None, work: Path) -> dict:
    """{name: manifest} of every case, run with this checkout's wingcrack."""
    wingcrack = Path(sys.executable).parent / "wingcrack"
    out = {}
    for name in names:
        case = ROOT / "cases" / f"{name}.toml"
        own = tomllib.loads(case.read_text()).get("propagation", {}).get("steps")
        if steps is not None and (own is None or own > steps):   # a cap: a case of fewer steps keeps its own
            variant = work / f"{name}.toml"
            variant.write_text(variant_text(case.read_text(), {"propagation.steps": steps}))
            case = variant
        folder = work / name
        if own == 0:
            run = _sif(folder, case, wingcrack)   # a stress-intensity case: `run` would solve nothing
        else:
            run = run_case(name, folder, case=case, wingcrack=wingcrack)
        out[name] = manifest_of(folder, run)
        print(f"{name}: exit {run['exit']}, {len(out[name]['summary'].get('steps', []))} steps, "
              f"{len(out[name]['files'])} files, {run['wall']:.0f} s", flush=True)
    return out


def _sif(folder: Path, case: Path, wingcrack: Path) -> dict:
    """`wingcrack sif` of `case` into `folder` (run_case's fields that manifest_of reads)."""
    proc = subprocess.run([str(wingcrack), "sif", str(case), "-o", str(folder), "--quiet"], capture_output=True,
                          text=True)
    summary = folder / "summary.json"
    return {"exit": proc.returncode, "summary": json.loads(summary.read_text()) if summary.exists() else {},
            "wall": 0.0}


def differences(want: dict, got: dict) -> list[str]:
    """Every difference between two manifests, one line each."""
    lines = []
    for name in sorted(set(want) | set(got)):
        a, b = want.get(name), got.get(name)
        if a is None or b is None:
            lines.append(f"{name}: only in {'the check' if a is None else 'the manifest'}")
            continue
        if a["exit"] != b["exit"]:
            lines.append(f"{name}: exit {a['exit']} -> {b['exit']}")
        if a["summary"] != b["summary"]:
            lines.append(f"{name}: summary.json differs ({_first_difference(a['summary'], b['summary'])})")
        for f in sorted(set(a["files"]) | set(b["files"])):
            if a["files"].get(f) != b["files"].get(f):
                lines.append(f"{name}: {f} differs" if f in a["files"] and f in b["files"]
                             else f"{name}: {f} only in {'the manifest' if f in a['files'] else 'the check'}")
    return lines


def _first_difference(a, b, where="") -> str:
    if type(a) is not type(b):
        return f"{where or 'top'}: {a!r} -> {b!r}"
    if isinstance(a, dict):
        for k in list(a) + [k for k in b if k not in a]:
            if a.get(k) != b.get(k):
                return _first_difference(a.get(k), b.get(k), f"{where}.{k}" if where else str(k))
    if isinstance(a, list):
        if len(a) != len(b):
            return f"{where}: {len(a)} -> {len(b)} entries"
        for i, (x, y) in enumerate(zip(a, b)):
            if x != y:
                return _first_difference(x, y, f"{where}[{i}]")
    return f"{where}: {str(a)[:80]} -> {str(b)[:80]}"


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    mode = ap.add_mutually_exclusive_group(required=True)
    mode.add_argument("--write", type=Path, metavar="FILE")
    mode.add_argument("--check", type=Path, metavar="FILE")
    ap.add_argument("--steps", type=int, help="cap each case's propagation.steps (--write)")
    ap.add_argument("--cases", nargs="+", help="these cases of cases/ only (--write; default: all)")
    ap.add_argument("--keep", type=Path, help="keep the output folders here")
    args = ap.parse_args()
    if args.check:
        want = json.loads(args.check.read_text())
        names, steps = want["cases"], want["steps"]
    else:
        names = args.cases or sorted(p.stem for p in (ROOT / "cases").glob("*.toml"))
        steps = args.steps
    with tempfile.TemporaryDirectory(prefix="wingcrack-identical-") as tmp:
        work = args.keep or Path(tmp)
        work.mkdir(parents=True, exist_ok=True)
        got = run_all(names, steps, work)
    if args.write:
        args.write.write_text(json.dumps({"cases": names, "steps": steps, "manifests": got}, indent=1))
        print(f"wrote {args.write}")
        return 0
    lines = differences(want["manifests"], got)
    for line in lines:
        print(line)
    print(f"{len(names)} cases: " + ("identical" if not lines else f"{len(lines)} differences"))
    return 1 if lines else 0


if __name__ == "__main__":
    sys.exit(main())
