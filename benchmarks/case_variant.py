"""A case file with a few settings changed (`propagation.steps = 34`,
`mesh.adaptive = false`), written beside the benchmark's outputs: the
benchmarks' variants of the committed cases, as plain case files that
`wingcrack run` reads like any other."""
from __future__ import annotations

from pathlib import Path


def toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    raise TypeError(f"no TOML form for {v!r} here")


def variant_text(text: str, settings: dict) -> str:
    """`text` (a case file) with each `"table.key": value` of `settings` set:
    the key's line in [table] replaced, or added at the table's head, or the
    table added at the end. Only plain tables ([mesh], [propagation]), not
    arrays of tables ([[fractures]]); line by line, so the case's comments
    stay (the standard library reads TOML but does not write it)."""
    want: dict[str, dict[str, str]] = {}
    for dotted, v in settings.items():
        table, _, key = dotted.rpartition(".")
        if not table or "." in table:
            raise ValueError(f"{dotted}: give table.key of a top-level table")
        want.setdefault(table, {})[key] = toml_value(v)
    out, table, done = [], None, set()
    for line in text.splitlines():
        s = line.strip()
        if s.startswith("["):
            table = None if s.startswith("[[") else s[1:s.index("]")].strip()
            out.append(line)
            for key, v in want.get(table, {}).items():
                out.append(f"{key} = {v}")
                done.add((table, key))
            continue
        key = s.split("=", 1)[0].strip() if "=" in s and not s.startswith("#") else None
        if table in want and key in want[table]:
            continue   # replaced by the line given at the table's head
        out.append(line)
    for table, keys in want.items():
        rest = [f"{k} = {v}" for k, v in keys.items() if (table, k) not in done]
        if rest:
            out += ["", f"[{table}]"] + rest
    return "\n".join(out) + "\n"


def write_variant(case: Path, settings: dict, to: Path) -> Path:
    """Write `case` with `settings` (see variant_text) to `to`; returns `to`."""
    to.parent.mkdir(parents=True, exist_ok=True)
    to.write_text(variant_text(Path(case).read_text(), settings))
    return to
