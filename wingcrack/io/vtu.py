"""VTU files (VTK XML unstructured grid, inline base64 of zlib blocks) in one
pass: the layout meshio 5 writes, with the field data in it (meshio 5
writes none), so that a step file is not read back and rewritten to add
its step and load factor.

The text is the one meshio's writer and a rewrite adding the field data
gave together (tests/command_line/test_output_vtu.py keeps that route as the
reference): attributes, line breaks, the FieldData element at the head
of UnstructuredGrid, byte for byte at the same zlib level; every reader
of those files (meshio, VTK's vtkXMLUnstructuredGridReader, ParaView)
reads these. Each array is cut into blocks of BLOCK bytes, each block a
zlib stream of its own, and a UInt32 header (number of blocks, block
size, size of the last block, compressed size of each) goes first, as
VTK's vtkZLibDataCompressor reads it. The streams are deflated by ISA-L
(the isal package) where it is installed, else by zlib's fastest level
(FAST): the bytes differ from meshio's (zlib level 6), the data they
inflate to do not.

Every number of a file is finite: a NaN or inf in the points, a point or
cell array or the field data is a bug upstream, and vtu_chunks raises
(ValueError naming the array) before the first byte, so no such file is
written.

The file is written to a temporary name in the same folder, synced and
renamed (io/atomic.py): a run stopped while writing leaves no half file
under the step's name.
"""
from __future__ import annotations

import base64
import zlib
from pathlib import Path

import numpy as np

from .atomic import write_atomic

#: bytes of an array compressed as one zlib stream (meshio's and VTK's block size)
BLOCK = 32768
# Deflating is most of the cost of a step file. ISA-L's deflate (its default
# level 2) makes zlib streams that zlib and VTK inflate as any other, faster
# than zlib's fastest level and about as small as zlib's default level 6;
# without it, zlib's fastest level (somewhat larger files than level 6).
try:
    from isal.isal_zlib import compress as _fast_compress
    FAST = ("isal", 2)
except ImportError:
    from zlib import compress as _fast_compress
    FAST = ("zlib", 1)
#: VTK cell type codes of the cell kinds wingcrack writes (meshio's names)
VTK_TYPES = {"line3": 21, "triangle6": 22}
_VTU_TYPES = {np.dtype(np.float64): "Float64", np.dtype(np.float32): "Float32", np.dtype(np.int64): "Int64",
              np.dtype(np.int32): "Int32", np.dtype(np.int8): "Int8", np.dtype(np.uint8): "UInt8"}


def _attr(value) -> str:
    return str(value).replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;").replace('"', "&quot;")


def _deflate(level: int | None):
    if level is None:
        return lambda block: _fast_compress(block, FAST[1])
    return lambda block: zlib.compress(block, level)


