"""3D local meshes: volume, boundaries, refinement, quality, determinism, order 2, input errors; mesh files."""

import meshio
import numpy as np
import pytest
import skfem

from wrlayer.errors import InputError
from meshes.meshing.local_mesh import local_mesh
from meshes.meshing.mesh_io import write_mesh
from meshes.meshing.mesh_quality import (
    edge_lengths_at,
    element_quality,
    mesh_measure,
    surface_deviation_mm,
)
from meshes.profiles import get_profile, outline_area
from meshes.meshing.section_mesh import default_depth_mm

H_MIN, H_MAX, LENGTH = 1.0, 8.0, 20.0
CASES = [("60E1", 5.0), ("S1002", -30.0)]


@pytest.fixture(scope="module", params=CASES, ids=[f"{n}@{y}" for n, y in CASES])
def case(request):
    name, y0 = request.param
    profile = get_profile(name)
    return profile, y0, local_mesh(profile, y0, H_MIN, H_MAX, length_mm=LENGTH, refine_box=(2.0, 2.0, 1.0))


def test_volume_is_section_area_times_length(case):
    profile, _, mesh = case
    assert isinstance(mesh, skfem.MeshTet1)
    area = outline_area(profile.section_outline(default_depth_mm(profile)))
    assert mesh_measure(mesh) == pytest.approx(area * LENGTH, rel=5e-3)


def test_named_boundaries(case):
    profile, _, mesh = case
    names = ("surface", "side", "fixed", "symmetry", "end")
    groups = [mesh.boundaries[n] for n in names]
    assert all(len(g) > 0 for g in groups)
    together = np.concatenate(groups)
    assert len(np.unique(together)) == len(together)
    np.testing.assert_array_equal(np.sort(together), np.sort(mesh.boundary_facets()))
    x_of = {n: mesh.p[0, np.unique(mesh.facets[:, mesh.boundaries[n]])] for n in names}
    np.testing.assert_allclose(x_of["symmetry"], 0.0, atol=1e-9)
    np.testing.assert_allclose(x_of["end"], LENGTH, atol=1e-9)
    assert surface_deviation_mm(mesh, profile) < 1e-3


def test_refined_at_the_load_point_with_good_quality(case):
    profile, y0, mesh = case
    at_load = edge_lengths_at(mesh, [0.0, y0, float(profile.z(y0))]).mean()
    assert 0.5 * H_MIN <= at_load <= 1.5 * H_MIN
    far = mesh.p[0, mesh.t].mean(axis=0) > 15.0
    corners = mesh.p[:, mesh.t[:, far]]
    assert np.linalg.norm(corners[:, 0] - corners[:, 1], axis=0).mean() > 3 * H_MIN
    assert element_quality(mesh).min() > 0.25  # Netgen-optimised tetrahedra
    np.testing.assert_array_equal(np.unique(mesh.t), np.arange(mesh.nvertices))


def test_quadratic_and_deterministic():
    profile = get_profile("S1002")
    a, b = (local_mesh(profile, 0.0, 2.0, 8.0, length_mm=10.0, order=2) for _ in range(2))
    assert isinstance(a, skfem.MeshTet2)
    np.testing.assert_array_equal(a.doflocs, b.doflocs)
    np.testing.assert_array_equal(a.t, b.t)
    for name in a.boundaries:
        np.testing.assert_array_equal(a.boundaries[name], b.boundaries[name])
    area = outline_area(profile.section_outline(default_depth_mm(profile)))
    assert mesh_measure(a) == pytest.approx(area * 10.0, rel=1e-4)
    ends = a.p[:, a.edges]
    mid = a.doflocs[:, a.nvertices + np.arange(a.edges.shape[1])]
    length = np.linalg.norm(ends[:, 1] - ends[:, 0], axis=0)
    assert np.all(np.linalg.norm(mid - ends.mean(axis=1), axis=0) < 0.1 * length)
    assert surface_deviation_mm(a, profile) < 1e-3


