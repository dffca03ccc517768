"""mesh.style = "structured" (a core structured along the surface, the normal and x; docs/calibration.md "Mesh
convergence"): build_mesh with it, the resolution guard, and a coarse 3D calibration of one position with it."""

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from calibration.config import load_config
from calibration.hertz.geometry import given_geometry
from calibration.indentation import MeshSettings, build_mesh, check_resolution, mesh_style
from calibration.pipeline import run_calibration
from contact.layer.layer_table import LayerTable
from meshes.profiles import get_profile
from wrlayer.errors import InputError

ROOT = Path(__file__).resolve().parents[2]
COARSE = ROOT / "calibration" / "configs" / "test_coarse.toml"


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


def test_coarse_calibration_with_the_structured_style(tmp_path):
    cfg = load_config(COARSE)
    cfg = dataclasses.replace(cfg, mesh=dataclasses.replace(cfg.mesh, style="structured"))
    summary = run_calibration(cfg, tmp_path, show_progress=False, log=lambda *a, **k: None)
    assert summary["failed"] == [] and summary["positions_computed"] == 1
    pos = LayerTable.read(tmp_path / "rail_layer_table.json").positions[0]
    # half-space first yield at p0 = 1.62 Y for a/b ~ 1.33 (as tests/calibration/test_pipeline.py), within 5 %
    assert pos["first_yield_fem_MPa"] == pytest.approx(1.62 * cfg.bodies[0].material.yield_MPa, rel=0.05)
    assert all(r > 0 for r in pos["residual_fem_mm"][1:])
    assert pos["max_error_mm"] <= cfg.fit.max_relative_error * max(pos["fem_points"]["u_mm"])
