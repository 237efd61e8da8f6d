"""The key tables of docs/case-format.md, rendered from the Keys of wingcrack.case.

Each table of the reference sits between `<!-- keys: NAME -->` and
`<!-- end keys -->` (NAME as in `case.DESCRIPTION`). `python -m
wingcrack.case_doc` rewrites them; tests/unit/test_case.py checks that the file
holds what `render` gives, so the reference and the reader cannot drift.
"""
from __future__ import annotations

import re
import sys
from pathlib import Path

from wingcrack.case import DESCRIPTION, NUMBERS, POINT, REQUIRED, SHAPE_KEYS, STRING, Key, Range, Ref

DOC = Path(__file__).resolve().parents[1] / "docs" / "case-format.md"
_BLOCK = re.compile(r"(<!-- keys: (\w+) -->\n).*?(<!-- end keys -->)", re.S)
_SHAPE_OF = {k.name: shape for shape, keys in SHAPE_KEYS.items() for k in keys}


def _toml(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return f'"{v}"'
    if isinstance(v, tuple):
        return "[" + ", ".join(_toml(x) for x in v) + "]"
    return repr(v)


def _default(k: Key) -> str:
    if k.default_doc:
        return k.default_doc
    if k.default is REQUIRED:
        return "required"
    if k.required_with is not None:
        other, want = k.required_with
        return f'required with `{other} = "{want}"`, else `{_toml(k.default)}`'
    if k.default is None:
        return ""
    if isinstance(k.default, Ref):
        return f"`{k.default.key}`"
    return f"`{_toml(k.default)}`"


def _range(r: Range, name: str) -> str:
    if r.lo is not None and r.hi is not None:
        return f"{r.lo:g} < {name} < {r.hi:g}" if r.open else f"{r.lo:g} ... {r.hi:g}"
    if r.lo is not None:
        return f"{'>' if r.open else '>='} {r.lo:g}"
    return f"{'<' if r.open else '<='} {r.hi:g}"


def _limit(k: Key) -> str:
    if k.type == STRING:
        return f"at most {k.limit.hi:g} characters"
    if k.limit.lo > 0:
        return f"{k.limit.lo:g} ... {k.limit.hi:g}"
    return f"|x| <= {k.limit.bound}" if k.signed else f"<= {k.limit.bound}"


def _allowed(k: Key) -> str:
    parts = []
    if k.choices:
        parts.append(" | ".join(f'`"{c}"`' for c in k.choices))
    if k.range is not None:
        parts.append(("each " if k.type in (POINT, NUMBERS) else "") + _range(k.range, k.name))
    if k.min_points:
        parts.append(f"at least {k.min_points} points")
    if k.only_with is not None:
        parts.append(f'other than the default only with `{k.only_with[0]} = "{k.only_with[1]}"`')
    if k.limit is not None:
        unit = f" {k.unit}" if k.unit and not k.limit.of else ""
        each = "each " if k.type in (POINT, NUMBERS) else ""
        parts.append(f"{each}{_limit(k)}{unit} ({k.limit.why}) **R**")
    if k.rule:
        parts.append(f"{k.rule} **R**")
    return "; ".join(parts)


def table(name: str, keys) -> str:
    """The markdown table of one case table's Keys."""
    rows = ["| key | type, unit | default | allowed | meaning |", "|---|---|---|---|---|"]
    for k in keys:
        key = f"`{k.name}`" + (f" ({_SHAPE_OF[k.name]})" if name == "domain" and k.name in _SHAPE_OF else "")
        cells = [key + (" **+**" if k.added else ""), k.type + (f", {k.unit}" if k.unit else ""),
                 _default(k), _allowed(k), k.doc]
        rows.append("| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |")
    return "\n".join(rows) + "\n"


def render(text: str) -> str:
    """`text` with every keys block replaced by its rendered table."""
    def block(m: re.Match) -> str:
        return m.group(1) + table(m.group(2), DESCRIPTION[m.group(2)]) + m.group(3)

    return _BLOCK.sub(block, text)


def blocks(text: str) -> list[str]:
    """The names of the keys blocks in `text`, in order."""
    return [m.group(2) for m in _BLOCK.finditer(text)]


def main() -> int:
    DOC.write_text(render(DOC.read_text()))
    print(f"rewrote {len(blocks(DOC.read_text()))} key tables in {DOC}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
