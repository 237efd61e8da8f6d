"""The boundary facet tags of to_dolfinx on one process
(fem.mesh._facet_tags_one_process, a search on sorted facet vertex pairs)
against DOLFINx's own route (distribute_entity_data +
meshtags_from_entities), the second method: the same facets with the same
tags, exactly (integers); and against the geometry: every tagged facet's
two vertices are the two end nodes of its mesher edge."""
import numpy as np
import pytest
from dolfinx import cpp as _cpp
from dolfinx import mesh as dmesh

from builders import brazilian_disc, square_plate_with_cracks
from wingcrack.case import Case
from wingcrack.fem import mesh as femesh
from wingcrack.step import Timer, discretise


def cases():
    t = np.array([np.sin(np.radians(60)), np.cos(np.radians(60))])
    plate = square_plate_with_cracks(40.0, [[-t, t]], (2.0e5, -1.0e6, 3.0e5), size=2.0, tip_size=0.2)
    return {"plate": Case.from_dict(plate), "disc": Case.from_dict(brazilian_disc(45.0))}


@pytest.mark.parametrize("name", ["plate", "disc"])
def test_facet_tags_equal_dolfinx_route(name):
    case = cases()[name]
    cm = discretise(case, case.fractures, Timer()).cm
    fm = femesh.to_dolfinx(cm)
    msh, tdim = fm.mesh, fm.mesh.topology.dim
    facets = np.asarray(cm.boundary_edges, dtype=np.int64)
    values = np.asarray(cm.boundary_tags, dtype=np.int32)
    entities, vals = _cpp.io.distribute_entity_data(msh._mesh, tdim - 1, facets, values)
    ref = dmesh.meshtags_from_entities(msh, tdim - 1, _cpp.graph.AdjacencyList_int32(entities),
                                       vals.astype(np.int32))
    assert len(fm.facet_tags.indices) == len(facets) > 0
    assert np.array_equal(fm.facet_tags.indices, ref.indices)
    assert np.array_equal(fm.facet_tags.values, ref.values)
    # geometry: the facet's vertices sit at its mesher edge's end nodes (bitwise: the same coordinates)
    f2v = msh.topology.connectivity(tdim - 1, 0)
    vx = _cpp.mesh.entities_to_geometry(msh._mesh, 0, np.arange(msh.topology.index_map(0).size_local,
                                                                 dtype=np.int32), False).ravel()
    xy = msh.geometry.x[:, :2]
    got = {tuple(sorted(map(tuple, xy[vx[f2v.links(f)]]))): v for f, v in zip(fm.facet_tags.indices,
                                                                              fm.facet_tags.values)}
    want = {tuple(sorted(map(tuple, np.asarray(cm.x)[e[:2]]))): v for e, v in zip(facets, values)}
    assert got == want


def test_an_edge_that_is_no_facet_falls_back():
    """An edge joining two vertices no facet joins: None (to_dolfinx then
    takes DOLFINx's route)."""
    case = cases()["plate"]
    cm = discretise(case, case.fractures, Timer()).cm
    fm = femesh.to_dolfinx(cm)
    facets = np.asarray(cm.boundary_edges, dtype=np.int64)
    a, b = facets[0, 0], facets[len(facets) // 2, 0]   # two boundary vertices far apart
    bad = np.vstack([facets, [[a, b, facets[0, 2]]]])
    values = np.r_[cm.boundary_tags, 1].astype(np.int32)
    assert femesh._facet_tags_one_process(fm.mesh, bad, values) is None
    assert femesh._facet_tags_one_process(fm.mesh, np.vstack([facets, facets[:1]]),
                                          np.r_[cm.boundary_tags, 1].astype(np.int32)) is None   # tagged twice
