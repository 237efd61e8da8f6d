"""Process helpers for the tests of the worker processes."""
from __future__ import annotations


def alive(pid) -> bool:
    """Running (a zombie waiting for a reaper that may never come is dead)."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except FileNotFoundError:
        return False
