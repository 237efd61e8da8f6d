"""Figures of the code's structure, for a renovation's before and after: the
largest files and functions, imports inside functions, import cycles among
the project's own modules, the share of comment and docstring lines and README.md's length.

    python3 benchmarks/structure.py [ROOT]          (ROOT: a checkout; default this one)
    python3 benchmarks/structure.py --before CHECKOUT --record FILE
                                                    (this checkout against CHECKOUT, written as
                                                    JSON: the developer page's table, doc_tables.py)

Reads the sources only (ast): nothing is imported, so any checkout can be
measured with any python. A cycle counts every import, also those inside
functions (they are as much a dependency as one at the top).
"""
from __future__ import annotations

import argparse
import ast
import io
import json
import subprocess
import sys
import tokenize
from pathlib import Path

PACKAGES = ("wingcrack", "meshing", "procs")


def modules(root: Path) -> dict[str, Path]:
    """Dotted module name -> file, for the project's packages under root."""
    out = {}
    for package in PACKAGES:
        for path in sorted((root / package).rglob("*.py")):
            parts = list(path.relative_to(root).with_suffix("").parts)
            if parts[-1] == "__init__":
                parts.pop()
            out[".".join(parts)] = path
    return out


def imported(name: str, path: Path, node: ast.AST, known: set[str]) -> set[str]:
    """The project modules that one import statement of module `name` loads."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    if isinstance(node, ast.Import):
        targets = [a.name for a in node.names]
    else:
        base = node.module or ""
        if node.level:
            up = package.split(".")
            up = up[: len(up) - node.level + 1]
            base = ".".join(up + ([base] if base else []))
        # `from pkg import name` loads the submodule pkg.name where there is one, else pkg itself
        targets = [f"{base}.{a.name}" if f"{base}.{a.name}" in known else base for a in node.names]
    found = set()
    for t in targets:
        while t and t not in known:
            t = t.rpartition(".")[0]
        if t and t != name:
            found.add(t)
    return found


def comment_lines(text: str, tree: ast.AST) -> int:
    """Lines holding a comment token or a docstring."""
    rows = set()
    for tok in tokenize.generate_tokens(io.StringIO(text).readline):
        if tok.type == tokenize.COMMENT:
            rows.add(tok.start[0])
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)) and node.body:
            first = node.body[0]
            if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant) and isinstance(first.value.value, str):
                rows.update(range(first.lineno, first.end_lineno + 1))
    return len(rows)


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components of more than one module (Tarjan)."""
    index, low, stack, on, out = {}, {}, [], set(), []
    counter = [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    sys.setrecursionlimit(10_000)
    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def measure(root: Path) -> dict:
    mods = modules(root)
    known = set(mods)
    graph: dict[str, set[str]] = {}
    lines = comments = inner = 0
    files, functions = [], []
    for name, path in mods.items():
        text = path.read_text()
        tree = ast.parse(text)
        n = len(text.splitlines())
        lines += n
        comments += comment_lines(text, tree)
        files.append((n, str(path.relative_to(root))))
        graph[name] = set()
        for node in ast.walk(tree):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                functions.append((node.end_lineno - node.lineno + 1, f"{path.relative_to(root)}:{node.name}"))
                inner += sum(isinstance(s, (ast.Import, ast.ImportFrom)) for s in ast.walk(node))
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                graph[name] |= imported(name, path, node, known)
    readme = root / "README.md"
    return {
        "largest files": sorted(files, reverse=True)[:3],
        "longest functions": sorted(functions, reverse=True)[:3],
        "imports inside functions": inner,
        "import cycles": cycles(graph),
        "comment share": round(comments / max(lines, 1), 3),
        "lines": lines,
        "README.md lines": len(readme.read_text().splitlines()) if readme.exists() else 0,
    }


def commit_of(root: Path) -> str:
    """The short commit of the checkout at root (its work tree as measured)."""
    return subprocess.run(["git", "-C", str(root), "rev-parse", "--short", "HEAD"], capture_output=True,
                          text=True, check=True).stdout.strip()


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("root", nargs="?", type=Path, default=Path(__file__).resolve().parents[1])
    ap.add_argument("--before", type=Path, help="another checkout, measured as the 'before'")
    ap.add_argument("--record", type=Path, help="with --before: write both measures here as JSON")
    a = ap.parse_args(argv)
    root = a.root.resolve()
    if a.before is not None:
        data = {"before": {"commit": commit_of(a.before), **measure(a.before.resolve())},
                "after": {"commit": commit_of(root), **measure(root)}}
        text = json.dumps(data, indent=1)
        if a.record:
            a.record.write_text(text + "\n")
        print(text)
        return 0
    for key, value in measure(root).items():
        if isinstance(value, list):
            print(f"{key}:")
            for v in value:
                print(f"    {v}")
        else:
            print(f"{key}: {value}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
