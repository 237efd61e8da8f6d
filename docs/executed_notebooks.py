"""The notebooks with their outputs, for the site: executed copies of
notebooks/*.ipynb (stored there without outputs) in build/notebooks/, which
docs/notebooks/*.nblink point Sphinx at.

tests/command_line/test_notebooks.py executes every notebook anyway and keeps
each copy that ran without an error here (keep); `make docs` then runs this
file, which executes only the notebooks whose copy is missing or stale, so
that `make test` (the tests, then the docs) executes each notebook once.

    .venv/bin/python docs/executed_notebooks.py

A copy is current when it was made from the same notebook and the same
library sources (wingcrack/, meshing/, procs/, cpp_kernels/): its metadata
holds their digest. The files a notebook writes go to build/notebooks/out/
(WINGCRACK_NOTEBOOK_OUT).
"""
from __future__ import annotations

import hashlib
import os
import sys
import time
from pathlib import Path

import nbformat
from nbclient import NotebookClient

ROOT = Path(__file__).resolve().parents[1]
FOLDER = ROOT / "notebooks"
EXECUTED = ROOT / "build" / "notebooks"
NOTEBOOKS = ["01_stress_intensity_factors", "02_fracture_contact", "03_wing_cracks", "04_one_step", "05_friction"]
#: the Jupyter kernel `make setup` installs into the venv (it runs .venv/bin/python)
KERNEL = "wingcrack"
#: seconds one cell may take: the longest (the 34-step run of 03) takes ~45 s
CELL_TIMEOUT = 300
#: what a notebook's outputs depend on besides the notebook itself
SOURCES = ("wingcrack", "meshing", "procs", "cpp_kernels")


def digest(name: str) -> str:
    """SHA-256 of the stored notebook and of every library source file."""
    h = hashlib.sha256((FOLDER / f"{name}.ipynb").read_bytes())
    for folder in SOURCES:
        for path in sorted((ROOT / folder).rglob("*")):
            if path.suffix in (".py", ".cpp", ".hpp") and "__pycache__" not in path.parts:
                h.update(path.relative_to(ROOT).as_posix().encode())
                h.update(path.read_bytes())
    return h.hexdigest()


def execute(name: str) -> nbformat.NotebookNode:
    """notebooks/NAME.ipynb run top to bottom in the kernel (from notebooks/, as a
    user opens it); nbclient's CellExecutionError names a cell that fails."""
    nb = nbformat.read(FOLDER / f"{name}.ipynb", as_version=4)
    NotebookClient(nb, timeout=CELL_TIMEOUT, kernel_name=KERNEL,
                   resources={"metadata": {"path": str(FOLDER)}}).execute()
    return nb


def keep(name: str, nb: nbformat.NotebookNode, source_digest: str) -> Path:
    """Store an executed notebook as build/notebooks/NAME.ipynb (written whole,
    then renamed: Sphinx never reads half a file)."""
    EXECUTED.mkdir(parents=True, exist_ok=True)
    nb.metadata["wingcrack"] = {"digest": source_digest}
    path = EXECUTED / f"{name}.ipynb"
    part = path.with_suffix(".part")
    nbformat.write(nb, part)
    part.replace(path)
    return path


def current(name: str) -> bool:
    path = EXECUTED / f"{name}.ipynb"
    if not path.exists():
        return False
    kept = nbformat.read(path, as_version=4).metadata.get("wingcrack", {}).get("digest")
    return kept == digest(name)


def main() -> int:
    os.environ.setdefault("WINGCRACK_NOTEBOOK_OUT", str(EXECUTED / "out"))
    for name in NOTEBOOKS:
        if current(name):
            continue
        source_digest = digest(name)   # before the run: an edit meanwhile makes the copy stale
        t = time.perf_counter()
        keep(name, execute(name), source_digest)
        print(f"executed notebooks/{name}.ipynb for the site in {time.perf_counter() - t:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