def encode(data: np.ndarray, level: int | None = None) -> bytes:
    """The base64 text of `data` as a compressed binary DataArray: the
    header, then the blocks (each part base64-encoded on its own, as VTK
    reads it). level: None, the fast deflate (FAST); a number, zlib's
    level (6: zlib's default, meshio's)."""
    deflate = _deflate(level)
    raw = np.ascontiguousarray(data).reshape(-1).view(np.uint8)
    n = len(raw)
    count = -(-n // BLOCK)
    blocks = [deflate(raw[i:i + BLOCK]) for i in range(0, n, BLOCK)]
    header = np.array([count, BLOCK, n - (count - 1) * BLOCK] + [len(b) for b in blocks], dtype="<u4")
    return base64.b64encode(header.tobytes()) + base64.b64encode(b"".join(blocks))


def _data_array(name: str, data: np.ndarray, level: int | None) -> tuple[bytes, ...]:
    data = np.asarray(data)
    data = data.astype(data.dtype.newbyteorder("<"), copy=False)   # the file says LittleEndian
    kind = _VTU_TYPES.get(data.dtype)
    if kind is None:
        raise TypeError(f"{name}: no VTU type for {data.dtype}")
    comps = f' NumberOfComponents="{data.shape[1]}"' if data.ndim == 2 else ""
    head = f'<DataArray type="{kind}" Name="{_attr(name)}"{comps} format="binary">\n'.encode()
    return head, encode(data, level), b"\n</DataArray>\n"


def require_finite(name: str, data) -> None:
    """ValueError when the array `data` (called `name` in the file) holds a
    NaN or inf: how many of its rows, and the first."""
    data = np.atleast_1d(np.asarray(data))
    if data.dtype.kind != "f":
        return   # integers are finite
    finite = np.isfinite(data)
    bad = ~finite.all(axis=tuple(range(1, finite.ndim)))   # per entry (row)
    if bad.any():
        rows = np.flatnonzero(bad)
        raise ValueError(f"{name} is not finite at {len(rows)} of {len(bad)} entries (the first: {rows[0]}, "
                         f"{data[rows[0]]}): a VTU file is written only with finite values")


def all_finite(points, point_data: dict | None, cell_data: dict | None, field_data: dict | None) -> None:
    """require_finite of every number a VTU file of these would hold."""
    require_finite("Points", points)
    for name, data in (point_data or {}).items():
        require_finite(f"point data {name!r}", data)
    for name, data in (cell_data or {}).items():
        for block in data:
            require_finite(f"cell data {name!r}", block)
    for name, value in (field_data or {}).items():
        require_finite(f"field data {name!r}", np.array([float(value)]))


def vtu_chunks(points: np.ndarray, cells: list, point_data: dict, cell_data: dict | None = None,
               field_data: dict | None = None, level: int | None = None):
    """The text of a VTU file, in pieces (a generator: one array is encoded
    at a time): `points` (n, 3), `cells` [(kind, (m, k) node indices)] with
    kind a key of VTK_TYPES, `point_data` {name: (n,) or (n, c)},
    `cell_data` {name: [an array per cell block]}, `field_data` {name:
    number} (written as Float64, in ascii as that rewrite wrote
    them); level as for encode."""
    points = np.asarray(points)
    if points.ndim != 2 or points.shape[1] != 3:
        raise ValueError(f"points must be (n, 3), not {points.shape}")
    blocks = [(kind, np.asarray(c)) for kind, c in cells]
    all_finite(points, point_data, cell_data, field_data)
    yield (b"<?xml version='1.0' encoding='utf-8'?>\n"
           b'<VTKFile type="UnstructuredGrid" version="0.1" byte_order="LittleEndian" '
           b'compressor="vtkZLibDataCompressor">\n'
           b"<!--This file was created by wingcrack (the layout of meshio v5.0.0)-->\n"
           b"<UnstructuredGrid>\n")
    if field_data:
        yield b"<FieldData>" + b"".join(
            f'<DataArray type="Float64" Name="{_attr(k)}" NumberOfTuples="1" format="ascii">{float(v)!r}'
            f"</DataArray>".encode() for k, v in field_data.items()) + b"</FieldData>"
    yield (f'<Piece NumberOfPoints="{len(points)}" NumberOfCells="{sum(len(c) for _, c in blocks)}">\n'
           "<Points>\n").encode()
    yield from _data_array("Points", points, level)
    yield b"</Points>\n"
    if blocks:
        conn = np.concatenate([c.reshape(-1) for _, c in blocks])
        ends, at = [], 0
        for _, c in blocks:   # offset: the end of each cell in the connectivity
            ends.append(at + c.shape[1] * np.arange(1, len(c) + 1, dtype=conn.dtype))
            at += c.size
        yield b"<Cells>\n"
        yield from _data_array("connectivity", conn, level)
        yield from _data_array("offsets", np.concatenate(ends), level)
        yield from _data_array("types", np.concatenate([np.full(len(c), VTK_TYPES[kind]) for kind, c in blocks]),
                               level)
        yield b"</Cells>\n"
    if point_data:
        yield b"<PointData>\n"
        for name, data in point_data.items():
            yield from _data_array(name, data, level)
        yield b"</PointData>\n"
    if cell_data:
        yield b"<CellData>\n"
        for name, data in cell_data.items():
            yield from _data_array(name, np.concatenate([np.asarray(d) for d in data]), level)
        yield b"</CellData>\n"
    yield b"</Piece>\n</UnstructuredGrid>\n</VTKFile>"


def write_vtu(path, points, cells: list, point_data: dict, cell_data: dict | None = None,
              field_data: dict | None = None, level: int | None = None) -> Path:
    """Write the VTU file `path` of vtu_chunks(...) atomically, each array
    as it is encoded; ValueError, naming the file and the array, and no
    file when a value is not finite."""
    try:
        all_finite(points, point_data, cell_data, field_data)
    except ValueError as err:
        raise ValueError(f"{Path(path).name}: {err}") from None
    return write_atomic(path, vtu_chunks(points, cells, point_data, cell_data, field_data, level))
