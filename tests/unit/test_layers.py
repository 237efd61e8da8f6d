"""The layering that docs/architecture.md draws, checked on the imports:
DOLFINx, ufl and PETSc are imported in wingcrack/fem/ only, gmsh never in
wingcrack/fem/, and meshing uses the compiled kernels (wingcrack_kernels)
without loading the wingcrack package. Static (every import statement,
nested ones too) and by what a fresh interpreter really loads."""
import ast
import importlib.util
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
FEM_ONLY = ("dolfinx", "ufl", "ffcx", "basix", "petsc4py")


def imported_modules(path: Path) -> set[str]:
    out = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            out |= {a.name.split(".")[0] for a in node.names}
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            out.add(node.module.split(".")[0])
    return out


def test_dolfinx_ufl_petsc_only_in_fem():
    bad = {}
    for path in (ROOT / "wingcrack").rglob("*.py"):
        rel = path.relative_to(ROOT).as_posix()
        if rel.startswith("wingcrack/fem/"):
            continue
        hit = imported_modules(path) & set(FEM_ONLY)
        if hit:
            bad[rel] = sorted(hit)
    assert not bad, bad
    assert "dolfinx" in imported_modules(ROOT / "wingcrack/fem/elasticity.py")   # the check sees imports


def test_no_gmsh_in_fem():
    modules = sorted(p.stem for p in (ROOT / "wingcrack/fem").glob("*.py") if p.stem != "__init__")
    bad = [m for m in modules if "gmsh" in imported_modules(ROOT / f"wingcrack/fem/{m}.py")]
    assert not bad, bad
    # nor through DOLFINx (dolfinx.io.gmshio imports gmsh)
    code = (f"import sys; import {', '.join('wingcrack.fem.' + m for m in modules)}; "
            "assert 'gmsh' not in sys.modules")
    subprocess.run([sys.executable, "-c", code], check=True, cwd=ROOT)


def test_gmsh_only_in_meshing():
    bad = sorted(p.relative_to(ROOT).as_posix() for p in (ROOT / "wingcrack").rglob("*.py")
                 if "gmsh" in imported_modules(p))
    assert not bad, bad
    assert "gmsh" in imported_modules(ROOT / "meshing/gmsh_session.py")   # the check sees nested imports


def test_meshing_never_imports_the_wingcrack_package():
    static = {p.name: imported_modules(p) & {"wingcrack"} for p in (ROOT / "meshing").glob("*.py")}
    assert not any(static.values()), static
    # a real mesh, through the kernels (split_faces, quarter_points, min_jacobian)
    code = ("import sys, numpy as np; from meshing import Domain, crack_mesh; "
            "d = Domain('rectangle', corner=[-1, -1], size=[2, 2]); "
            "m = crack_mesh(d, [np.array([[-0.2, 0.0], [0.2, 0.0]])], [], size=0.5, tip_size=0.05); "
            "assert len(m.tips) == 2 and len(m.pairs) > 0; "
            "loaded = sorted(k for k in sys.modules if k.split('.')[0] == 'wingcrack'); "
            "assert not loaded, loaded; assert 'wingcrack_kernels' in sys.modules")
    subprocess.run([sys.executable, "-c", code], check=True, cwd=ROOT)


def test_the_array_layers_load_without_dolfinx():
    code = ("import sys; import wingcrack.io.fields, wingcrack.io.faces, wingcrack.loads, "
            "wingcrack.free_pieces, wingcrack.error_estimate, wingcrack.material, wingcrack.contact.active_set, "
            "wingcrack.contact.constraints; "
            f"bad = [k for k in {FEM_ONLY!r} if k in sys.modules]; assert not bad, bad")
    subprocess.run([sys.executable, "-c", code], check=True, cwd=ROOT)


def test_the_case_does_not_know_the_propagation_loop():
    """`check` reads a case without the loop: no file of wingcrack/case/ (or
    the doc renderer) imports wingcrack.propagation, and importing the case
    loads none of it (nor DOLFINx, nor gmsh)."""
    def dotted(path: Path) -> set[str]:
        out = set()
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.Import):
                out |= {a.name for a in node.names}
            elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                out.add(node.module)
        return out

    files = sorted((ROOT / "wingcrack/case").glob("*.py")) + [ROOT / "wingcrack/case_doc.py"]
    assert len(files) > 2 and "meshing.domain" in dotted(ROOT / "wingcrack/case/reader.py")   # the check sees imports
    bad = {p.name: sorted(m for m in dotted(p) if m.startswith("wingcrack.propagation")) for p in files}
    assert not any(bad.values()), bad
    code = ("import sys; import wingcrack.case, wingcrack.case_doc; "
            "bad = [m for m in sys.modules if m.startswith('wingcrack.propagation') or m in ('dolfinx', 'gmsh')]; "
            "assert not bad, bad")
    subprocess.run([sys.executable, "-c", code], check=True, cwd=ROOT)


