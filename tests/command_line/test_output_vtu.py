"""io/vtu.py, the one-pass writer of the step and face files, against the
route it replaced: meshio 5's VTU writer followed by io.pvd.add_field_data,
which read the file back and rewrote it with the field data.

- At meshio's zlib level (6) the two give the same bytes (but for the
  comment that names the writer): the same XML, the same blocks.
- With the deflate the runs use (vtu.FAST: ISA-L's, or zlib's level 1
  without the isal package) the blocks differ but decompress to the same
  data: meshio reads the same arrays back, exactly, the same
  field data and the same XML elements and attributes; and a decoder
  written here from the VTK format's description (UInt32 header, one zlib
  stream per block) gets the arrays' bytes.
- On a solved disc, write_step_files gives the files the old route gives
  for the same solution.
- A write that fails or is interrupted half-way leaves neither a file under
  the name nor a temporary file (io/atomic.py); the temporary file of a
  process killed outright goes when the folder is prepared for a result.
- A NaN or inf in any array or field datum is refused (a bug upstream,
  not a value): ValueError naming the file and the array, nothing written.
"""
from __future__ import annotations

import base64
import xml.etree.ElementTree as ET
import zlib
from pathlib import Path

import meshio
import numpy as np
import pytest

from wingcrack.io import vtu

MESHIO_5_0 = meshio.__version__ == "5.0.0"


def add_field_data(path, values: dict) -> Path:
    """The route io/vtu.py replaced, kept here as its reference: put {name:
    number} into the field data of the meshio 5 VTU file `path` (meshio 5
    writes none) by parsing and rewriting it."""
    path = Path(path)
    tree = ET.parse(path, parser=ET.XMLParser(target=ET.TreeBuilder(insert_comments=True)))
    grid = tree.getroot().find("UnstructuredGrid")
    if grid is None:
        raise ValueError(f"{path}: not an unstructured-grid VTU file")
    for old in grid.findall("FieldData"):
        grid.remove(old)
    data = ET.Element("FieldData")
    for name, value in values.items():
        array = ET.SubElement(data, "DataArray", type="Float64", Name=str(name), NumberOfTuples="1",
                              format="ascii")
        array.text = repr(float(value))
    grid.insert(0, data)
    tree.write(path, encoding="utf-8", xml_declaration=True)
    return path


def reference_write(path, points, cells, point_data, cell_data=None, field_data=None, level=None):
    """The previous route: meshio writes, add_field_data rewrites."""
    meshio.Mesh(points, cells, point_data=point_data, cell_data=cell_data or {}).write(Path(path))
    if field_data:
        add_field_data(path, field_data)
    return Path(path)


def field_file(n_cells=2000, seed=1):
    """A P2-like triangle mesh's arrays (node numbers in order, values
    random): several 32 KiB blocks per array and a part block at the end."""
    rng = np.random.default_rng(seed)
    cells = rng.permutation(6 * n_cells).reshape(-1, 6).astype(np.int64)
    n = 6 * n_cells
    points = np.c_[rng.normal(size=(n, 2)), np.zeros(n)]
    stress = rng.normal(size=(n, 9)) * 1e6
    vm = np.abs(stress[:, 0])
    return (points, [("triangle6", cells)],
            {"displacement": np.c_[rng.normal(size=(n, 2)) * 1e-5, np.zeros(n)], "stress": stress, "von_mises": vm},
            None, {"step": 3, "load_factor": 1.25})


def face_file(n_edges=40):
    """A face file's arrays: line3 cells, float and Int8 point data, Int64
    cell data, the field data of a step and the state codes."""
    n = 2 * n_edges + 1
    cells = np.c_[2 * np.arange(n_edges), 2 * np.arange(n_edges) + 2, 2 * np.arange(n_edges) + 1]
    x = np.c_[np.linspace(-1, 1, n), np.zeros((n, 2))]
    data = {"opening": np.linspace(0, 1e-4, n), "slip": -np.linspace(0, 1e-5, n), "closed": (np.arange(n) % 2) * 1.0,
            "state": (np.arange(n) % 3).astype(np.int8)}
    return (x, [("line3", cells.astype(np.int64))], data, {"fracture": [np.arange(n_edges) % 2]},
            {"step": 0, "load_factor": 0.5, "state_open": 0, "state_stick": 1, "state_slip": 2})


