"""2D section meshes: geometry, grading, boundaries, quality, determinism, input errors (coarse meshes)."""

import gmsh
import numpy as np
import pytest
import skfem
from hypothesis import given, settings
from hypothesis import strategies as st

from wrlayer.errors import InputError
from meshes.meshing.mesh_quality import (
    edge_lengths_at,
    element_quality,
    mesh_measure,
    surface_deviation_mm,
)
from meshes.meshing.gmsh_session import initialize_gmsh
from meshes.meshing.mesh_size import GradedSize
from meshes.profiles import get_profile, outline_area
from meshes.meshing.section_mesh import DEFAULT_GRADING, default_depth_mm, section_mesh

H_MIN, H_MAX = 0.5, 5.0
CASES = [("60E1", 0.0), ("54E1", 10.0), ("S1002", 0.0), ("S1002", -30.0)]  # S1002 y0 = -30: flange root


@pytest.fixture(scope="module", params=CASES, ids=[f"{n}@{y}" for n, y in CASES])
def case(request):
    name, y0 = request.param
    profile = get_profile(name)
    return profile, y0, section_mesh(profile, y0, H_MIN, H_MAX, order=1)


def test_area_matches_the_outline(case):
    profile, _, mesh = case
    depth = default_depth_mm(profile)
    exact = profile.section_area(depth) if profile.body == "rail" else outline_area(profile.section_outline(depth))
    assert mesh_measure(mesh) == pytest.approx(exact, rel=5e-3)


def test_quadratic_mesh_is_geometry_exact_and_consistent(case):
    profile, y0, _ = case
    mesh = section_mesh(profile, y0, 1.0, 6.0, order=2)
    assert isinstance(mesh, skfem.MeshTri2)
    exact = outline_area(profile.section_outline(default_depth_mm(profile)))
    assert mesh_measure(mesh) == pytest.approx(exact, rel=1e-4)  # curved edges: far better than 0.5 %
    # every mid-edge node sits near the middle of its edge (exactly for straight interior edges)
    ends = mesh.p[:, mesh.facets]
    mid = mesh.doflocs[:, mesh.nvertices + np.arange(mesh.facets.shape[1])]
    length = np.linalg.norm(ends[:, 1] - ends[:, 0], axis=0)
    assert np.all(np.linalg.norm(mid - ends.mean(axis=1), axis=0) < 0.1 * length)
    assert surface_deviation_mm(mesh, profile) < 1e-3


def test_size_is_h_min_at_the_load_point_and_grows(case):
    profile, y0, mesh = case
    z0 = float(profile.z(y0))
    at_load = edge_lengths_at(mesh, [y0, z0]).mean()
    assert 0.5 * H_MIN <= at_load <= 1.5 * H_MIN
    # mean edge length per element against the requested size at its centroid
    corners = mesh.p[:, mesh.t]
    edges = np.linalg.norm(corners - np.roll(corners, 1, axis=1), axis=0).mean(axis=0)
    centroid = corners.mean(axis=1)
    target = GradedSize(H_MIN, H_MAX, DEFAULT_GRADING, (0.0, y0, z0)).size(
        np.c_[np.zeros(mesh.nelements), centroid.T])
    assert np.max(edges / target) < 1.4  # never coarser than asked (curvature may make it finer)
    far = np.hypot(centroid[0] - y0, centroid[1] - z0) > 15.0
    assert edges[far].mean() > 4 * H_MIN


def test_boundaries_cover_the_boundary_and_surface_lies_on_the_profile(case):
    profile, _, mesh = case
    groups = [mesh.boundaries[name] for name in ("surface", "side", "fixed")]
    assert all(len(g) > 0 for g in groups)
    together = np.concatenate(groups)
    assert len(np.unique(together)) == len(together)  # disjoint
    np.testing.assert_array_equal(np.sort(together), np.sort(mesh.boundary_facets()))
    assert surface_deviation_mm(mesh, profile) < 1e-3
    # the "fixed" cut is the straight far-field line
    depth = default_depth_mm(profile)
    z_fixed = mesh.p[1, np.unique(mesh.facets[:, mesh.boundaries["fixed"]])]
    np.testing.assert_allclose(z_fixed, -depth if profile.body == "rail" else depth, atol=1e-9)


def test_quality_and_no_orphan_nodes(case):
    _, _, mesh = case
    assert element_quality(mesh).min() > 0.3
    np.testing.assert_array_equal(np.unique(mesh.t), np.arange(mesh.nvertices))