def test_the_kernels_have_one_name():
    """The compiled kernels are imported as `wingcrack_kernels` everywhere:
    a second name inside the package (the former wingcrack._kernels) is what
    an environment built for an older checkout still resolves to its own old
    binary, so `check` ran on old kernels while `sif` failed on the new name."""
    def other_name(node) -> bool:
        if isinstance(node, ast.Import):
            return any(a.name.endswith("._kernels") for a in node.names)
        return isinstance(node, ast.ImportFrom) and (
            (node.module or "").endswith("_kernels") and node.module != "wingcrack_kernels"
            or any(a.name == "_kernels" for a in node.names))

    bad = [str(p.relative_to(ROOT)) for d in ("wingcrack", "meshing", "tests", "benchmarks")
           for p in (ROOT / d).rglob("*.py")
           if p.stem == "_kernels" or any(other_name(n) for n in ast.walk(ast.parse(p.read_text())))]
    assert not bad, bad


def test_a_missing_kernel_module_is_named_with_its_remedy():
    """Without wingcrack_kernels in the environment every command, `check`
    included, says which module is missing and that `make setup` installs it
    (exit 1, one line, no traceback)."""
    code = ("import sys\n"
            "class Absent:\n"
            "    def find_spec(self, name, path=None, target=None):\n"
            "        if name == 'wingcrack_kernels':\n"
            "            raise ModuleNotFoundError(f'No module named {name!r}', name=name)\n"
            "sys.meta_path.insert(0, Absent())\n"
            "from wingcrack.cli import main\n"
            "sys.exit(main(['check', 'cases/griffith_inclined.toml']))\n")
    proc = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True)
    assert proc.returncode == 1, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and "wingcrack_kernels" in lines[0] and "make setup" in lines[0], proc.stderr


# The target layering (tests/whiteboard.json, a copy of the design's board):
# parts are files or folders, "never" pairs are imports that must not exist.
# A file belongs to the part that names it most precisely (meshing/domain.py
# is geometry, not meshing).


def _part_of(rel: str, parts: dict) -> str | None:
    best, length = None, -1
    for name, part in parts.items():
        for entry in part["is"]:
            hit = rel == entry or (entry.endswith("/") and rel.startswith(entry))
            if hit and len(entry) > length:
                best, length = name, len(entry)
    return best


def _module_file(module: str) -> str | None:
    base = ROOT / Path(*module.split("."))
    for cand in (base.with_suffix(".py"), base / "__init__.py"):
        if cand.is_file():
            return cand.relative_to(ROOT).as_posix()
    return None


def _imported_files(path: Path) -> set[str]:
    """The repository files that `path` imports, at any depth of its code
    (imports inside functions count), relative imports resolved."""
    rel = path.relative_to(ROOT).with_suffix("")
    package = list(rel.parts[:-1]) if rel.name != "__init__" else list(rel.parts[:-1])
    out = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        names = []
        if isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                anchor = package[:len(package) - node.level + 1]
                mod = ".".join(anchor + ([node.module] if node.module else []))
            else:
                mod = node.module or ""
            # `from pkg import sub` imports pkg/sub.py; `from pkg import name`, pkg itself
            names = [f"{mod}.{a.name}" if _module_file(f"{mod}.{a.name}") else mod
                     for a in node.names]
        for name in names:
            f = _module_file(name)
            if f is not None and f != path.relative_to(ROOT).as_posix():
                out.add(f)
    return out


def test_no_import_the_board_forbids():
    import json

    board = json.loads((ROOT / "tests/whiteboard.json").read_text())
    parts = board["parts"]
    files = [p for d in ("wingcrack", "meshing", "procs") if (ROOT / d).is_dir()
             for p in (ROOT / d).rglob("*.py")]
    edges = {p.relative_to(ROOT).as_posix(): _imported_files(p) for p in files}
    assert "wingcrack/step.py" in edges["wingcrack/propagation/loop.py"]   # the check sees relative imports
    bad = {}
    for src, dst, *why in board["never"]:
        for a, targets in edges.items():
            for b in targets:
                if _part_of(a, parts) == src and _part_of(b, parts) == dst:
                    bad.setdefault(f"{src} -> {dst}", []).append(f"{a} -> {b}")
    assert not bad, bad


def test_no_two_modules_import_each_other_in_a_circle():
    """Among wingcrack/, meshing/ and procs/, every import (those inside
    functions too) taken as a dependency: no cycle (benchmarks/structure.py
    reads them, the same count its report gives)."""
    spec = importlib.util.spec_from_file_location("_structure", ROOT / "benchmarks" / "structure.py")
    structure = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(structure)
    assert structure.measure(ROOT)["import cycles"] == []