def test_stretched_mesh_is_the_same_body_with_elements_longer_along_x():
    """x_stretch s: meshed in x / s and stretched back: the same prism (volume, end at x = length, exact
    surface), the refinement box elongated along x with s times fewer elements along it."""
    profile = get_profile("60E1")
    box = (6.0, 1.5, 1.0)
    plain, stretched = (local_mesh(profile, 0.0, 0.5, 8.0, length_mm=LENGTH, refine_box=box, x_stretch=s,
                                   optimize_netgen=False) for s in (1.0, 4.0))
    area = outline_area(profile.section_outline(default_depth_mm(profile)))
    assert mesh_measure(stretched) == pytest.approx(area * LENGTH, rel=5e-3)
    assert stretched.p[0].min() == pytest.approx(0.0, abs=1e-12)
    assert stretched.p[0].max() == pytest.approx(LENGTH, rel=1e-12)
    np.testing.assert_allclose(stretched.p[0, np.unique(stretched.facets[:, stretched.boundaries["end"]])], LENGTH)
    assert surface_deviation_mm(stretched, profile) < 1e-3
    assert stretched.t.shape[1] < 0.5 * plain.t.shape[1]

    def extent_at_load(mesh, axis):  # mean extent along an axis of the elements within 1 mm of (1, 0, z(0))
        near = np.array([[1.0], [0.0], [float(profile.z(0.0))]])
        at = np.linalg.norm(mesh.p[:, mesh.t].mean(axis=1) - near, axis=0) < 1.0
        c = mesh.p[axis, mesh.t[:, at]]
        return float(np.mean(c.max(axis=0) - c.min(axis=0)))

    assert extent_at_load(stretched, 0) > 2.5 * extent_at_load(plain, 0)
    assert extent_at_load(stretched, 1) == pytest.approx(extent_at_load(plain, 1), rel=0.3)


@pytest.mark.parametrize("kwargs, what", [
    ({"length_mm": 0.5}, "length_mm"), ({"refine_box": (1.0, -1.0, 1.0)}, "refine_box"),
    ({"refine_box": (1.0, 1.0)}, "refine_box"), ({"h_min": 5.0, "h_max": 1.0}, "h_min"), ({"order": 0}, "order"),
    ({"x_stretch": 0.5}, "x_stretch"), ({"x_stretch": float("nan")}, "x_stretch"),
])
def test_bad_inputs_raise_input_error(kwargs, what):
    args = {"profile": get_profile("60E1"), "y0": 0.0, "h_min": 1.0, "h_max": 8.0} | kwargs
    with pytest.raises(InputError) as err:
        local_mesh(**args)
    assert err.value.what == what


@pytest.mark.parametrize("suffix", [".vtu", ".msh"])
@pytest.mark.parametrize("order", [1, 2])
def test_mesh_files_round_trip(tmp_path, suffix, order):
    mesh = local_mesh(get_profile("60E1"), 0.0, 3.0, 10.0, length_mm=10.0, order=order, optimize_netgen=False)
    path = write_mesh(mesh, tmp_path / f"m{suffix}")
    assert sorted(p.name for p in tmp_path.iterdir()) == [path.name]  # no temporary left behind
    back = skfem.Mesh.load(path)
    assert type(back) is type(mesh)
    np.testing.assert_allclose(back.doflocs, mesh.doflocs)
    np.testing.assert_array_equal(back.t, mesh.t)
    for name, facets in mesh.boundaries.items():
        np.testing.assert_array_equal(np.sort(back.boundaries[name]), np.sort(facets))
    if suffix == ".msh":
        assert set(meshio.read(path).field_data) == {*mesh.boundaries, "domain"}


def test_write_mesh_rejects_unknown_suffix(tmp_path):
    mesh = local_mesh(get_profile("60E1"), 0.0, 4.0, 10.0, length_mm=10.0, optimize_netgen=False)
    with pytest.raises(InputError):
        write_mesh(mesh, tmp_path / "m.stl")
    assert list(tmp_path.iterdir()) == []