def empty_face_file():
    """A case without fractures: no nodes, one empty block of line3 cells."""
    return (np.zeros((0, 3)), [("line3", np.zeros((0, 3), np.int64))], {"opening": np.zeros(0)},
            {"fracture": [np.zeros(0, np.int64)]}, {"step": 0, "load_factor": 1.0})


def same_comment(text: bytes) -> bytes:
    return text.replace(b"created by meshio v5.0.0", b"created by wingcrack (the layout of meshio v5.0.0)")


def skeleton(path):
    """Every element's tag, attributes and ascii text (the field data), in
    document order: the XML without the binary payloads."""
    root = ET.parse(path).getroot()
    return [(e.tag, dict(e.attrib), e.text if e.get("format") == "ascii" else None) for e in root.iter()]


@pytest.mark.skipif(not MESHIO_5_0, reason="the layout is meshio 5.0.0's")
@pytest.mark.parametrize("make", [field_file, face_file, empty_face_file])
def test_same_bytes_as_meshio_and_add_field_data_at_meshios_level(tmp_path, make):
    args = make()
    ref = reference_write(tmp_path / "ref.vtu", *args)
    new = vtu.write_vtu(tmp_path / "new.vtu", *args, level=6)   # zlib.compress's default, meshio's
    assert new.read_bytes() == same_comment(ref.read_bytes())


@pytest.mark.parametrize("level", [None, 1], ids=["fast", "zlib-1"])
@pytest.mark.parametrize("make", [field_file, face_file])
def test_the_runs_deflate_reads_back_to_the_same_arrays_and_field_data(tmp_path, make, level):
    args = make()
    ref = meshio.read(reference_write(tmp_path / "ref.vtu", *args))
    path = vtu.write_vtu(tmp_path / "new.vtu", *args, level=level)
    new = meshio.read(path)
    assert np.array_equal(new.points, ref.points)
    assert [c.type for c in new.cells] == [c.type for c in ref.cells]
    for a, b in zip(new.cells, ref.cells):
        assert a.data.dtype == b.data.dtype and np.array_equal(a.data, b.data)
    assert list(new.point_data) == list(ref.point_data)
    for name, value in ref.point_data.items():
        assert new.point_data[name].dtype == value.dtype
        assert np.array_equal(new.point_data[name], value), name
    assert list(new.cell_data) == list(ref.cell_data)
    for name, value in ref.cell_data.items():
        assert all(np.array_equal(a, b) for a, b in zip(new.cell_data[name], value))
    assert {k: float(v[0]) for k, v in new.field_data.items()} == {k: float(v) for k, v in args[4].items()}
    assert skeleton(path) == skeleton(tmp_path / "ref.vtu")