def test_deterministic():
    profile = get_profile("S1002")
    a, b = (section_mesh(profile, 5.0, 0.7, 5.0, refine_radius_mm=2.0) for _ in range(2))
    np.testing.assert_array_equal(a.p, b.p)
    np.testing.assert_array_equal(a.t, b.t)
    assert a.boundaries.keys() == b.boundaries.keys()
    for name in a.boundaries:
        np.testing.assert_array_equal(a.boundaries[name], b.boundaries[name])


def test_refine_radius_keeps_h_min_inside_the_disc():
    profile = get_profile("60E1")
    mesh = section_mesh(profile, 0.0, 0.5, 5.0, refine_radius_mm=3.0)
    corners = mesh.p[:, mesh.t]
    centroid = corners.mean(axis=1)
    edges = np.linalg.norm(corners - np.roll(corners, 1, axis=1), axis=0).mean(axis=0)
    inside = np.hypot(centroid[0], centroid[1]) < 2.5
    assert inside.sum() > 20 and edges[inside].max() < 1.4 * 0.5


@pytest.mark.parametrize("kwargs, what", [
    ({"h_min": 0.0}, "h_min"), ({"h_min": -1.0}, "h_min"), ({"h_max": 0.0}, "h_max"),
    ({"h_min": 3.0, "h_max": 2.0}, "h_min"), ({"h_min": float("nan")}, "h_min"), ({"y0": 500.0}, "y0"),
    ({"order": 3}, "order"), ({"grading": 0.0}, "grading"), ({"depth_mm": -5.0}, "depth_mm"),
    ({"depth_mm": 30.0}, "depth_mm"),  # 60E1: above the head/web junction
    ({"refine_radius_mm": -1.0}, "refine_radius_mm"),
])
def test_bad_inputs_raise_input_error(kwargs, what):
    args = {"profile": get_profile("60E1"), "y0": 0.0, "h_min": 0.5, "h_max": 5.0} | kwargs
    with pytest.raises(InputError) as err:
        section_mesh(**args)
    assert err.value.what == what


def test_load_point_too_close_to_the_cut_is_rejected():
    wheel = get_profile("S1002")
    with pytest.raises(InputError, match="depth_mm"):
        section_mesh(wheel, 0.0, 2.0, 5.0, depth_mm=5.0)  # only 5 mm of rim above the taping line


class _BrokenOutline:
    """A real profile whose outline has a gap: Gmsh is running when the error is raised."""

    def __init__(self, profile):
        self._profile = profile

    def __getattr__(self, name):
        return getattr(self._profile, name)

    def section_outline(self, depth_mm):
        return self._profile.section_outline(depth_mm)[1:]


def test_gmsh_is_finalised_after_an_error_and_the_next_call_works():
    profile = get_profile("60E1")
    with pytest.raises(InputError, match="closed"):
        section_mesh(_BrokenOutline(profile), 0.0, 1.0, 5.0)
    assert not gmsh.isInitialized()
    assert section_mesh(profile, 0.0, 1.0, 5.0).nelements > 0


def test_session_leaves_a_caller_initialised_gmsh_alone():
    initialize_gmsh()  # not gmsh.initialize: that would leave this test process's signal dispositions changed
    try:
        gmsh.model.add("caller")
        models = gmsh.model.list()
        section_mesh(get_profile("S1002"), 0.0, 1.0, 5.0)
        assert gmsh.isInitialized()
        assert gmsh.model.list() == models
        assert gmsh.model.getCurrent() == "caller"
    finally:
        gmsh.finalize()


@settings(max_examples=8, deadline=None)
@given(name=st.sampled_from(["60E1", "54E1", "S1002"]), where=st.floats(0.0, 1.0), h_min=st.floats(0.15, 1.0))
def test_any_load_position_gives_a_good_mesh(name, where, h_min):
    profile = get_profile(name)
    y0 = profile.y_min + where * (profile.y_max - profile.y_min)
    mesh = section_mesh(profile, y0, h_min, 6.0)
    assert 0.5 * h_min <= edge_lengths_at(mesh, [y0, float(profile.z(y0))]).mean() <= 1.5 * h_min
    assert element_quality(mesh).min() > 0.3
    assert surface_deviation_mm(mesh, profile) < 1e-3
