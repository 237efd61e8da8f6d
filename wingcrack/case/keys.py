"""The description of a key: its type, unit, default, the range its meaning
allows, the magnitude a case may ask for and its documentation (`Key`), and
the dataclass field that carries one (`key`, `keys_of`). The reader checks
values by their Keys and docs/case-format.md's key tables are rendered from
them (wingcrack/case_doc.py), so the two cannot drift."""
from __future__ import annotations

import dataclasses
import functools
import math
import typing
from dataclasses import dataclass, field, replace

import numpy as np

from wingcrack.errors import CaseError

NUMBER, INTEGER, BOOLEAN, STRING = "number", "integer", "boolean", "string"
POINT, POINTS, TABLE, TABLES = "[x, y]", "[[x, y], ...]", "table", "array of tables"
NUMBERS = "[a, b, ...]"


class _Required:
    def __repr__(self) -> str:
        return "REQUIRED"


REQUIRED = _Required()


@dataclass(frozen=True)
class Ref:
    """A default taken from another key of the case, named by its full path."""

    key: str


@dataclass(frozen=True)
class Range:
    """What the key's meaning allows: lo < x < hi (`open`) or lo <= x <= hi;
    either end may be None. `note` is added to the message."""

    lo: float | None = None
    hi: float | None = None
    open: bool = False
    note: str = ""

    def check(self, x, key: str, what: str = "") -> None:
        got = _shown(x) if isinstance(x, float) else str(x)
        lo, hi = self.lo, self.hi
        if lo is not None and hi is not None and self.open:
            if not lo < x < hi:
                raise CaseError(key, f"{what}must lie in ({lo:g}, {hi:g}){self.note}, got {got}")
            return
        if lo is not None and not (x > lo if self.open else x >= lo):
            raise CaseError(key, f"{what}must be {'>' if self.open else '>='} {lo:g}{self.note}, got {got}")
        if hi is not None and not (x < hi if self.open else x <= hi):
            raise CaseError(key, f"{what}must be {'<' if self.open else '<='} {hi:g}{self.note}, got {got}")


def _shown(x) -> str:
    """A refused number as %g, or with the digits it takes to be exact: a value
    just beyond a bound (E = 1.0000001e13) must not read as the bound itself
    ("got 1e+13")."""
    x = float(x)
    for digits in range(6, 18):
        text = f"{x:.{digits}g}"
        if float(text) == x:
            return text
    return repr(x)


POSITIVE = Range(0, open=True)
NON_NEGATIVE = Range(0)


@dataclass(frozen=True)
class Limit:
    """The magnitude a case may ask for, lo*scale <= |x| <= hi*scale, where
    `of` names a scale of the case ("E", "L", "E L", "E / (density L)"; ""
    for none) and `why` says where the bound comes from. A string's limit
    counts its characters. These bound what the meaning would allow, so that
    nothing a case asks for overflows or underflows in the solve."""

    lo: float = 0.0
    hi: float = math.inf
    of: str = ""
    why: str = ""

    def check(self, x, key: str, unit: str, signed: bool, scales: dict) -> None:
        if isinstance(x, str):
            if len(x) > self.hi:
                raise CaseError(key, f"at most {self.hi:g} characters ({self.why}), got {len(x)}")
            return
        scale = scales[self.of] if self.of else 1.0
        if abs(x) <= self.hi * scale and (self.lo == 0 or abs(x) >= self.lo * scale):
            return
        unit = f" {unit}" if unit else ""
        if self.lo > 0:
            raise CaseError(key, f"must lie within {self.lo:g} .. {self.hi:g}{unit} ({self.why}), got {_shown(x)}")
        bound = f"{self.bound} = {self.hi * scale:.4g}{unit}" if self.of else f"{self.hi:g}{unit}"
        size = " in magnitude" if signed else ""
        raise CaseError(key, f"must be at most {bound}{size} ({self.why}), got {_shown(x)}")

    @property
    def bound(self) -> str:
        """The upper bound as text: "0.1 E", "L", "1e+09"."""
        return self.of if self.of and self.hi == 1 else f"{self.hi:g} {self.of}".strip()


@dataclass(frozen=True)
class Key:
    """One key of a case table.

    name and type (NUMBER, INTEGER, BOOLEAN, STRING, POINT, POINTS, NUMBERS,
    TABLE, TABLES) come from the dataclass field when the Key sits on one. default:
    REQUIRED, a value, None (absent means not given) or a Ref. choices: the
    allowed strings. range: what the meaning allows (a point's components
    each, named by `parts`; a list's numbers each). limit: the magnitude a case may ask for.
    only_with (key, value): a value other than the default only when that
    earlier key of the table has that value. required_with (key, value):
    required when that earlier key has that value (elsewhere the default
    applies). min_points with `noun`: the fewest points of a POINTS key.
    doc: the reference's text; `rule`: what the checks further on ask of it;
    added: a key wingcrack adds to the contract.
    """

    name: str = ""
    type: str = ""
    default: object = REQUIRED
    unit: str = ""
    choices: tuple[str, ...] = ()
    range: Range | None = None
    limit: Limit | None = None
    only_with: tuple[str, str] | None = None
    required_with: tuple[str, str] | None = None
    parts: tuple[str, ...] = ()
    min_points: int = 0
    noun: str = ""
    doc: str = ""
    rule: str = ""
    default_doc: str = ""
    added: bool = False

    @property
    def signed(self) -> bool:
        return self.range is None or self.range.lo is None or self.range.lo < 0

    def check(self, v, key: str, values: dict, known: dict) -> None:
        """Everything this key asks of its (converted) value v."""
        if self.choices and v not in self.choices:
            options = " | ".join(f'"{c}"' for c in self.choices)
            raise CaseError(key, f'"{v}" is not one of {options}')
        if self.type == POINTS and len(v) < self.min_points:
            raise CaseError(key, f"{self.noun} needs at least {self.min_points} points, got {len(v)}")
        if self.only_with is not None:
            other, want = self.only_with
            if v != self.default and values[other] != want:
                raise CaseError(key, f'only with {other} = "{want}" ({other} is "{values[other]}")')
        items = list(enumerate(v)) if self.type in (POINT, NUMBERS) else [(None, v)]
        for i, x in items:
            at = key if i is None else f"{key}[{i}]"
            if self.range is not None:
                self.range.check(x, at, f"{self.parts[i]} " if self.parts else "")
            if self.limit is not None:
                self.limit.check(x, at, self.unit, self.signed, known)


def key(default=REQUIRED, **spec) -> dataclasses.Field:
    """A dataclass field described by a Key (its name and type are the field's)."""
    k = Key(default=default, **spec)
    if default is REQUIRED or isinstance(default, Ref):
        return field(metadata={"key": k})
    return field(default=default, metadata={"key": k})


_TYPES = {float: NUMBER, int: INTEGER, bool: BOOLEAN, str: STRING, tuple[float, float]: POINT, np.ndarray: POINTS,
          tuple[float, ...]: NUMBERS}


@functools.cache
def keys_of(cls) -> tuple[Key, ...]:
    """The Keys on the fields of dataclass `cls`, in field order."""
    hints = typing.get_type_hints(cls)
    return tuple(replace(f.metadata["key"], name=f.name, type=_TYPES[hints[f.name]])
                 for f in dataclasses.fields(cls) if "key" in f.metadata)