def decode_vtk(text: str, dtype) -> np.ndarray:
    """A binary DataArray's text as VTK's XML reader decodes it (header_type
    UInt32, vtkZLibDataCompressor): the header's three numbers (blocks,
    block size, size of the last block) and the compressed sizes, base64
    on their own; then the blocks, base64 together."""
    text = text.strip()
    first = base64.b64decode(text[:16])   # 12 bytes of header: 16 base64 characters
    nb, size, last = np.frombuffer(first[:12], "<u4")
    head_len = 4 * -(-(4 * (3 + int(nb))) // 3)
    header = np.frombuffer(base64.b64decode(text[:head_len]), "<u4")
    sizes = header[3:3 + nb]
    data = base64.b64decode(text[head_len:])
    assert len(data) == sizes.sum()
    raw, at = [], 0
    for i, s in enumerate(sizes):
        block = zlib.decompress(data[at:at + s])
        assert len(block) == (last if i == nb - 1 else size)
        raw.append(block)
        at += s
    return np.frombuffer(b"".join(raw), dtype)


def test_blocks_decode_as_the_vtk_format_describes(tmp_path):
    points, cells, point_data, _, _ = field_file()
    path = vtu.write_vtu(tmp_path / "new.vtu", points, cells, point_data)
    root = ET.parse(path).getroot()
    assert root.get("compressor") == "vtkZLibDataCompressor" and root.get("header_type") is None   # UInt32
    arrays = {a.get("Name"): a for a in root.iter("DataArray")}
    want = {"Points": points, "connectivity": cells[0][1].ravel(), **point_data}
    for name, value in want.items():
        got = decode_vtk(arrays[name].text, value.dtype)
        assert np.array_equal(got, value.ravel()), name
        if value.ndim == 2:
            assert arrays[name].get("NumberOfComponents") == str(value.shape[1])
    # the offsets are the ends of the cells, the types VTK's quadratic triangle
    assert np.array_equal(decode_vtk(arrays["offsets"].text, np.int64), 6 * np.arange(1, len(cells[0][1]) + 1))
    assert set(decode_vtk(arrays["types"].text, np.int64)) == {22}


def test_without_isal_the_fast_deflate_is_zlibs_fastest(tmp_path, monkeypatch):
    import importlib
    import sys

    args = field_file()
    monkeypatch.setitem(sys.modules, "isal.isal_zlib", None)   # its import fails
    try:
        importlib.reload(vtu)
        assert vtu.FAST == ("zlib", 1)
        fallback = vtu.write_vtu(tmp_path / "fallback.vtu", *args)
    finally:
        monkeypatch.undo()
        importlib.reload(vtu)
    assert fallback.read_bytes() == vtu.write_vtu(tmp_path / "zlib1.vtu", *args, level=1).read_bytes()


class Interrupting:
    """An array whose conversion is interrupted (Ctrl-C while the file is
    half written)."""

    def __array__(self, dtype=None):
        raise KeyboardInterrupt


@pytest.mark.parametrize("bad, error", [(np.zeros(6 * 2000, dtype=bool), TypeError),
                                        (Interrupting(), KeyboardInterrupt)])
def test_a_write_stopped_half_way_leaves_the_previous_file_and_no_other(tmp_path, bad, error):
    points, cells, point_data, _, fd = field_file()
    path = vtu.write_vtu(tmp_path / "step_0000.vtu", points, cells, point_data, field_data=fd)
    before = path.read_bytes()
    with pytest.raises(error):   # the last point array cannot be written: the file is half done then
        vtu.write_vtu(path, points, cells, {**point_data, "bad": bad}, field_data=fd)
    assert path.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["step_0000.vtu"]
    with pytest.raises(error):
        vtu.write_vtu(tmp_path / "step_0001.vtu", points, cells, {**point_data, "bad": bad}, field_data=fd)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["step_0000.vtu"]


def test_the_temporary_file_of_a_killed_write_goes_with_the_next_result(tmp_path):
    import tempfile

    from wingcrack.io.atomic import temporary_of
    from wingcrack.io.outdir import leftovers, prepare

    names = ["step_0003.vtu", "faces_0003.vtu", "summary.json", "checkpoint.npz", "fields.pvd"]
    left = [Path(tempfile.mkstemp(prefix=f".{Path(n).stem}.", dir=tmp_path)[1]) for n in names]   # as write_atomic
    assert [temporary_of(p.name) for p in left] == [Path(n).stem for n in names]
    kept = [tmp_path / ".notes.txt", tmp_path / "my_data.vtu", tmp_path / ".step_0003.vtu"]
    for p in kept:
        p.write_text("not ours")
    assert leftovers(tmp_path) == sorted(left)
    prepare(tmp_path)   # no result in it: not refused, and the leftovers go
    assert sorted(tmp_path.iterdir()) == sorted(kept)


@pytest.fixture(scope="module")
def solved_disc():
    """The open 45-degree disc of cases/, its first mesh, solved at load
    factor 1 (a real CrackMesh and solution: quarter-point tips, faces)."""
    from wingcrack.case import Case
    from wingcrack.propagation.fracture_set import FractureSet
    from wingcrack.step import Timer, discretise

    case = Case.from_toml(Path(__file__).parents[2] / "cases" / "brazilian_disc_45_open.toml")
    disc = discretise(case, FractureSet.from_case(case).fractures, Timer())
    disc.solver.solve(1.0)
    return disc


def test_step_files_of_a_solution_hold_what_the_previous_writer_wrote(tmp_path, monkeypatch, solved_disc):
    from wingcrack.step import write_step_files

    (tmp_path / "new").mkdir()
    (tmp_path / "ref").mkdir()
    write_step_files(tmp_path / "new", 2, 1.5, solved_disc)
    monkeypatch.setattr(vtu, "write_vtu", reference_write)   # fields.py and faces.py take it at each call
    write_step_files(tmp_path / "ref", 2, 1.5, solved_disc)
    for name in ("step_0002.vtu", "faces_0002.vtu"):
        a, b = meshio.read(tmp_path / "new" / name), meshio.read(tmp_path / "ref" / name)
        assert np.array_equal(a.points, b.points)
        assert all(x.type == y.type and np.array_equal(x.data, y.data) for x, y in zip(a.cells, b.cells))
        assert list(a.point_data) == list(b.point_data)
        for k in b.point_data:
            assert a.point_data[k].dtype == b.point_data[k].dtype
            assert np.array_equal(a.point_data[k], b.point_data[k]), (name, k)
        for k in b.cell_data:
            assert all(np.array_equal(x, y) for x, y in zip(a.cell_data[k], b.cell_data[k]))
        assert {k: v.tolist() for k, v in a.field_data.items()} == {k: v.tolist() for k, v in b.field_data.items()}
        assert skeleton(tmp_path / "new" / name) == skeleton(tmp_path / "ref" / name)
    for name in ("fields.pvd", "faces.pvd"):
        assert (tmp_path / "new" / name).read_bytes() == (tmp_path / "ref" / name).read_bytes()
    assert meshio.read(tmp_path / "new" / "step_0002.vtu").field_data["load_factor"][0] == 1.5


@pytest.mark.parametrize("where", ["points", "point data", "cell data", "field data"])
@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_a_value_that_is_not_finite_is_refused_and_nothing_written(tmp_path, where, bad):
    points, cells, point_data, _, fd = field_file()
    path = vtu.write_vtu(tmp_path / "step_0000.vtu", points, cells, point_data, field_data=fd)
    before = path.read_bytes()
    points, point_data, fd = points.copy(), {k: v.copy() for k, v in point_data.items()}, dict(fd)
    cell_data = {"fracture": [np.zeros(len(cells[0][1]))]}
    name = {"points": "Points", "point data": "point data 'stress'", "cell data": "cell data 'fracture'",
            "field data": "field data 'load_factor'"}[where]
    if where == "points":
        points[5, 1] = bad
    elif where == "point data":
        point_data["stress"][9, 4] = bad
    elif where == "cell data":
        cell_data["fracture"][0][3] = bad
    else:
        fd["load_factor"] = bad
    for target in ("step_0000.vtu", "step_0001.vtu"):
        with pytest.raises(ValueError) as err:
            vtu.write_vtu(tmp_path / target, points, cells, point_data, cell_data=cell_data, field_data=fd)
        assert str(err.value).startswith(f"{target}: {name} is not finite at 1 of "), str(err.value)
    assert path.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["step_0000.vtu"]
