"""A step's files in the output folder: step_XXXX.vtu (the displacement and
stress fields), faces_XXXX.vtu (the faces' values) and the two ParaView
indices over the steps so far (io/outdir.py names them)."""
from __future__ import annotations

from pathlib import Path

from .face_values import face_values
from .io.faces import write_faces
from .io.fields import write_field_arrays
from .io.outdir import FACES_PVD, FIELDS_PVD, SUMMARY, faces_name, fields_name
from .io.pvd import increasing, write_pvd
from .parallel import on_root


def write_step_files(out, k: int, load_factor: float, disc, times=None) -> None:
    """step_XXXX.vtu and faces_XXXX.vtu of step k (with the step and its
    load factor as field data, and its time where `times`, the times of
    steps 0..k, are given: then the ParaView indices' time axis), and the
    two ParaView indices over steps 0..k, rewritten so that an interrupted
    run keeps a complete index.
    Collective: the values are gathered first, then rank 0 writes, and a
    file it cannot write (WriteError) is raised on every rank (parallel.on_root:
    otherwise the others would wait for rank 0 in the next step). disc: the
    step's step.Discretisation at its solution."""
    out = Path(out)
    about = {"step": k, "load_factor": load_factor}
    axis = None if times is None else increasing(times)
    if times is not None:
        about["time"] = float(times[k])
    fields = disc.problem.nodal_fields(len(disc.cm.x), [t.node for t in disc.cm.tips])   # on rank 0
    faces = face_values(disc)

    def write():
        write_field_arrays(out / fields_name(k), disc.cm, fields, field_data=about)
        write_faces(out / faces_name(k), disc.cm, faces, field_data=about)
        write_pvd(out / FIELDS_PVD, [fields_name(j) for j in range(k + 1)], axis)
        write_pvd(out / FACES_PVD, [faces_name(j) for j in range(k + 1)], axis)

    on_root(write)


def files_of(out, n: int) -> dict:
    """{name: path} of the data files of a result of n steps in `out`
    (span names such as step_{0000..0014}.vtu; the pictures are added by
    api)."""
    def span(name):
        return name(0) if n == 1 else name(0).replace("0000", f"{{0000..{n - 1:04d}}}")

    out = Path(out)
    files = {"summary": out / SUMMARY}
    if n:   # one field file and one face file per step, and their indices
        files.update(fields=out / span(fields_name), faces=out / span(faces_name),
                     fields_pvd=out / FIELDS_PVD, faces_pvd=out / FACES_PVD)
    return files
