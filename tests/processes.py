"""Process helpers for the tests of the worker processes."""
from __future__ import annotations

import time


def alive(pid) -> bool:
    """Running (a zombie waiting for a reaper that may never come is dead)."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except FileNotFoundError:
        return False


def working(seconds: float) -> tuple[float, float]:
    """(start, end) wall-clock times of `seconds` of work (a sleep), for a
    test that asks when a worker process was busy (one clock for every
    process of the machine)."""
    start = time.time()
    time.sleep(seconds)
    return start, time.time()
