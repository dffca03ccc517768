"""3D local meshes with a core structured along the surface, the normal and x (mesh.style = "structured"):
conformity, the core's nodes on the surface normals and layer planes, quality, boundaries, inputs."""

import numpy as np
import pytest
import skfem

from wrlayer.errors import InputError
from meshes.meshing.mesh_quality import element_quality, mesh_measure, surface_deviation_mm
from meshes.meshing.section_mesh import MIN_ACCEPTED_QUALITY, default_depth_mm
from meshes.meshing.structured_core_mesh import (
    StructuredCore,
    core_for_contact,
    split_outline,
    structured_core_local_mesh,
)
from meshes.profiles import get_profile, outline_area

# the three convergence positions (crown, gauge corner, flange root) with their Hertz semi-axes (a, b), 2 cells
# per semi-axis: coarse enough to be quick
CASES = [("60E1", 0.0, 7.16, 5.39), ("60E1", -35.0, 3.51, 2.60), ("S1002", -37.5, 3.51, 2.60)]
N = 2.0


@pytest.fixture(scope="module", params=CASES, ids=[f"{c[0]}@{c[1]}" for c in CASES])
def case(request):
    name, y0, a, b = request.param
    profile = get_profile(name)
    core = core_for_contact(a, b, N)
    mesh = structured_core_local_mesh(profile, y0, core, 8.0, max(5 * a, 4 * b), order=2)
    return profile, y0, core, max(5 * a, 4 * b), mesh


def test_core_for_contact_cells():
    core = core_for_contact(7.16, 5.39, 4)
    assert (core.cells_s, core.cells_depth, core.layers) == (10, 4, 5)  # 2 ceil(1.2 n), ceil(n), ceil(1.2 n)
    assert core.half_width_mm == pytest.approx(1.2 * 5.39) and core.length_mm == pytest.approx(1.2 * 7.16)
    assert core.h_mm == pytest.approx(min(2 * 1.2 * 5.39 / 10, 5.39 / 4, 1.2 * 7.16 / 5))


def test_conforming(case):
    """No hanging nodes or duplicated interfaces: every facet lies on two tetrahedra or on a named boundary, and
    no two vertices coincide."""
    mesh = case[-1]
    assert isinstance(mesh, skfem.MeshTet2)
    on_boundary = mesh.boundary_facets()
    named = np.concatenate([mesh.boundaries[n] for n in ("surface", "side", "fixed", "symmetry", "end")])
    assert np.array_equal(np.sort(named), np.sort(on_boundary))
    # every facet is shared by two elements unless it is on the boundary
    counts = np.bincount(mesh.t2f.ravel(), minlength=mesh.facets.shape[1])
    assert set(np.unique(counts)) <= {1, 2} and np.count_nonzero(counts == 1) == on_boundary.size
    vertices = mesh.p[:, :mesh.nvertices].T
    assert len(np.unique(np.round(vertices, 9), axis=0)) == len(vertices)


def test_core_is_structured(case):
    """The core's vertices: on the layer planes x_j, and in every plane at the nodes P(s_i) - d_k n(s_i) (surface
    point and inward normal at the arc length s_i from the load point, d_k the depth nodes)."""
    profile, y0, core, _, mesh = case
    s0 = float(profile.arc_length(y0))
    s = s0 - core.s_nodes()  # the rails' and the wheel's s run in opposite senses to y: the set is symmetric
    y = profile.y_at_arc_length(s)
    surface = np.column_stack([y, profile.z(y)])
    depths = core.depth_nodes()
    nodes = (surface[:, None, :] - depths[None, :, None] * profile.normal(y)[:, None, :]).reshape(-1, 2)
    v = mesh.p[:, :mesh.nvertices]
    for x in core.x_nodes():
        plane = v[1:, np.abs(v[0] - x) < 1e-9].T
        gap = np.min(np.linalg.norm(plane[None, :, :] - nodes[:, None, :], axis=2), axis=1)
        assert gap.max() < 1e-6, f"core node missing in the plane x = {x:g} mm"
    # inside the core block (strictly), no vertex lies between the planes
    inner = (v[0] < core.length_mm - 1e-6)
    d, foot = profile.signed_distance(v[1:, inner].T)
    in_block = (-d < core.depth_mm - 1e-6) & (np.abs(profile.arc_length(foot) - s0) < core.half_width_mm - 1e-6)
    gap = np.min(np.abs(v[0, inner][in_block][:, None] - core.x_nodes()[None, :]), axis=1)
    assert gap.max() < 1e-9


def test_quality_volume_and_surface(case):
    profile, _, _, length, mesh = case
    assert element_quality(mesh).min() > MIN_ACCEPTED_QUALITY
    area = abs(outline_area(profile.section_outline(default_depth_mm(profile))))
    assert mesh_measure(mesh) == pytest.approx(area * length, rel=1e-4)
    assert surface_deviation_mm(mesh, profile) < 1e-3


def test_split_outline_keeps_a_closed_loop():
    rail = get_profile("60E1")
    outline = rail.section_outline(60.0)
    before, y_in, y_out, after = split_outline(rail, outline, -35.0, 3.12)
    assert rail.arc_length(y_in) - rail.arc_length(y_out) == pytest.approx(2 * 3.12)  # the rail runs towards -y
    assert np.allclose(before[-1].end, (y_in, rail.z(y_in))) and np.allclose(after[0].start, (y_out, rail.z(y_out)))


def test_deterministic():
    rail = get_profile("60E1")
    args = (rail, 0.0, core_for_contact(7.16, 5.39, 2), 8.0, 36.0)
    a, b = structured_core_local_mesh(*args), structured_core_local_mesh(*args)
    assert np.array_equal(a.p, b.p) and np.array_equal(a.t, b.t)


def test_graded_nodes():
    core = StructuredCore(3.0, 2.0, 4.0, 6, 3, 2, s_progression=1.5, depth_progression=1.2, x_progression=2.0)
    s = core.s_nodes()
    assert s[0] == pytest.approx(-3.0) and s[-1] == pytest.approx(3.0) and s[3] == 0.0
    assert np.diff(s)[3:] == pytest.approx(3.0 / (1 + 1.5 + 2.25) * np.array([1, 1.5, 2.25]))
    assert np.diff(core.depth_nodes())[1] / np.diff(core.depth_nodes())[0] == pytest.approx(1.2)
    assert core.x_nodes() == pytest.approx([0.0, 4.0 / 3.0, 4.0])


@pytest.mark.parametrize("kw, name", [({"cells_s": 3}, "core.cells_s"), ({"cells_depth": 0}, "core.cells_depth"),
                                      ({"layers": 2.5}, "core.layers"), ({"depth_mm": -1.0}, "core.depth_mm"),
                                      ({"depth_progression": 5.0}, "core.depth_progression")])
def test_bad_core(kw, name):
    args = {"half_width_mm": 3.0, "depth_mm": 2.0, "length_mm": 4.0, "cells_s": 4, "cells_depth": 2, "layers": 2}
    with pytest.raises(InputError) as err:
        StructuredCore(**{**args, **kw})
    assert name in str(err.value)


def test_core_past_the_profile_end_or_too_deep():
    rail = get_profile("60E1")
    with pytest.raises(InputError, match="core.half_width_mm"):
        structured_core_local_mesh(rail, -35.5, StructuredCore(5.0, 1.0, 4.0, 4, 2, 2), 8.0, 20.0)
    with pytest.raises(InputError, match="core.depth_mm"):
        structured_core_local_mesh(rail, -33.0, StructuredCore(2.0, 12.0, 4.0, 4, 2, 2), 8.0, 20.0)
