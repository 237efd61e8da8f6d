"""The gallery (docs/user-guide/gallery.md, pictures in docs/gallery/) drawn again from the shipped cases:
each picture there named <case>.png is that case's fractures.png,
<case>_history.png its history.png, <case>.gif its growth animation. Every
case with a picture in the gallery runs as `wingcrack run` (with its
pictures) into a scratch folder, and the pictures the gallery holds are
copied over. Not a test: a run of every case takes some minutes.

    .venv/bin/python benchmarks/gallery.py [--cases NAME ...]
"""
from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import tempfile
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
GALLERY = ROOT / "docs" / "gallery"
#: a gallery file's suffix -> the result file it copies
KINDS = {".png": "fractures.png", "_history.png": "history.png", ".gif": "growth.gif"}


def pictures_of(name: str) -> dict:
    """{result file: gallery file} of the case `name`."""
    out = {}
    for suffix, result in KINDS.items():
        if (GALLERY / f"{name}{suffix}").exists():
            out[result] = GALLERY / f"{name}{suffix}"
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", nargs="+")
    args = ap.parse_args()
    names = args.cases or sorted(p.stem for p in (ROOT / "cases").glob("*.toml") if pictures_of(p.stem))
    wingcrack = Path(sys.executable).parent / "wingcrack"
    failed = 0
    with tempfile.TemporaryDirectory(prefix="wingcrack-gallery-") as tmp:
        for name in names:
            out = Path(tmp) / name
            case = ROOT / "cases" / f"{name}.toml"
            # a stress-intensity case (no step asked for) is drawn by `sif`
            none = tomllib.loads(case.read_text()).get("propagation", {}).get("steps") == 0
            cmd = [str(wingcrack), "sif" if none else "run", str(case), "-o", str(out), "--quiet"]
            res = subprocess.run(cmd, capture_output=True, text=True)
            if res.returncode not in (0,):
                print(f"{name}: exit {res.returncode}: {res.stderr.strip()[-300:]}")
                failed += 1
                continue
            for result, target in pictures_of(name).items():
                if (out / result).exists():
                    shutil.copyfile(out / result, target)
                    print(f"{name}: {target.relative_to(ROOT)}")
                else:
                    print(f"{name}: no {result} drawn")
                    failed += 1
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
