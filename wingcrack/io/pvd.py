"""ParaView collection files (.pvd): one index per series of step files, so
that ParaView opens a whole run as one time series.

The time of each entry is the step number, not the load factor: the load
factor repeats when growth is unstable (no load increase is needed for the
next step) and may even fall, and ParaView needs strictly increasing times.
A run with a physical time (a pump: load = "injection") has the steps'
times instead (s; steps at one time, unstable growth, a rounding apart:
`increasing`). The load factor is in each step file's field data
(`load_factor`, with `step`, and `time` where there is one); ParaView shows
it with "Annotate Global Data" or plots it with "Plot Data Over Time".
"""
from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

from .atomic import write_atomic


def write_pvd(path, files, times=None) -> Path:
    """Write the collection `path` listing `files` (names relative to the
    folder of `path`) at `times` (default 0, 1, 2, ...; strictly
    increasing). Written atomically (rewritten after every step)."""
    path = Path(path)
    files = [str(f) for f in files]
    times = list(range(len(files))) if times is None else [float(t) for t in times]
    if len(times) != len(files):
        raise ValueError(f"{len(files)} files but {len(times)} times")
    if any(b <= a for a, b in zip(times, times[1:])):
        raise ValueError("the times of a .pvd collection must increase strictly")
    root = ET.Element("VTKFile", type="Collection", version="0.1", byte_order="LittleEndian")
    collection = ET.SubElement(root, "Collection")
    for t, name in zip(times, files):
        ET.SubElement(collection, "DataSet", timestep=repr(t), group="", part="0", file=name)
    ET.indent(root)
    write_atomic(path, ET.tostring(root, encoding="utf-8", xml_declaration=True))
    return path


def increasing(times) -> list[float]:
    """`times` (non-decreasing) made strictly increasing by the least change:
    a time equal to the one before becomes the next float above it."""
    out = []
    for t in times:
        t = float(t)
        out.append(t if not out or t > out[-1] else float(np.nextafter(out[-1], np.inf)))
    return out


def read_pvd(path) -> list[tuple[float, str]]:
    """[(time, file)] of a collection, in file order."""
    root = ET.parse(path).getroot()
    return [(float(d.get("timestep")), d.get("file")) for d in root.iter("DataSet")]
