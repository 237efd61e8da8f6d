"""Reading one TOML table by its Keys: each value converted to its type
(a number is finite and not a boolean, a point is two numbers, ...) and
checked against its Key, or its default; unknown keys refused with the
closest known one suggested. Errors name the key by its full path."""
from __future__ import annotations

import difflib
import math

import numpy as np

from wingcrack.case.bounds import MAX_ITEMS
from wingcrack.case.keys import (BOOLEAN, INTEGER, NUMBER, NUMBERS, POINT, POINTS, REQUIRED, STRING, TABLE,
                                 TABLES, Key, Ref)
from wingcrack.errors import CaseError

def _scalar(v):
    """A numpy scalar (np.float32, np.int64, np.bool_: what arrays hand a Python user) as the
    Python value a TOML file would have given; anything else as it is."""
    return v.item() if isinstance(v, np.generic) and v.shape == () else v


def _what(v) -> str:
    v = _scalar(v)
    if isinstance(v, bool):
        return "a boolean"
    if isinstance(v, (int, float)):
        return "a number"
    if isinstance(v, str):
        return "a string"
    if isinstance(v, list):
        return "an array"
    if isinstance(v, dict):
        return "a table"
    return f"a {type(v).__name__}"


def _as_number(v, key: str) -> float:
    v = _scalar(v)
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise CaseError(key, f"expected a number, got {_what(v)}")
    try:
        x = float(v)
    except OverflowError:
        x = math.inf
    if not math.isfinite(x):
        got = f"an integer of {len(str(abs(v)))} digits" if isinstance(v, int) else str(v)
        raise CaseError(key, f"must be a finite number, got {got}")
    return x


def _as_point(v, key: str) -> tuple[float, float]:
    if not isinstance(v, list) or len(v) != 2:
        got = f"{len(v)} values" if isinstance(v, list) else _what(v)
        raise CaseError(key, f"expected [x, y] (2 numbers), got {got}")
    return (_as_number(v[0], f"{key}[0]"), _as_number(v[1], f"{key}[1]"))


def _as_integer(v, key: str) -> int:
    v = _scalar(v)
    if isinstance(v, bool) or not isinstance(v, int):
        raise CaseError(key, f"expected an integer, got {_what(v)}")
    return v


def _as_boolean(v, key: str) -> bool:
    v = _scalar(v)
    if not isinstance(v, bool):
        raise CaseError(key, f"expected true or false, got {_what(v)}")
    return v


def _as_string(v, key: str) -> str:
    if not isinstance(v, str):
        raise CaseError(key, f"expected a string, got {_what(v)}")
    return v


def _as_points(v, key: str) -> np.ndarray:
    if not isinstance(v, list):
        raise CaseError(key, f"expected an array of [x, y], got {_what(v)}")
    if len(v) > MAX_ITEMS:
        raise CaseError(key, f"at most {MAX_ITEMS} points, got {len(v)}")
    pts = [_as_point(p, f"{key}[{i}]") for i, p in enumerate(v)]
    return np.array(pts, dtype=float).reshape(-1, 2)


def _as_numbers(v, key: str) -> tuple[float, ...]:
    if not isinstance(v, list):
        raise CaseError(key, f"expected an array of numbers, got {_what(v)}")
    if len(v) > MAX_ITEMS:
        raise CaseError(key, f"at most {MAX_ITEMS} numbers, got {len(v)}")
    return tuple(_as_number(x, f"{key}[{i}]") for i, x in enumerate(v))


def _as_tables(v, key: str) -> list[Table]:
    if not isinstance(v, list):
        raise CaseError(key, f"expected an array of tables ([[{key}]]), got {_what(v)}")
    if len(v) > MAX_ITEMS:
        raise CaseError(key, f"at most {MAX_ITEMS} entries, got {len(v)}")
    return [Table(item, f"{key}[{i}]") for i, item in enumerate(v)]


class Table:
    """A TOML table being read: knows its key path, reads its keys by their Keys."""

    def __init__(self, data, path: str):
        if not isinstance(data, dict):
            raise CaseError(path, f"expected a table, got {_what(data)}")
        self.data = data
        self.path = path

    def key(self, k: str) -> str:
        return f"{self.path}.{k}" if self.path else k

    def refuse_unknown(self, keys) -> None:
        """Refuse any key not among `keys`, suggesting the closest one."""
        allowed = [k.name for k in keys]
        for k in self.data:
            if not isinstance(k, str):   # Case.from_dict: a TOML key is always a string
                raise CaseError(self.key(repr(k)), f"unknown key (keys are strings, got {_what(k)})")
            if k not in allowed:
                near = difflib.get_close_matches(k, allowed, n=1)
                hint = f" (did you mean {near[0]}?)" if near else ""
                raise CaseError(self.key(k), f"unknown key{hint}")

    def read(self, keys, known: dict | None = None) -> dict:
        """{name: value} of every Key, checked, in order. `known` holds what
        was read before: the scales a Limit names and the keys a Ref names."""
        self.refuse_unknown(keys)
        values: dict = {}
        for k in keys:
            values[k.name] = self.value(k, values, known or {})
        return values

    def value(self, k: Key, values: dict | None = None, known: dict | None = None):
        """Key k's value, converted and checked (`values`: the table's keys
        read before it), or its default."""
        key = self.key(k.name)
        if k.name not in self.data:
            if k.default is REQUIRED:
                raise CaseError(key, "missing (required table)" if k.type == TABLE else "missing (required)")
            if k.required_with is not None and (values or {}).get(k.required_with[0]) == k.required_with[1]:
                other, want = k.required_with
                raise CaseError(key, f'missing (required with {other} = "{want}")')
            if isinstance(k.default, Ref):
                return known[k.default.key]
            if k.type == TABLE:  # an optional table left out reads as an empty one
                return Table({}, key)
            return [] if k.type == TABLES else k.default
        v = READERS[k.type](self.data[k.name], key)
        k.check(v, key, values or {}, known or {})
        return v


READERS = {NUMBER: _as_number, INTEGER: _as_integer, BOOLEAN: _as_boolean, STRING: _as_string, POINT: _as_point,
            POINTS: _as_points, NUMBERS: _as_numbers, TABLE: Table, TABLES: _as_tables}
