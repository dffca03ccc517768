"""3D local meshes with a structured core (mesh.style = "extruded"): layers, quality, boundaries, volume, inputs."""

import numpy as np
import pytest
import skfem

from wrlayer.errors import InputError
from meshes.meshing.extruded_mesh import BOUNDARY_NAMES, core_layers, extruded_local_mesh
from meshes.meshing.local_mesh import local_mesh
from meshes.meshing.mesh_quality import edge_lengths_at, element_quality, mesh_measure, surface_deviation_mm
from meshes.meshing.section_mesh import MIN_ACCEPTED_QUALITY, default_depth_mm
from meshes.profiles import get_profile, outline_area

# an elongated patch (a/b = 4, section size 0.5 mm, layers 2 mm) and a round one, coarse enough to be quick
CASES = [("60E1", 0.0, 0.5, 2.0), ("S1002", -30.0, 1.0, 1.0)]
LENGTH, CORE = 20.0, 8.0


@pytest.fixture(scope="module", params=CASES, ids=[f"{c[0]}@{c[1]}" for c in CASES])
def case(request):
    name, y0, h_yz, h_x = request.param
    profile = get_profile(name)
    mesh = extruded_local_mesh(profile, y0, h_yz, h_x, 8.0, LENGTH, CORE, order=2, refine_box_yz=(2.0, 1.0))
    return profile, y0, h_yz, h_x, mesh


def test_structured_layers_in_the_core(case):
    _, _, _, h_x, mesh = case
    assert isinstance(mesh, skfem.MeshTet2)
    n = core_layers(h_x, CORE)
    x = mesh.p[0, :mesh.nvertices]
    planes = np.linspace(0.0, CORE, n + 1)
    in_core = x <= CORE + 1e-9
    # every core vertex lies on a layer plane, and every plane holds the same (section) vertices
    assert np.min(np.abs(x[in_core][:, None] - planes[None, :]), axis=1).max() < 1e-9
    counts = [np.count_nonzero(np.abs(x - p) < 1e-9) for p in planes]
    assert len(set(counts)) == 1 and counts[0] > 50
    yz = [np.sort(mesh.p[1:, :mesh.nvertices][:, np.abs(x - p) < 1e-9].T.view("f8,f8"), axis=0) for p in planes]
    assert all(np.array_equal(yz[0], s) for s in yz[1:])
    # beyond the core: unstructured (vertices off the planes)
    assert np.count_nonzero(x > CORE + 1e-6) > 0


def test_quality_and_refinement(case):
    profile, y0, h_yz, h_x, mesh = case
    q = element_quality(mesh)
    assert q.min() > MIN_ACCEPTED_QUALITY
    # prism tetrahedra of aspect h_x / h_yz: about 0.17 at 4 (measured: 0.17-0.20), better for round cells
    assert q.min() > (0.1 if h_x / h_yz > 2 else 0.2)
    edges = edge_lengths_at(mesh, [CORE / 2 + 0.5 * h_x / core_layers(h_x, CORE), y0, float(profile.z(y0))])
    assert edges.max() <= 1.6 * np.hypot(h_x, h_yz)
    assert edges.min() <= 1.2 * h_yz


def test_same_boundary_groups_as_the_isotropic_mesh(case):
    profile, _, _, _, mesh = case
    iso = local_mesh(profile, 0.0 if profile.body == "rail" else -30.0, 3.0, 8.0, length_mm=LENGTH,
                     optimize_netgen=False)
    assert set(mesh.boundaries) == set(iso.boundaries) == set(BOUNDARY_NAMES)
    groups = [mesh.boundaries[n] for n in BOUNDARY_NAMES]
    assert all(len(g) > 0 for g in groups)
    together = np.concatenate(groups)
    assert len(np.unique(together)) == len(together)
    np.testing.assert_array_equal(np.sort(together), np.sort(mesh.boundary_facets()))
    x_of = {n: mesh.p[0, np.unique(mesh.facets[:, mesh.boundaries[n]])] for n in BOUNDARY_NAMES}
    np.testing.assert_allclose(x_of["symmetry"], 0.0, atol=1e-9)
    np.testing.assert_allclose(x_of["end"], LENGTH, atol=1e-9)
    assert surface_deviation_mm(mesh, profile) < 1e-3
    # the same body: the lateral groups cover the same (y, z) extents
    for name in ("surface", "side", "fixed"):
        yz = lambda m: m.p[1:, np.unique(m.facets[:, m.boundaries[name]])]  # noqa: E731
        np.testing.assert_allclose(yz(mesh).min(axis=1), yz(iso).min(axis=1), atol=1e-3)
        np.testing.assert_allclose(yz(mesh).max(axis=1), yz(iso).max(axis=1), atol=1e-3)
    area = outline_area(profile.section_outline(default_depth_mm(profile)))
    assert mesh_measure(mesh) == pytest.approx(area * LENGTH, rel=1e-4)


def test_deterministic():
    args = (get_profile("60E1"), 0.0, 1.0, 2.0, 8.0, 12.0, 4.0)
    a, b = extruded_local_mesh(*args), extruded_local_mesh(*args)
    np.testing.assert_array_equal(a.p, b.p)
    np.testing.assert_array_equal(a.t, b.t)


@pytest.mark.parametrize("kwargs, what", [
    ({"h_x": 0.0}, "h_x"), ({"h_x": 9.0}, "h_x"), ({"core_length_mm": 0.0}, "core_length_mm"),
    ({"core_length_mm": 12.0}, "length_mm"), ({"refine_box_yz": (1.0, -1.0)}, "refine_box_yz"),
    ({"h_yz": 5.0, "h_max": 1.0, "h_x": 1.0}, "h_min"), ({"h_x": 0.01}, "h_x"),
])
def test_bad_inputs_raise_input_error(kwargs, what):
    args = {"profile": get_profile("60E1"), "y0": 0.0, "h_yz": 1.0, "h_x": 2.0, "h_max": 8.0, "length_mm": 12.0,
            "core_length_mm": 4.0} | kwargs
    with pytest.raises(InputError) as err:
        extruded_local_mesh(**args)
    assert err.value.what == what
