"""mesh.style = "structured" (a core structured along the surface, the normal and x; docs/calibration.md "Mesh
convergence"): build_mesh with it, the resolution guard, and a coarse real 3D indentation with it; and
mesh.yield_zone_refinement (a finer zone of the isotropic mesh at the first-yield point)."""

import numpy as np
import pytest

from calibration.config import parse_config
from calibration.fem.material import J2Material
from calibration.hertz.geometry import given_geometry
from calibration.indentation import IndentationJob, indent
from calibration.position_mesh import build_mesh, check_resolution, mesh_style
from calibration.settings import LoadSettings, MeshSettings
from meshes.meshing.mesh_quality import edge_lengths_at
from meshes.profiles import get_profile
from wrlayer.errors import InputError


def test_build_mesh_structured_core_cells():
    rail = get_profile("60E1")
    geo = given_geometry(rail, 0.0, 7.16, 5.39)
    settings = MeshSettings(elements_per_semi_axis=2, h_max_mm=12.0, style="structured")
    assert mesh_style(geo, settings) == "structured"
    mesh = build_mesh(rail, geo, "3d", settings)
    x = mesh.p[0, :mesh.nvertices]
    # core 1.2 a long in ceil(1.2 n) = 3 layers: every vertex at the load point's normal lies on a layer plane
    on_axis = ((np.abs(mesh.p[1, :mesh.nvertices]) < 1e-9) & (x <= 1.2 * 7.16 + 1e-9)
               & (mesh.p[2, :mesh.nvertices] >= -5.39 - 1e-9))  # the core is b = 5.39 mm deep
    planes = np.linspace(0.0, 1.2 * 7.16, 4)
    assert np.min(np.abs(x[on_axis][:, None] - planes[None, :]), axis=1).max() < 1e-9
    # 2 ceil(1.2 n) = 6 cells along s, ceil(n) = 2 in depth: 3 nodes on the normal at s = 0 in each plane
    assert np.count_nonzero(on_axis) == 4 * 3


def test_too_coarse_is_refused_for_the_structured_style_too():
    rail = get_profile("60E1")
    geo = given_geometry(rail, 0.0, 7.16, 5.39)
    with pytest.raises(InputError, match="mesh.elements_per_semi_axis"):
        check_resolution(geo, "3d", MeshSettings(elements_per_semi_axis=1.5, style="structured"))


def test_coarse_indentation_with_the_structured_style():
    """A real 3D elastoplastic indentation of the crown on the coarse structured mesh (n = 2, P2): first yield near
    the half-space value, a positive dent after unloading."""
    rail = get_profile("60E1")
    geo = given_geometry(rail, 0.0, 7.16, 5.39)
    mat = J2Material(210000.0, 0.3, 500.0, 10000.0, 10000.0)
    mesh = MeshSettings(elements_per_semi_axis=2, h_max_mm=12.0, style="structured")
    load = LoadSettings(max_factor=1.6, n_levels=2, unload_factors=(1.6,), max_increment_factor=0.3)
    res = indent(IndentationJob(profile=rail, geometry=geo, material=mat, model="3d", mesh=mesh, load=load,
                                linear_solver="scipy"))
    # half-space first yield at p0 = 1.62 Y for a/b ~ 1.33 (as tests/calibration/test_pipeline.py), within 5 %
    assert res.first_yield_MPa == pytest.approx(1.62 * 500.0, rel=0.05)
    assert res.residual_fem_mm[0] > 0 and res.u_pl_mm[-1] > 0


def test_yield_zone_refinement_config():
    body = {"body": "rail", "profile": "60E1", "mate": "S1002", "positions_mm": [0.0]}
    assert parse_config({"mesh": {"yield_zone_refinement": 2}, "bodies": [body]}).mesh.yield_zone_refinement == 2
    assert parse_config({"bodies": [body]}).mesh.yield_zone_refinement == 1.0  # off by default
    for bad in (0.5, 5.0, "2", True):
        with pytest.raises(InputError, match="mesh.yield_zone_refinement"):
            parse_config({"mesh": {"yield_zone_refinement": bad}, "bodies": [body]}, "my.toml")


def test_yield_zone_refinement_refines_around_the_first_yield_point():
    """Isotropic mesh: h_min / f at the von Mises maximum (0.55 b below the load centre), unchanged elsewhere."""
    rail = get_profile("60E1")
    geo = given_geometry(rail, 0.0, 7.16, 5.39)
    plain = build_mesh(rail, geo, "3d", MeshSettings(elements_per_semi_axis=2, h_max_mm=12.0))
    zone = build_mesh(rail, geo, "3d", MeshSettings(elements_per_semi_axis=2, h_max_mm=12.0,
                                                    yield_zone_refinement=2.0))
    point = [0.5, 0.0, -0.55 * 5.39]
    assert edge_lengths_at(zone, point).max() < 0.75 * edge_lengths_at(plain, point).max()
    assert zone.t.shape[1] > plain.t.shape[1]
    same = build_mesh(rail, geo, "3d", MeshSettings(elements_per_semi_axis=2, h_max_mm=12.0,
                                                    yield_zone_refinement=1.0))
    assert np.array_equal(same.p, plain.p)  # 1 = off: the same mesh
