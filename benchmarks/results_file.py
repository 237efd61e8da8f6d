"""A benchmark's results file (benchmarks/*.json, rendered on the performance
page by doc_tables.py): what was measured and when, how, the load average
before and after on how many cores, and the figures."""
from __future__ import annotations

import json
import os
import time
from pathlib import Path


def load() -> float:
    """The 1-minute load average now (a shared machine's: noted beside the figures)."""
    return round(os.getloadavg()[0], 2)


def write(path: Path, about: str, how: str, loads: list, **figures) -> None:
    """The file at `path`: `about` stamped with the time (UTC), `how`, `load`
    [before, after], `cores`, then the figures."""
    path.write_text(json.dumps({"about": f"{about}, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}",
                               "how": how, "load": loads, "cores": os.cpu_count(), **figures}, indent=1) + "\n")
